// The worker's side of failure classes: which exceptions a task may throw are bad input
// (no worker could run it), a transfer, or the worker's own fault.
#include "worker/failure_class.h"

#include <gtest/gtest.h>

#include <new>
#include <stdexcept>

#include "image/exr_io.h"
#include "renderer/decomposition/lpe_automaton.h"
#include "renderer/scene/mesh_io.h"
#include "renderer/scene/scene_error.h"
#include "renderer/scene/texture.h"

namespace pathfarm::farm {
namespace {

TEST(FailureClass, ScenesMeshesTexturesChunksAndArgumentsThatMakeNoSenseAreBadInput) {
  EXPECT_EQ(classifyFailure(SceneError("scene.json: \"radius\": not a number")), FAILURE_BAD_INPUT);
  EXPECT_EQ(classifyFailure(MeshError("a.obj: line 3: vertex nan")), FAILURE_BAD_INPUT);
  EXPECT_EQ(classifyFailure(TextureError("wood.png: not an image")), FAILURE_BAD_INPUT);
  EXPECT_EQ(classifyFailure(ExrError("not an EXR")), FAILURE_BAD_INPUT);
  EXPECT_EQ(classifyFailure(LpeError("E(D")), FAILURE_BAD_INPUT);
  EXPECT_EQ(classifyFailure(std::invalid_argument("frame -1")), FAILURE_BAD_INPUT);
  EXPECT_EQ(classifyFailure(BadInput("tile chunk holds a NaN")), FAILURE_BAD_INPUT);
}

TEST(FailureClass, AChunkThatCouldNotBeMovedIsATransferFailure) {
  EXPECT_EQ(classifyFailure(TransferFailed("cannot fetch input chunk")), FAILURE_TRANSPORT);
}

TEST(FailureClass, EverythingElseIsTheWorkersFault) {
  EXPECT_EQ(classifyFailure(std::bad_alloc()), FAILURE_WORKER_FAULT);
  EXPECT_EQ(classifyFailure(std::runtime_error("this worker cannot see the scene file")), FAILURE_WORKER_FAULT);
  EXPECT_EQ(classifyFailure(std::out_of_range("vector")), FAILURE_WORKER_FAULT);
}

}  // namespace
}  // namespace pathfarm::farm
