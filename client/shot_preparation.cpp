#include "client/shot_preparation.h"

#include "client/keyframe_probe.h"
#include "client/reference_choice.h"
#include "renderer/scene/scene.h"
#include "scheduler/planner.h"

namespace pathfarm::farm {
namespace {

// "keyframe_interval": "auto" (or none given) in an interpolating shot: the probe's choice.
ShotSpec withKeyframesChosen(ShotSpec spec, const ShotFile& file) {
  if (!isFilteringPipeline(spec.pipeline()) || spec.keyframe_interval() > 0) return spec;
  const KeyframeChoice choice = chooseKeyframeInterval(*file.scene(), spec, file.rerenderBound());
  spec.set_keyframe_interval(choice.interval);
  spec.set_keyframe_reason(choice.reason);
  // dui with every frame a keyframe interpolates nothing and only upsamples quarter-sample
  // renders, which loses what no half-resolution filter restores (texture edges, thin
  // lines): on the moving-camera suite that cost 3x pt at equal error, d 0.9x
  // (docs/performance.md). So such a shot renders every frame at full spp and denoises it.
  if (choice.interval == 1 && spec.pipeline() == PIPELINE_DUI) {
    spec.set_pipeline(PIPELINE_D);
    spec.set_pipeline_reason("the shot asked for dui, but its probe chose k = 1, so nothing would be interpolated: every "
                             "frame is rendered at the shot's spp and denoised instead of upsampled from a quarter of "
                             "the samples");
  }
  return spec;
}

}  // namespace

ShotSpec preparedShot(const ShotFile& file, Pipeline pipeline) {
  ShotSpec spec = pipeline == file.pipeline() ? file.spec() : file.specAs(pipeline);
  const PipelineFamily family = traitsOf(pipeline).family;
  if (family == PipelineFamily::Choice || family == PipelineFamily::Noop) return spec;
  spec = withReferenceChosen(withKeyframesChosen(std::move(spec), file), *file.scene());
  if (plannedTasksAtLeast(spec) <= ShotLimits{}.maxTasks) {
    try {
      planShot(spec);
    } catch (const PlanError& e) {
      file.root().fail(e.what());
    }
  }
  return spec;
}

ShotSpec preparedShot(const ShotFile& file) { return preparedShot(file, file.pipeline()); }

ShotSpec loadShotFile(const std::filesystem::path& file) { return preparedShot(ShotFile::load(file)); }

}  // namespace pathfarm::farm
