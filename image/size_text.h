#pragma once
// A frame's size as the error messages write it: "WxH".
#include <string>

namespace pathfarm {

inline std::string sizeText(int width, int height) { return std::to_string(width) + "x" + std::to_string(height); }

}  // namespace pathfarm
