#pragma once
// A window of frames with everything path-space Metropolis needs, and bidirectional
// sample paths of it to start moves from.
#include <vector>

#include "renderer/accel/embree_device.h"
#include "renderer/accel/shot_geometry.h"
#include "renderer/bidirectional/subpath.h"
#include "renderer/integrators/light_sampler.h"
#include "renderer/metropolis/path_space/path_state.h"
#include "renderer/metropolis/path_space/specular_chain.h"
#include "test_support.h"

namespace pathfarm::test_support {

struct WindowFixture {
  Scene scene;
  EmbreeDevice device;
  ShotGeometry shot;
  WindowTime time;
  WindowGeometry geometry;
  LightSampler lights;
  CameraImportance camera;
  WindowScene window;

  WindowFixture(const std::string& json, FrameWindow frames, int size, int maxDepth)
      : scene(sceneFromJson(json)),
        shot(scene, device),
        time(WindowTime::of(scene, frames)),
        geometry(shot, frames),
        lights(shot),
        camera(scene.camera, size, size),
        window{time, geometry, lights, camera, maxDepth} {}

  // The states of every contributing strategy of `samples` bidirectional samples, each
  // at a window time uniform over the open time, their specular chains straightened;
  // with `weights`, also each state's bidirectional estimate (MIS-weighted f / p, as a
  // luminance), whose sum over the samples divided by `samples` estimates the integral
  // of f over the paths and the open time divided by the open time.
  std::vector<PathSpaceState> samplePaths(int samples, uint64_t seed, std::vector<double>* weights = nullptr) const {
    std::vector<PathSpaceState> states;
    Subpath cameraPath, lightPath;
    std::vector<WeightedPath> paths;
    for (int i = 0; i < samples; ++i) {
      SampleStream stream(SampleKey{seed, 0, i, 0, 0});
      StreamSource u(stream);
      const double tau = time.fromPrimary(u.next1D());
      const WindowInstant instant = *time.instant(tau);
      const BdptScene bdpt = window.frame(instant.frame);
      const Vec2f film{u.next1D() * static_cast<float>(camera.width()), u.next1D() * static_cast<float>(camera.height())};
      generateCameraSubpath(bdpt, instant.shutterFraction, film, u.next2D(), u, maxCameraVertices(bdpt), cameraPath);
      generateLightSubpath(bdpt, instant.shutterFraction, u, maxLightVertices(bdpt), lightPath);
      paths.clear();
      completePathsOf(bdpt, instant.shutterFraction, cameraPath, lightPath, film, u, paths);
      for (WeightedPath& p : paths) {
        if (!straightenChains(bdpt, instant.shutterFraction, p.path.vertices)) continue;
        PathSpaceState s = stateAt(window, std::move(p.path), tau);
        if (!(s.density > 0)) continue;
        states.push_back(std::move(s));
        if (weights) weights->push_back(Contribution{0, p.raster, p.contribution}.scalar());
      }
    }
    return states;
  }
};

}  // namespace pathfarm::test_support
