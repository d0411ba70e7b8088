#pragma once
// Moving a path vertex to another time of the window, as the temporal perturbation does
// (Van de Woestijne et al. 2017): a vertex on an animated object keeps its point of the
// object's shape and follows the object; the camera vertex follows the camera; a
// punctual light's vertex follows the light; vertices on static objects and environment
// directions stay.
#include "renderer/bidirectional/path_vertex.h"
#include "renderer/metropolis/window_scene.h"

namespace pathfarm {

// Whether the vertex moves with time: on an animated object or punctual light, or the
// lens point of an animated camera.
bool movesWithTime(const WindowScene& scene, const PathVertex& x);

// The vertex, which lies where its object is at `from`, placed where that object is at
// `to` (position and normals; the shape point, object and primitive stay).
PathVertex placedAt(const WindowScene& scene, const PathVertex& x, WindowInstant from, WindowInstant to);

// The area of world space per area of the object's shape at the vertex at `at`
// (dA_world / dA_shape): 1 for static vertices, for punctual lights and for the camera,
// whose motion is rigid.
double areaScale(const WindowScene& scene, const PathVertex& x, WindowInstant at);

}  // namespace pathfarm
