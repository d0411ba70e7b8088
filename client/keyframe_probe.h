#pragma once
// Choosing the keyframe interval k of an interpolating shot (di, dui) from a probe: the
// first frames are rendered small and with few samples, and for each candidate k the
// frame halfway between two keyframes k apart is interpolated exactly as the farm would
// (primary motion, per component, the directly seen light taken from the frame itself) and
// checked by the farm's rules against the probe's own render of it (in_between_checks.h;
// all but the light check, which would read the probe's raw keyframes' noise as change);
// the share it flags predicts the shot's re-render of its in-between frames. The largest k
// whose prediction stays under the bound wins. A quarter-resolution probe sees edges four
// times thicker relative to the image, so its silhouette and edge shares, and the
// prediction, err on the high side.
#include <string>

#include "pathfarm/shot.pb.h"

namespace pathfarm {
struct Scene;
}

namespace pathfarm::farm {

struct KeyframeChoice {
  int interval = 1;
  std::string reason;  // the predictions behind the choice, for the report
};

// `spec` has its frames, resolution and decomposition resolved. Tries k = maxInterval
// down to 2 (fewer when the shot is shorter).
KeyframeChoice chooseKeyframeInterval(const Scene& scene, const ShotSpec& spec, double rerenderBound,
                                      int maxInterval = 8);

}  // namespace pathfarm::farm
