// The camera as a sensor: its importance and direction density integrate to 1 over the
// film (analytically they must, camera_importance.h), and connections land where the
// pinhole projection puts a point.
#include "renderer/bidirectional/camera_importance.h"

#include <gtest/gtest.h>

#include "renderer/math/frame.h"
#include "test_support.h"
#include "renderer/math/sampling.h"

namespace pathfarm {
namespace {

// The materials scene's camera, which looks down at its subject, with another aperture.
CameraDesc tiltedCamera(float aperture) {
  CameraDesc desc = loadScene(test_support::sourceDir() / "scenes/materials/scene.json").camera;
  desc.apertureRadius = aperture;
  desc.focusDistance = 3;
  return desc;
}

// Midpoint rule over the cone of directions within 40 degrees of the viewing axis (the
// film spans at most 31 degrees from it): the integral of We cos and of the density.
void integrateOverDirections(const CameraImportance& camera, Vec3f lensPoint, double& importance, double& density) {
  const Frame frame = Frame::fromNormal(camera.viewDirection(0));
  const int n = 700;
  const double maxTheta = 40.0 * kPi / 180.0;
  importance = density = 0;
  for (int i = 0; i < n; ++i) {
    const double theta = (i + 0.5) / n * maxTheta;
    for (int j = 0; j < n; ++j) {
      const double phi = (j + 0.5) / n * 2 * kPi;
      const Vec3f local{static_cast<float>(std::sin(theta) * std::cos(phi)),
                        static_cast<float>(std::sin(theta) * std::sin(phi)), static_cast<float>(std::cos(theta))};
      const Vec3f d = frame.toWorld(local);
      const double dOmega = std::sin(theta) * (maxTheta / n) * (2 * kPi / n);
      importance += camera.importance(lensPoint, d, 0) * std::cos(theta) * dOmega;
      density += camera.directionPdf(lensPoint, d, 0) * dOmega;
    }
  }
}

TEST(CameraImportance, PinholeImportanceAndDensityIntegrateToOneOverTheFilm) {
  const CameraDesc desc = tiltedCamera(0);
  const CameraImportance camera(desc, 48, 32);
  double importance, density;
  integrateOverDirections(camera, camera.camera().cameraToWorld(0).point({0, 0, 0}), importance, density);
  EXPECT_NEAR(importance, 1.0, 2e-3);
  EXPECT_NEAR(density, 1.0, 2e-3);
}

TEST(CameraImportance, ThinLensImportanceIntegratesToOneOverLensAndFilm) {
  const CameraDesc desc = tiltedCamera(0.05f);
  const CameraImportance camera(desc, 40, 40);
  // The importance is the same from every lens point up to the film's shift, so a few
  // lens points stand for the lens: each integral over directions is 1 / lensArea.
  for (const Vec2f u : {Vec2f{0.5f, 0.5f}, Vec2f{0.1f, 0.8f}, Vec2f{0.95f, 0.3f}}) {
    const Vec2f disk = sampleUniformDisk(u);
    const Vec3f lens = camera.camera().cameraToWorld(0).point({disk.x * 0.05f, disk.y * 0.05f, 0});
    double importance, density;
    integrateOverDirections(camera, lens, importance, density);
    EXPECT_NEAR(importance / camera.lensDensity(), 1.0, 3e-3);
    EXPECT_NEAR(density, 1.0, 3e-3);
  }
}

TEST(CameraImportance, ConnectionsLandWhereTheCameraProjectsAndTheRayCameFrom) {
  const CameraDesc pinholeDesc = tiltedCamera(0), lensDesc = tiltedCamera(0.05f);
  const CameraImportance pinhole(pinholeDesc, 64, 48), lens(lensDesc, 64, 48);
  const Vec3f point{-0.2f, 0.6f, -0.4f};
  const auto c = pinhole.connect(point, 0, {0.3f, 0.7f});
  ASSERT_TRUE(c.has_value());
  const auto projected = pinhole.camera().project(point, 0);
  EXPECT_NEAR(c->raster.x, projected->x, 1e-3);
  EXPECT_NEAR(c->raster.y, projected->y, 1e-3);
  // A thin-lens ray generated through a film position and lens sample comes back to them.
  const Ray ray = lens.camera().generateRay({20.25f, 31.5f}, {0.8f, 0.2f}, 0);
  const auto back = lens.connect(ray.origin + ray.direction * 2.5f, 0, {0.8f, 0.2f});
  ASSERT_TRUE(back.has_value());
  EXPECT_NEAR(back->raster.x, 20.25f, 2e-3);
  EXPECT_NEAR(back->raster.y, 31.5f, 2e-3);
}

}  // namespace
}  // namespace pathfarm
