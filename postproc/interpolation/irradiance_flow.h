#pragma once
// A component's irradiance motion between two keyframes (component_motion.h): the optical
// flow of its irradiance, bootstrapped by its primary motion (Zimmer et al. 2015, Section
// 4.3), solved in bands of rows.
//
// Why bands: the flow is a global variational solve, so every pixel's flow depends a
// little on every row of the frame, and a task computing it would hold whole keyframes
// (gigabytes at 4K). A frame taller than a band is cut into bands of at most
// FlowBanding::rows rows; each is solved on its rows and `halo` rows on either side and
// keeps its own rows. A band's flow depends only on the keyframes' rows of its halo and on
// the rows of the other keyframe its primary motion leads to, so rows computed alone are
// the bits the whole frame gets. What the bands cost in accuracy against one solve over
// the frame is measured by bench/interpolation_benchmark (docs/performance.md).
#include <functional>
#include <vector>

#include "postproc/filters/nlmeans.h"
#include "postproc/filters/warp.h"
#include "postproc/flow/optical_flow.h"
#include "postproc/interpolation/component_motion.h"

namespace pathfarm {

struct FlowBanding {
  int rows = 512;  // a band keeps at most this many rows (0: the frame is one band)
  int halo = 128;  // rows solved on either side of them
};

struct FlowBand {
  int first = 0, end = 0;          // the rows it keeps
  int haloFirst = 0, haloEnd = 0;  // the rows it is solved on
};

// The bands of a frame `frameHeight` rows tall, top to bottom, cut as the farm's filter
// windows are (evenRowBands, image/row_bands.h) with banding.rows rows at most.
std::vector<FlowBand> flowBandsOf(int frameHeight, FlowBanding banding = {});

// One keyframe's component on rows [first, end): its irradiance (R, G, B planes, finite)
// and its primary motion towards the other keyframe, placed in the frame
// (MotionField::top, frameHeight).
struct ComponentBand {
  Planes irradiance;
  MotionField motion;
};

// How a band reads a keyframe's component: its halo's rows (`rows`), and the irradiance
// alone of the rows the other keyframe's motion leads to beyond them (`irradiance`).
struct ComponentRows {
  int width = 0, height = 0;  // the frame's
  std::function<ComponentBand(int first, int end)> rows;
  std::function<Planes(int first, int end)> irradiance;
};

// Where the forward and backward flows of a band disagree by more than this many pixels
// (forwardBackward, optical_flow.h), neither is trusted. On noisy keyframes the pyramid's
// coarse levels find matches in the noise, flows tens of pixels off the true motion that
// their finest levels keep; the two directions then rarely agree, while flows of real
// irradiance motion do (docs/performance.md, "Irradiance flows checked forward and backward").
// The interpolation takes the primary motion where the flow is invalid.
inline constexpr float kFlowConsistency = 0.5f;

// The flows of rows [first, end): forward from keyframe 0 to 1, backward from 1 to 0, each
// valid where p + flow(p) lies inside the frame and, with `consistency` > 0, the other
// direction's flow over the band's halo leads back within `consistency` pixels (a flow
// leading beyond the halo is not). A band whose halo holds no irradiance of
// the component in either keyframe has nothing to track: its flows are invalid there
// (`skippedRows` counts those of rows [first, end)). The callbacks of `k0` and `k1` are
// called only during the call.
struct IrradianceFlows {
  MotionField forward, backward;
  int bands = 0, bandsSkipped = 0, skippedRows = 0;
};
IrradianceFlows irradianceFlowRows(const ComponentRows& k0, const ComponentRows& k1, int first, int end,
                                   const FlowSettings& settings, FlowBanding banding = {},
                                   float consistency = kFlowConsistency);

// Adds the irradiance motion of every component of `motions` but "" (the frame-wide motion):
// irradianceFlowRows of `<c>.irradiance.R/G/B` over the whole frame, in the log domain
// (settings.logDomain is forced on), bootstrapped by the component's primary motion
// forward/backward (0 where that is invalid), valid where the two directions agree within
// `consistency` pixels. Sets hasIrradianceMotion. Throws
// std::invalid_argument for mismatched sizes or decompositions, missing irradiance
// channels, non-finite values or a component of `motions` the keyframes do not have.
void addIrradianceFlow(ComponentMotions& motions, const FrameImage& k0, const FrameImage& k1,
                       const FlowSettings& settings, FlowBanding banding = {},
                       float consistency = kFlowConsistency);

}  // namespace pathfarm
