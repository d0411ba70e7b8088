#include "worker/failure_class.h"

#include "image/exr_io.h"
#include "renderer/scene/mesh_io.h"
#include "renderer/scene/scene_error.h"
#include "renderer/scene/texture.h"

namespace pathfarm::farm {
namespace {

template <class... Errors>
bool isOneOf(const std::exception& error) {
  return ((dynamic_cast<const Errors*>(&error) != nullptr) || ...);
}

}  // namespace

FailureClass classifyFailure(const std::exception& error) {
  if (isOneOf<TransferFailed>(error)) return FAILURE_TRANSPORT;
  // LpeError and PlanError are invalid arguments too.
  if (isOneOf<BadInput, SceneError, MeshError, TextureError, ExrError, std::invalid_argument>(error))
    return FAILURE_BAD_INPUT;
  return FAILURE_WORKER_FAULT;
}

}  // namespace pathfarm::farm
