#pragma once
// Follows one camera sample's path through the decomposition's automaton (Zimmer et al.
// 2015, Section 3). The path's throughput is kept as a weight per automaton state; at a
// vertex with several lobes each lobe's share (f_lobe / pdf) moves to the state its
// symbol leads to, and next-event contributions are split the same way, so the
// components of a sample add up to its undecomposed estimate. Each component also gets
// the features of its first non-specular (D) vertex along the sampled path, and its
// directly seen light: what reaches the camera along a path with no D vertex (an emitter
// or the environment seen directly or through specular chains, Zimmer's E S* L paths),
// which the filters must leave alone (worker/direct_emission.h).
#include <array>
#include <cstdint>
#include <vector>

#include "renderer/decomposition/decomposition.h"
#include "renderer/materials/bsdf.h"

namespace pathfarm {

// What a vertex offers a component as features.
struct VertexFeatures {
  Vec3f position;  // world
  Vec3f normal;    // shading normal, facing the incoming path
  Vec2f uv;
  float depth = 0;     // distance from the camera along the sampled path
  int object = -1;     // scene object index
  uint32_t objectId = 0;
  uint32_t primitive = 0;
};

// One camera sample's share of every component.
struct SampleComponents {
  struct Features : VertexFeatures {
    Rgb reflectance;  // a one-sample estimate of the D lobes' directional albedo
  };
  std::vector<Rgb> color;
  std::vector<Rgb> direct;  // the part of `color` whose path has no D vertex
  std::vector<Features> features;
  std::vector<uint8_t> hasFeatures;

  void reset(int components);
};

class PathDecomposer {
 public:
  PathDecomposer(const Decomposition& decomposition, SampleComponents& out);
  // Starts the next camera sample: clears `out` and puts the path at the eye.
  void begin();

  // Radiance `value` reaching the camera along the current path (an emitter hit, with
  // its MIS weight), without the path's throughput.
  void addEmission(Rgb value);
  // Next-event estimation at the current vertex: f per lobe, times `lightOverPdf`.
  void addLightSample(const LobeList& lobes, const LobeValues& f, Rgb lightOverPdf);
  // The vertex's features for the components whose first D vertex this is, and the
  // path's continuation by `sample` (nullptr: the path ends here).
  void scatter(const LobeList& lobes, const VertexFeatures& vertex, const BsdfSample* sample);
  // Russian roulette's survival scaling.
  void scale(float factor);

 private:
  static constexpr int kMaxStates = 32;
  // The throughput of the paths in one automaton state, apart for paths that have
  // met a D vertex and paths that have not (the latter's light is directly seen).
  struct StateWeight {
    int state;
    bool diffuse;
    Rgb weight;
  };
  // `value` to the component that accepts `state`; also directly seen unless `diffuse`.
  void addTo(int state, bool diffuse, Rgb value);
  void recordFeatures(const LobeList& lobes, const VertexFeatures& vertex, const BsdfSample* sample);

  const Decomposition& decomposition_;
  const LpeAutomaton& automaton_;
  SampleComponents& out_;
  // Two buffers of state weights, swapped at every bounce (no copying, no construction);
  // each state may hold a diffuse and a directly seen entry.
  std::array<StateWeight, 2 * kMaxStates> buffers_[2];
  int current_ = 0;
  int count_ = 0;
  int sampledState_;  // the automaton along the sampled lobes only, for features
};

}  // namespace pathfarm
