#pragma once
// The parts of the scene loader, one per kind of JSON block (used by scene_loader.cpp).
#include <filesystem>

#include "renderer/scene/json_node.h"
#include "renderer/scene/scene.h"

namespace pathfarm {

// The largest coordinate a scene file may give a position: beyond it a float's spacing
// (about 1 at 1e7) is coarser than any scene's detail, and a typo is more likely than a scene.
inline constexpr float kMaxCoordinate = 1e7f;

// {"translate": [x,y,z], "rotate": ROTATION, "scale": s | [sx,sy,sz]}
Trs parseTrs(const JsonNode& node);
// {"axis": [x,y,z], "angle": degrees} or {"quaternion": [w,x,y,z]}
Quaternion parseRotation(const JsonNode& node);
// {"translate": [KEY...], "rotate": [KEY...], "scale": [KEY...]}, each key having
// "time" (seconds) or "frame" (converted with fps) and a value.
void parseAnimation(const JsonNode& node, double fps, AnimatedTrs& animation);

// {"radiance": RGB} or {"map": FILE, "strength": s, "rotation": degrees}; FILE relative
// to `folder`.
EnvironmentLight parseEnvironment(const JsonNode& node, const std::filesystem::path& folder);

// {"type": "point"|"spot"|"directional", "intensity": RGB, "position", "direction",
// "transform", "animation", "inner_cone", "outer_cone", "name"}
PunctualLight parsePunctualLight(const JsonNode& node, double fps);

Material parseMaterial(const JsonNode& node, const std::filesystem::path& folder,
                       std::vector<ImageTexture>& textures);

}  // namespace pathfarm
