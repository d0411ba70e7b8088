// Specular motion by temporal manifold exploration (Zimmer et al. 2015, Section 4.1).
// Planar mirrors and a glass slab against their analytic solutions; curved mirrors and
// glass against a brute-force search over camera rays with a tracer of the test's own;
// hard inputs, which must give flags rather than NaN or hangs.
#include <gtest/gtest.h>

#include <fstream>
#include <functional>

#include "renderer/accel/shot_geometry.h"
#include "renderer/decomposition/specular_motion.h"
#include "renderer/integrators/frame_renderer.h"
#include "test_support.h"

namespace pathfarm {
namespace {

constexpr int kReflection = 2, kTransmission = 3;  // in Decomposition::standard()
constexpr double kDegrees = 3.14159265358979323846 / 180;

// A scene's frame-1 geometry and the specular motion of its components. Every test scene
// runs at 1 frame per second with an instantaneous shutter, so frame f is time f.
class TrackedScene {
 public:
  TrackedScene(const std::string& json, int width, int height, Decomposition decomposition = Decomposition::standard())
      : scene_(test_support::sceneFromJson(json)),
        shot_(scene_, device_),
        geometry_(shot_, 1),
        shapes_(preciseShapesOf(scene_)),
        decomposition_(std::move(decomposition)),
        motion_(geometry_, shapes_, decomposition_, width, height),
        width_(width),
        height_(height) {}

  SpecularTrack track(int x, int y, int component) const { return motion_.track(x, y, component); }
  // Calls `f(x, y, track)` for every pixel where `component` has a representative path.
  void forEachChain(int component, const std::function<void(int, int, const SpecularTrack&)>& f) const {
    for (int y = 0; y < height_; ++y)
      for (int x = 0; x < width_; ++x)
        if (const SpecularTrack t = motion_.track(x, y, component); t.hasChain) f(x, y, t);
  }

 private:
  Scene scene_;
  EmbreeDevice device_;
  ShotGeometry shot_;
  FrameGeometry geometry_;
  std::vector<PreciseShape> shapes_;
  Decomposition decomposition_;
  SpecularMotion motion_;
  int width_, height_;
};

// The test's own pinhole: at `position`, looking down -z with +y up, as every test scene's
// camera does (look_at straight ahead).
struct TestCamera {
  Vec3d position;
  double fovDegrees;
  int width, height;

  double tanHalf() const { return std::tan(0.5 * fovDegrees * kDegrees); }
  double aspect() const { return static_cast<double>(width) / height; }
  Vec3d direction(Vec2d f) const {
    return normalize(Vec3d{(2 * f.x / width - 1) * tanHalf() * aspect(), (1 - 2 * f.y / height) * tanHalf(), -1});
  }
  Vec2d project(Vec3d p) const {
    const Vec3d v = p - position;
    return {(v.x / -v.z / (tanHalf() * aspect()) + 1) * 0.5 * width, (1 - v.y / -v.z / tanHalf()) * 0.5 * height};
  }
};

Vec2d pixelCentre(int x, int y) { return {x + 0.5, y + 0.5}; }

void expectMotion(const std::optional<Vec2d>& motion, Vec2d expected, double tolerance, int x, int y) {
  ASSERT_TRUE(motion.has_value()) << "pixel " << x << "," << y << " not tracked";
  EXPECT_NEAR(motion->x, expected.x, tolerance) << "pixel " << x << "," << y;
  EXPECT_NEAR(motion->y, expected.y, tolerance) << "pixel " << x << "," << y;
}

Vec2d minus(Vec2d a, Vec2d b) { return {a.x - b.x, a.y - b.y}; }

// ---------------------------------------------------------------------------------------
// Planar mirror: a 45-degree mirror through `mirrorAt` (normal (1, 0, 1) / sqrt 2) shows
// the camera a card in the plane x = 3. A point P's mirror image is P - 2 ((P - Q).n) n.

std::string mirrorScene(const std::string& cameraAnimation, const std::string& mirrorAnimation) {
  return R"({
    "fps": 1,
    "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov": 30)" +
         cameraAnimation + R"(},
    "materials": {"mirror": {"type": "conductor", "specular_color": 1},
                  "card": {"type": "diffuse", "reflectance": 0.5}},
    "shapes": [
      {"type": "rectangle", "size": [10, 6], "material": "mirror",
       "transform": {"rotate": {"axis": [0, 1, 0], "angle": 45}})" +
         mirrorAnimation + R"(},
      {"type": "rectangle", "size": [8, 8], "material": "card",
       "transform": {"translate": [3, 0, 0], "rotate": {"axis": [0, 1, 0], "angle": -90}}}]
  })";
}

const Vec3d kMirrorNormal{std::sqrt(0.5), 0, std::sqrt(0.5)};

Vec3d mirrorImage(Vec3d p, Vec3d mirrorAt) { return p - kMirrorNormal * (2 * dot(p - mirrorAt, kMirrorNormal)); }

// The card point the pixel-centre ray sees through the mirror.
Vec3d cardPointSeen(const TestCamera& camera, Vec2d film, Vec3d mirrorAt) {
  const Vec3d d = camera.direction(film);
  const Vec3d x1 = camera.position + d * (dot(mirrorAt - camera.position, kMirrorNormal) / dot(d, kMirrorNormal));
  const Vec3d r = d - kMirrorNormal * (2 * dot(d, kMirrorNormal));
  return x1 + r * ((3 - x1.x) / r.x);
}

TEST(SpecularMotion, MovingPlanarMirrorMatchesTheMirrorImage) {
  const int width = 40, height = 30;
  const TrackedScene scene(mirrorScene("", R"(, "animation": {"translate": [
      {"frame": 0, "value": [-0.1, 0.05, 0.2]}, {"frame": 2, "value": [0.1, -0.05, -0.1]}]})"),
                           width, height);
  const TestCamera camera{{0, 0, 5}, 30, width, height};
  const Vec3d mirrorAt[3] = {{-0.1, 0.05, 0.2}, {0, 0, 0.05}, {0.1, -0.05, -0.1}};  // frames 0, 1, 2
  int tracked = 0;
  scene.forEachChain(kReflection, [&](int x, int y, const SpecularTrack& track) {
    const Vec3d p = cardPointSeen(camera, pixelCentre(x, y), mirrorAt[1]);
    const Vec2d now = camera.project(mirrorImage(p, mirrorAt[1]));
    expectMotion(track.forward, minus(camera.project(mirrorImage(p, mirrorAt[2])), now), 1e-3, x, y);
    expectMotion(track.backward, minus(camera.project(mirrorImage(p, mirrorAt[0])), now), 1e-3, x, y);
    ++tracked;
  });
  EXPECT_EQ(tracked, width * height);  // the mirror fills the view
}

TEST(SpecularMotion, StaticMirrorWithMovingCameraMatchesTheMirrorImage) {
  const int width = 40, height = 30;
  const TrackedScene scene(mirrorScene(R"(, "animation": {"translate": [
      {"frame": 0, "value": [-0.3, 0.2, 5.2]}, {"frame": 2, "value": [0.3, -0.2, 4.8]}]})",
                                       ""),
                           width, height);
  const TestCamera now{{0, 0, 5}, 30, width, height};
  const TestCamera next{{0.3, -0.2, 4.8}, 30, width, height}, previous{{-0.3, 0.2, 5.2}, 30, width, height};
  int tracked = 0;
  scene.forEachChain(kReflection, [&](int x, int y, const SpecularTrack& track) {
    const Vec3d image = mirrorImage(cardPointSeen(now, pixelCentre(x, y), {}), {});
    expectMotion(track.forward, minus(next.project(image), pixelCentre(x, y)), 1e-3, x, y);
    expectMotion(track.backward, minus(previous.project(image), pixelCentre(x, y)), 1e-3, x, y);
    ++tracked;
  });
  EXPECT_EQ(tracked, width * height);
}

// ---------------------------------------------------------------------------------------
// A parallel-sided glass slab (faces z = +-0.25, index 1.5) in front of a card at z = -2
// that slides: a ray crossing it keeps its direction and is shifted sideways, so the card
// point at lateral distance rho from the camera axis is seen at the angle theta with
// rho = 6.5 tan(theta) + 0.5 tan(theta'), sin(theta') = sin(theta) / 1.5.

double slabReach(double theta) {
  const double inside = std::asin(std::sin(theta) / 1.5);
  return 6.5 * std::tan(theta) + 0.5 * std::tan(inside);
}

// The direction the camera sees `p` (on the card) in, by bisection on the monotonic reach.
Vec3d throughSlabTowards(Vec3d camera, Vec3d p) {
  const double rho = std::hypot(p.x - camera.x, p.y - camera.y);
  double lo = 0, hi = 1.5;
  for (int i = 0; i < 200; ++i) (slabReach(0.5 * (lo + hi)) < rho ? lo : hi) = 0.5 * (lo + hi);
  const double theta = 0.5 * (lo + hi), phi = std::atan2(p.y - camera.y, p.x - camera.x);
  return {std::cos(phi) * std::sin(theta), std::sin(phi) * std::sin(theta), -std::cos(theta)};
}

TEST(SpecularMotion, GlassSlabShiftMatchesSnellsLaw) {
  const int width = 40, height = 30;
  const TrackedScene scene(R"({
    "fps": 1,
    "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov": 20},
    "materials": {"glass": {"type": "dielectric", "ior": 1.5}, "card": {"type": "diffuse", "reflectance": 0.5}},
    "shapes": [
      {"type": "box", "size": [6, 6, 0.5], "material": "glass"},
      {"type": "rectangle", "size": [12, 12], "material": "card",
       "animation": {"translate": [{"frame": 0, "value": [-0.2, 0.1, -2]}, {"frame": 2, "value": [0.2, -0.1, -2]}]}}]
  })",
                           width, height);
  const TestCamera view{{0, 0, 5}, 20, width, height};
  int tracked = 0;
  scene.forEachChain(kTransmission, [&](int x, int y, const SpecularTrack& track) {
    const Vec3d d = view.direction(pixelCentre(x, y));
    const double theta = std::acos(-d.z), rho = slabReach(theta), lateral = std::hypot(d.x, d.y);
    const Vec3d p{d.x / lateral * rho, d.y / lateral * rho, -2};
    const auto seen = [&](Vec3d shift) {
      return view.project(view.position + throughSlabTowards(view.position, p + shift));
    };
    const Vec2d now = seen({});
    expectMotion(track.forward, minus(seen({0.2, -0.1, 0}), now), 1e-3, x, y);
    expectMotion(track.backward, minus(seen({-0.2, 0.1, 0}), now), 1e-3, x, y);
    ++tracked;
  });
  EXPECT_EQ(tracked, width * height);
}

// ---------------------------------------------------------------------------------------
// Curved cases: spheres inside a large diffuse sphere (radius 20, about the origin) that
// turns about y by 6 degrees per frame, so the endpoints move too. The test traces spheres
// itself and searches film positions for the one whose path lands on the moved point.

// Every test sphere moves with kSphereAnimation (below): two keyed segments, so the walk
// crosses a key between frames. The keys are exact in float, as the scene stores them.
const char* kSphereAnimation = R"("animation": {"translate": [{"frame": 0, "value": [-0.25, 0, 0]},
    {"frame": 1.5, "value": [0.25, 0.125, 0.125]}, {"frame": 2, "value": [0.25, -0.125, 0.375]}]})";

Vec3d sphereCenterAt(double seconds) {
  const Vec3d a{-0.25, 0, 0}, b{0.25, 0.125, 0.125}, c{0.25, -0.125, 0.375};
  return seconds < 1.5 ? a + (b - a) * (seconds / 1.5) : b + (c - b) * ((seconds - 1.5) / 0.5);
}

struct TestSphere {
  double radius;
  double ior;  // 0: a mirror
};

constexpr double kRoomRadius = 20;

// A point of the room carried along by its turning over `seconds`.
Vec3d turnedRoomPoint(Vec3d p, double seconds) {
  const double a = 6 * kDegrees * seconds;
  return {p.x * std::cos(a) + p.z * std::sin(a), p.y, -p.x * std::sin(a) + p.z * std::cos(a)};
}

double sphereHit(Vec3d o, Vec3d d, Vec3d center, double radius, double minDistance) {
  const Vec3d oc = o - center;
  const double b = dot(oc, d), c = dot(oc, oc) - radius * radius, disc = b * b - c;
  if (disc < 0) return -1;
  const double near = -b - std::sqrt(disc), far = -b + std::sqrt(disc);
  return near > minDistance ? near : (far > minDistance ? far : -1);
}

// The path from `o` along `d` at `seconds`: specular vertices, then the room point.
std::optional<std::vector<Vec3d>> traceSpheres(const std::vector<TestSphere>& spheres, double seconds, Vec3d o,
                                               Vec3d d) {
  const Vec3d center = sphereCenterAt(seconds);
  std::vector<Vec3d> vertices;
  for (int bounce = 0; bounce < 10; ++bounce) {
    double nearest = sphereHit(o, d, {}, kRoomRadius, 1e-9);
    const TestSphere* hit = nullptr;
    for (const TestSphere& s : spheres) {
      const double t = sphereHit(o, d, center, s.radius, 1e-9);
      if (t > 0 && t < nearest) nearest = t, hit = &s;
    }
    o = o + d * nearest;
    vertices.push_back(o);
    if (!hit) return vertices;
    Vec3d n = (o - center) / hit->radius;
    if (hit->ior == 0) {
      d = d - n * (2 * dot(d, n));
      continue;
    }
    double cosIn = -dot(d, n), eta = 1 / hit->ior;
    if (cosIn < 0) n = -n, cosIn = -cosIn, eta = hit->ior;
    const double sin2 = eta * eta * (1 - cosIn * cosIn);
    if (sin2 >= 1) return std::nullopt;
    d = normalize(d * eta + n * (eta * cosIn - std::sqrt(1 - sin2)));
  }
  return std::nullopt;
}

// The film position whose path (with as many vertices) lands on `target`, searched
// without derivatives and without anything of the manifold walk: the best of a grid over
// the whole image every half pixel, refined by a pattern search whose step doubles after
// a success and halves after a failure.
std::optional<Vec2d> bruteForceFilm(const std::function<std::optional<std::vector<Vec3d>>(Vec2d)>& trace,
                                    size_t vertices, Vec3d target, int width, int height) {
  const auto miss = [&](Vec2d f) {
    const auto path = trace(f);
    return path && path->size() == vertices ? length(path->back() - target) : 1e30;
  };
  Vec2d best;
  double bestMiss = 1e30;
  for (double y = 0.25; y < height; y += 0.5)
    for (double x = 0.25; x < width; x += 0.5)
      if (const double m = miss({x, y}); m < bestMiss) best = {x, y}, bestMiss = m;
  for (double h = 0.25; h > 1e-12 && bestMiss > 1e-9;) {
    Vec2d next = best;
    double nextMiss = bestMiss;
    for (const Vec2d step : {Vec2d{1, 0}, Vec2d{-1, 0}, Vec2d{0, 1}, Vec2d{0, -1}, Vec2d{1, 1}, Vec2d{-1, -1},
                             Vec2d{1, -1}, Vec2d{-1, 1}}) {
      const Vec2d f{best.x + step.x * h, best.y + step.y * h};
      if (const double m = miss(f); m < nextMiss) next = f, nextMiss = m;
    }
    h *= nextMiss < bestMiss ? 2 : 0.5;
    best = next;
    bestMiss = nextMiss;
  }
  if (bestMiss > 1e-6) return std::nullopt;
  return best;
}

// The spheres `shapes` inside the turning room, seen by a camera at (0, 0, 5).
std::string curvedScene(const std::string& shapes) {
  return R"({
    "fps": 1,
    "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov": 32},
    "materials": {"mirror": {"type": "conductor", "specular_color": 1},
                  "glass": {"type": "dielectric", "ior": 1.5},
                  "water": {"type": "dielectric", "ior": 1.33},
                  "thin": {"type": "dielectric", "ior": 1.0001},
                  "room": {"type": "diffuse", "reflectance": 0.5}},
    "shapes": [
      {"type": "sphere", "radius": 20, "material": "room",
       "animation": {"rotate": [{"frame": 0, "axis": [0, 1, 0], "angle": -6}, {"frame": 2, "axis": [0, 1, 0], "angle": 6}]}},
      )" +
         shapes + "]}";
}

std::string sphereShape(double radius, const char* material) {
  return R"({"type": "sphere", "radius": )" + std::to_string(radius) + R"(, "material": ")" + material + R"(", )" +
         kSphereAnimation + "}";
}

// Every solved path at t + 1 satisfies the specular constraints (generalized half vector
// along the analytic normal) and lands on its target; its motion agrees with the search.
void expectCurvedCaseMatchesBruteForce(const std::string& shapes, const std::vector<TestSphere>& spheres, int component,
                                       Decomposition decomposition = Decomposition::standard()) {
  const int width = 32, height = 24;
  const TrackedScene scene(curvedScene(shapes), width, height, std::move(decomposition));
  const TestCamera camera{{0, 0, 5}, 32, width, height};
  int tracked = 0, reachable = 0, chains = 0;
  scene.forEachChain(component, [&](int x, int y, const SpecularTrack& track) {
    ++chains;
    const auto now = traceSpheres(spheres, 1, camera.position, camera.direction(pixelCentre(x, y)));
    ASSERT_TRUE(now.has_value());
    ASSERT_TRUE(track.now.has_value());
    // The same path now; near a silhouette rounding alone moves its far end a little.
    const Vec3d start = track.now->endpoint().surface.position;
    ASSERT_LT(length(start - now->back()), 1e-4) << "pixel " << x << "," << y;
    int found = 0;
    for (const int frames : {+1, -1}) {
      const int frame = 1 + frames;
      const Vec3d target = turnedRoomPoint(start, frames);
      const auto reference =
          bruteForceFilm([&](Vec2d f) { return traceSpheres(spheres, frame, camera.position, camera.direction(f)); },
                         now->size(), target, width, height);
      found += reference.has_value();
      const std::optional<ChainPath>& solved = frames > 0 ? track.next : track.previous;
      if (!solved) continue;
      ASSERT_TRUE(reference.has_value()) << "the search found no path at pixel " << x << "," << y;
      expectMotion(frames > 0 ? track.forward : track.backward, minus(*reference, pixelCentre(x, y)), 0.01, x, y);
      EXPECT_LT(length(solved->endpoint().surface.position - target), 1e-5) << "pixel " << x << "," << y;
      ASSERT_EQ(solved->vertices.size(), now->size());
      // The specular constraints at every vertex, with the test's own normals.
      for (size_t i = 0; i + 1 < solved->vertices.size(); ++i) {
        const Vec3d xi = solved->vertices[i].surface.position;
        const Vec3d previous = i == 0 ? solved->eye : solved->vertices[i - 1].surface.position;
        const Vec3d wi = normalize(previous - xi), wo = normalize(solved->vertices[i + 1].surface.position - xi);
        const TestSphere* on = nullptr;
        for (const TestSphere& s : spheres)
          if (std::abs(length(xi - sphereCenterAt(frame)) - s.radius) < 1e-9) on = &s;
        ASSERT_NE(on, nullptr) << "vertex " << i << " is on no sphere";
        const Vec3d n = (xi - sphereCenterAt(frame)) / on->radius;
        const auto eta = [&](Vec3d w) { return on->ior == 0 || dot(w, n) > 0 ? 1 : on->ior; };
        const Vec3d h = wi * eta(wi) + wo * eta(wo);
        EXPECT_LT(length(h - n * dot(h, n)), 1e-6) << "pixel " << x << "," << y << " vertex " << i;
      }
    }
    reachable += found == 2;
    tracked += track.tracked();
  });
  // The walk tracks nearly every pixel whose path the search finds in both frames.
  EXPECT_GT(chains, 40);
  EXPECT_GE(tracked, reachable * 9 / 10);
  EXPECT_GT(tracked, 40);
}

TEST(SpecularMotion, MirrorSphereMatchesBruteForceSearch) {
  expectCurvedCaseMatchesBruteForce(sphereShape(1, "mirror"), {{1, 0}}, kReflection);
}

TEST(SpecularMotion, GlassSphereMatchesBruteForceSearch) {
  expectCurvedCaseMatchesBruteForce(sphereShape(1, "glass"), {{1, 1.5}}, kTransmission);
}

TEST(SpecularMotion, NestedDielectricWithFourTransmissionsMatchesBruteForceSearch) {
  expectCurvedCaseMatchesBruteForce(sphereShape(1, "glass") + "," + sphereShape(0.5, "water"), {{1, 1.5}, {0.5, 1.33}},
                                    0, Decomposition::parse("deep=ETTTTD.*"));
}

TEST(SpecularMotion, IndexOfRefractionNearOneIsTrackedLikeAnyGlass) {
  expectCurvedCaseMatchesBruteForce(sphereShape(1, "thin"), {{1, 1.0001}}, kTransmission);
}

// The manifold's tangent (the implicit function theorem on the constraint Jacobian)
// against central differences of paths the search solves: how the first vertex moves as
// time advances with the endpoint on its object point, and as the endpoint slides along u.
TEST(SpecularMotion, ManifoldTangentMatchesFiniteDifferencesOfSolvedPaths) {
  const int width = 32, height = 24;
  const TrackedScene scene(curvedScene(sphereShape(1, "glass")), width, height);
  const std::vector<TestSphere> spheres{{1, 1.5}};
  const TestCamera camera{{0, 0, 5}, 32, width, height};
  const SpecularChain chain{{{1, true, 1.5}, {1, true, 1.5}}, 0};  // through the glass to the room
  // The first vertex of the path the search finds through `target` at `seconds`.
  const auto firstVertex = [&](Vec3d target, double seconds) {
    const auto trace = [&](Vec2d f) { return traceSpheres(spheres, seconds, camera.position, camera.direction(f)); };
    const auto film = bruteForceFilm(trace, 3, target, width, height);
    EXPECT_TRUE(film.has_value());
    return film ? trace(*film)->front() : Vec3d{};
  };
  const auto expectClose = [](Vec3d difference, Vec3d predicted, const char* what) {
    EXPECT_LT(length(difference - predicted), 1e-3 * length(predicted) + 1e-7)
        << what << ": " << difference.x << " " << difference.y << " " << difference.z << " against " << predicted.x
        << " " << predicted.y << " " << predicted.z;
  };
  for (const auto& [x, y] : {std::pair{14, 12}, std::pair{19, 8}, std::pair{10, 15}}) {
    const SpecularTrack track = scene.track(x, y, kTransmission);
    ASSERT_TRUE(track.now.has_value());
    const auto tangent = manifoldTangent(*track.now, chain);
    ASSERT_TRUE(tangent.has_value());
    const SurfaceDifferentials &first = track.now->vertices.front().surface, &end = track.now->endpoint().surface;
    const auto predicted = [&](int column) {
      return first.dpdu * tangent->du[column] + first.dpdv * tangent->dv[column] +
             (column == 2 ? first.velocity : Vec3d{});
    };
    const double h = 1e-3;
    expectClose(
        (firstVertex(turnedRoomPoint(end.position, h), 1 + h) - firstVertex(turnedRoomPoint(end.position, -h), 1 - h)) /
            (2 * h),
        predicted(2), "in time");
    const auto onRoom = [](Vec3d p) { return p * (kRoomRadius / length(p)); };
    expectClose(
        (firstVertex(onRoom(end.position + end.dpdu * h), 1) - firstVertex(onRoom(end.position - end.dpdu * h), 1)) /
            (2 * h),
        predicted(0), "along u");
  }
}

// ---------------------------------------------------------------------------------------
// Hard inputs: flags, never NaN, and every walk ends (the iteration bounds).

struct TrackCounts {
  int chains = 0, tracked = 0;
  int untrackedIterations = 0;  // manifold steps spent on the paths that were not tracked
};

TrackCounts expectFlagsOrFiniteMotion(const TrackedScene& scene, int component) {
  TrackCounts counts;
  scene.forEachChain(component, [&](int x, int y, const SpecularTrack& track) {
    ++counts.chains;
    for (const auto& motion : {track.forward, track.backward}) {
      if (!motion) continue;
      EXPECT_TRUE(std::isfinite(motion->x) && std::isfinite(motion->y)) << "pixel " << x << "," << y;
    }
    counts.tracked += track.tracked();
    if (!track.tracked()) counts.untrackedIterations += track.counts.inner;
  });
  return counts;
}

TEST(SpecularMotion, GrazingIncidenceGivesFlagsOrFiniteMotion) {
  // A mirror seen almost edge-on (87 degrees from facing the camera), sliding sideways.
  const TrackedScene scene(R"({
    "fps": 1,
    "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov": 30},
    "materials": {"mirror": {"type": "conductor", "specular_color": 1}, "card": {"type": "diffuse", "reflectance": 0.5}},
    "shapes": [
      {"type": "rectangle", "size": [20, 6], "material": "mirror", "transform": {"rotate": {"axis": [0, 1, 0], "angle": 87}},
       "animation": {"translate": [{"frame": 0, "value": [-0.6, 0, 0]}, {"frame": 2, "value": [-0.4, 0, 0.3]}]}},
      {"type": "rectangle", "size": [40, 40], "material": "card",
       "transform": {"translate": [3, 0, 0], "rotate": {"axis": [0, 1, 0], "angle": -90}}}]
  })",
                           32, 24);
  const TrackCounts counts = expectFlagsOrFiniteMotion(scene, kReflection);
  EXPECT_GT(counts.chains, 50);
}

TEST(SpecularMotion, TotalInternalReflectionAppearingBetweenFramesGivesFlags) {
  // A turning glass cube: rays entering a front face leave through a back face, or meet
  // it beyond the critical angle once the cube has turned.
  const TrackedScene scene(R"({
    "fps": 1,
    "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov": 30},
    "materials": {"glass": {"type": "dielectric", "ior": 1.5}, "card": {"type": "diffuse", "reflectance": 0.5}},
    "shapes": [
      {"type": "box", "size": [1.5, 1.5, 1.5], "material": "glass",
       "animation": {"rotate": [{"frame": 0, "axis": [0, 1, 0], "angle": 25}, {"frame": 2, "axis": [0, 1, 0], "angle": 65}]}},
      {"type": "rectangle", "size": [30, 30], "material": "card", "transform": {"translate": [0, 0, -3]}}]
  })",
                           32, 24);
  const TrackCounts counts = expectFlagsOrFiniteMotion(scene, kTransmission);
  EXPECT_GT(counts.chains, 50);
  EXPECT_GT(counts.tracked, 0);
  EXPECT_LT(counts.tracked, counts.chains);
}

TEST(SpecularMotion, PathLeavingTheMirrorIsFlagged) {
  // A small mirror slides 3 units along its own plane per frame: the card point's mirror
  // image stays where it is, but no part of the mirror is there to show it.
  const TrackedScene scene(R"({
    "fps": 1,
    "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov": 30},
    "materials": {"mirror": {"type": "conductor", "specular_color": 1}, "card": {"type": "diffuse", "reflectance": 0.5}},
    "shapes": [
      {"type": "rectangle", "size": [0.6, 0.6], "material": "mirror", "transform": {"rotate": {"axis": [0, 1, 0], "angle": 45}},
       "animation": {"translate": [{"frame": 0, "value": [0, -3, 0]}, {"frame": 2, "value": [0, 3, 0]}]}},
      {"type": "rectangle", "size": [8, 8], "material": "card",
       "transform": {"translate": [3, 0, 0], "rotate": {"axis": [0, 1, 0], "angle": -90}}}]
  })",
                           32, 24);
  const TrackCounts counts = expectFlagsOrFiniteMotion(scene, kReflection);
  EXPECT_GT(counts.chains, 10);
  EXPECT_EQ(counts.tracked, 0);
  // A path that ceases to exist fails only at the walk's bounds, so they set its cost. A
  // walk that succeeds takes about 3 manifold steps; the bounds of 24, 1/1024 and 1/256
  // spent 38 a path here (both walks), the present ones 19 (docs/performance.md, "Failed
  // walks cut short").
  EXPECT_LE(counts.untrackedIterations, 25 * counts.chains);
}

TEST(SpecularMotion, DegenerateTrianglesGiveFlagsOrFiniteMotion) {
  // A bent mirror with interpolated normals and zero-area triangles (a repeated vertex,
  // three collinear vertices) among its faces; the camera moves.
  const auto folder = test_support::processTemporaryFolder("pathfarm_specular_degenerate");
  std::filesystem::create_directories(folder);
  std::ofstream(folder / "bent.obj") << "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nv 0 -1 0\n"
                                        "vn -0.2 0 1\nvn 0.2 0 1\nvn 0.2 0 1\nvn -0.2 0 1\nvn 0 0 1\n"
                                        "f 1//1 2//2 3//3\nf 1//1 3//3 4//4\nf 1//1 1//1 3//3\nf 1//1 5//5 2//2\n";
  const TrackedScene scene(R"({
    "fps": 1,
    "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov": 30,
               "animation": {"translate": [{"frame": 0, "value": [-0.2, 0, 5]}, {"frame": 2, "value": [0.2, 0.1, 5]}]}},
    "materials": {"mirror": {"type": "conductor", "specular_color": 1}, "card": {"type": "diffuse", "reflectance": 0.5}},
    "shapes": [
      {"type": "mesh", "file": ")" + (folder / "bent.obj").string() + R"(", "material": "mirror",
       "transform": {"rotate": {"axis": [0, 1, 0], "angle": 45}}},
      {"type": "rectangle", "size": [8, 8], "material": "card",
       "transform": {"translate": [3, 0, 0], "rotate": {"axis": [0, 1, 0], "angle": -90}}}]
  })",
                           32, 24);
  const TrackCounts counts = expectFlagsOrFiniteMotion(scene, kReflection);
  EXPECT_GT(counts.chains, 50);
  EXPECT_GT(counts.tracked, counts.chains / 2);
  std::filesystem::remove_all(folder);
}

TEST(SpecularMotion, ZeroMotionIsExactlyZero) {
  // Keys that do not move the mirror: the walk runs and finds the same film position.
  const TrackedScene still(mirrorScene("", R"(, "animation": {"translate": [
      {"frame": 0, "value": [0, 0, 0]}, {"frame": 2, "value": [0, 0, 0]}]})"),
                           16, 12);
  int walked = 0;
  still.forEachChain(kReflection, [&](int x, int y, const SpecularTrack& track) {
    walked += track.walked;
    expectMotion(track.forward, {0, 0}, 0, x, y);
    expectMotion(track.backward, {0, 0}, 0, x, y);
  });
  EXPECT_EQ(walked, 16 * 12);
}

TEST(SpecularMotion, StaticChainIsZeroWithoutWalkingWhileOtherObjectsMove) {
  const std::string json = mirrorScene("", "");
  const TrackedScene scene(json.substr(0, json.rfind(']')) + R"(,
      {"type": "sphere", "radius": 0.2, "material": "card",
       "animation": {"translate": [{"frame": 0, "value": [0, 5, 0]}, {"frame": 2, "value": [1, 5, 0]}]}}]})",
                           16, 12);
  int chains = 0;
  scene.forEachChain(kReflection, [&](int x, int y, const SpecularTrack& track) {
    ++chains;
    EXPECT_FALSE(track.walked);
    expectMotion(track.forward, {0, 0}, 0, x, y);
    expectMotion(track.backward, {0, 0}, 0, x, y);
  });
  EXPECT_EQ(chains, 16 * 12);
}

TEST(SpecularMotion, PathHiddenInTheNextFrameIsFlagged) {
  // A card (1 x 1, in the plane x = 1.5) drops between the static mirror and the card it
  // shows during frame 1 to 2: the paths through its square are hidden in frame 2.
  const std::string json = mirrorScene("", "");
  const int width = 32, height = 24;
  const TrackedScene scene(json.substr(0, json.rfind(']')) + R"(,
      {"type": "rectangle", "size": [1, 1], "material": "card",
       "transform": {"rotate": {"axis": [0, 1, 0], "angle": -90}},
       "animation": {"translate": [{"frame": 1, "value": [1.5, 5, 0]}, {"frame": 2, "value": [1.5, 0, 0]}]}}]})",
                           width, height);
  const TestCamera camera{{0, 0, 5}, 30, width, height};
  int hidden = 0, seen = 0;
  scene.forEachChain(kReflection, [&](int x, int y, const SpecularTrack& track) {
    // Where the path crosses the plane x = 1.5, on its way to the mirror or from it.
    const Vec3d p = cardPointSeen(camera, pixelCentre(x, y), {});
    const Vec3d d = camera.direction(pixelCentre(x, y));
    const Vec3d x1 = camera.position + d * (dot(-camera.position, kMirrorNormal) / dot(d, kMirrorNormal));
    const auto margin = [&](Vec3d a, Vec3d b) {  // > 0 inside the square, < 0 outside
      if ((a.x - 1.5) * (b.x - 1.5) > 0) return -1.0;
      const Vec3d c = a + (b - a) * ((1.5 - a.x) / (b.x - a.x));
      return 0.5 - std::max(std::abs(c.y), std::abs(c.z));
    };
    const double m = std::max(margin(camera.position, x1), margin(x1, p));
    if (std::abs(m) < 0.02) return;  // too close to the square's edge to say
    EXPECT_TRUE(track.backward.has_value()) << "pixel " << x << "," << y;
    if (m > 0) {
      ++hidden;
      EXPECT_FALSE(track.forward.has_value()) << "pixel " << x << "," << y;
    } else {
      ++seen;
      expectMotion(track.forward, {0, 0}, 0, x, y);
    }
  });
  EXPECT_GT(hidden, 10);
  EXPECT_GT(seen, 100);
}

// ---------------------------------------------------------------------------------------
// The decomposed film carries the walk's result, the same bits for any tiling.

TEST(SpecularMotion, FilmChannelsHoldTheWalkAndDoNotDependOnTiles) {
  const std::string json = R"({
    "fps": 1,
    "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov": 32},
    "materials": {"mirror": {"type": "conductor", "specular_color": 1},
                  "glass": {"type": "dielectric", "ior": 1.5},
                  "room": {"type": "diffuse", "reflectance": 0.5}},
    "environment": {"radiance": 1},
    "shapes": [
      {"type": "sphere", "radius": 20, "material": "room",
       "animation": {"rotate": [{"frame": 0, "axis": [0, 1, 0], "angle": -6}, {"frame": 2, "axis": [0, 1, 0], "angle": 6}]}},
      {"type": "sphere", "radius": 0.8, "material": "mirror", "transform": {"translate": [-0.9, 0, 0]}},
      {"type": "sphere", "radius": 0.8, "material": "glass",
       "animation": {"translate": [{"frame": 0, "value": [0.7, -0.1, 0]}, {"frame": 2, "value": [1.1, 0.1, 0.2]}]}}]
  })";
  const Scene parsed = test_support::sceneFromJson(json);
  const int width = 24, height = 18;
  RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.spp = 1;
  settings.decomposition = std::make_shared<Decomposition>(Decomposition::standard());
  const auto [a, b] = test_support::renderedTwoWays(
      settings, [&](const RenderSettings& s) { return FrameRenderer(parsed, s).render(1); });
  const TrackedScene scene(json, width, height);
  for (const auto& [component, name] :
       {std::pair{kReflection, "reflection"}, std::pair{kTransmission, "transmission"}}) {
    int tracked = 0;
    for (const char* buffer : {".motion.X", ".motion.Y", ".motion_back.X", ".motion_back.Y", ".motion_valid.Y"})
      EXPECT_EQ(a.channel(name + std::string(buffer)), b.channel(name + std::string(buffer))) << name << buffer;
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        const SpecularTrack track = scene.track(x, y, component);
        const size_t p = static_cast<size_t>(y * width + x);
        ASSERT_EQ(a.channel(name + std::string(".motion_valid.Y"))[p], track.tracked() ? 1.0f : 0.0f) << name << p;
        if (!track.tracked()) continue;
        ++tracked;
        EXPECT_EQ(a.channel(name + std::string(".motion.X"))[p], static_cast<float>(track.forward->x));
        EXPECT_EQ(a.channel(name + std::string(".motion_back.Y"))[p], static_cast<float>(track.backward->y));
      }
    }
    EXPECT_GT(tracked, 20) << name;
  }
}

}  // namespace
}  // namespace pathfarm
