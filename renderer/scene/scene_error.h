#pragma once
// The error every scene reader throws. Its own header, so that code which only loads
// scenes (or catches their errors) does not parse the JSON library json_node.h brings.
#include <stdexcept>

namespace pathfarm {

// A scene that cannot be loaded; the message names the file and the key path.
class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace pathfarm
