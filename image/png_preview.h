#pragma once
// An 8-bit sRGB preview of a frame's beauty (R, G, B) for people to look at.
#include <filesystem>
#include <string>

#include "image/frame_image.h"

namespace pathfarm {

// Exposure-scaled, clamped to [0,1], sRGB-encoded; throws std::runtime_error on failure.
void writePngPreview(const std::filesystem::path& file, const FrameImage& frame,
                     float exposure = 1.0f);
// The same PNG, as bytes.
std::string encodePngPreview(const FrameImage& frame, float exposure = 1.0f);

}  // namespace pathfarm
