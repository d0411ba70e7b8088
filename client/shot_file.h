#pragma once
// Shot files (docs/shot-format.md): what to render and how. A file is read once: its text
// parsed, every key checked, its scene loaded and what every pipeline shares resolved with
// the scene's defaults and paths made absolute. It then reads as the spec of any pipeline
// without touching the file again: the pipeline it names, or each of auto's candidates.
// Reading runs neither the keyframe probe nor auto's pipeline probe (shot_preparation.h and
// pipeline_probe.h do); "decompose": "auto" is resolved as the keys are read, with its own
// small probe render (renderer/setup/auto_decomposition.h).
#include <filesystem>
#include <memory>
#include <string_view>

#include "contract/pipeline.h"
#include "pathfarm/shot.pb.h"
#include "renderer/scene/json_node.h"

namespace pathfarm {
struct Scene;
}

namespace pathfarm::farm {

class ShotFile {
 public:
  // Throw SceneError (renderer/scene/json_node.h) naming the file and key on bad input.
  static ShotFile load(const std::filesystem::path& file);
  // The file's text already in memory: `file` names it in messages, and the scene and
  // output paths resolve against its folder.
  static ShotFile parse(std::string_view text, const std::filesystem::path& file);

  // The pipeline the file names; PIPELINE_AUTO when it names none.
  Pipeline pipeline() const { return named_.pipeline(); }
  // The spec as the pipeline the file names: specAs(pipeline()), read with the file.
  const ShotSpec& spec() const { return named_; }
  // The spec as `pipeline` with that pipeline's keys read and checked. A keyframe interval
  // of "auto" (or none given) to probe stays 0. For PIPELINE_AUTO only the keys every
  // candidate shares are resolved, and each candidate's keys are checked. Throws SceneError.
  ShotSpec specAs(Pipeline pipeline) const;
  // Its scene; null for a noop shot.
  const Scene* scene() const { return scene_.get(); }
  // "rerender_bound": the most pixels the keyframe probe lets an interval re-render.
  double rerenderBound() const;
  // "reference_cache": the folder keeping references between shots (reference_cache.h),
  // absolute; empty when the file names none.
  const std::filesystem::path& referenceCache() const { return referenceCache_; }
  // The file's top level, for messages about what it asks (JsonNode::fail).
  JsonNode root() const { return JsonNode(text_->document, "", text_->label); }

 private:
  struct Text {
    std::string label;
    nlohmann::json document;
  };
  std::shared_ptr<const Text> text_;
  std::shared_ptr<const Scene> scene_;
  ShotSpec common_;  // the keys every pipeline shares
  ShotSpec named_;
  std::filesystem::path referenceCache_;
};

// The file's text, or SceneError.
std::string readShotFileText(const std::filesystem::path& file);

}  // namespace pathfarm::farm
