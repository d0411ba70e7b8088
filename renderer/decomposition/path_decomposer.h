#pragma once
// Follows one camera sample's path through the decomposition's automaton (Zimmer et al.
// 2015, Section 3). The path's throughput is kept as a weight per automaton state; at a
// vertex with several lobes each lobe's share (f_lobe / pdf) moves to the state its
// symbol leads to, and next-event contributions are split the same way, so the
// components of a sample add up to its undecomposed estimate. Each component also gets
// the features of its first non-specular (D) vertex along the sampled path, and its
// directly seen light: what reaches the camera along a path with no D vertex (an emitter
// or the environment seen directly or through specular chains, Zimmer's E S* L paths),
// which the filters must leave alone (postproc/filters/direct_emission.h). Beside the components it
// keeps the sample's *moving caustic*: light that reached the path's last D vertex through a
// specular chain (Heckbert's L S+ D, e.g. a glass ball focusing a lamp onto the floor) with
// a vertex of that chain on an animated object. Such light moves with the object that
// focuses it, not with the surface it falls on, so no keyframe's motion can carry it
// (postproc/interpolation/caustic_check.h).
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
  bool animated = false;  // the object moves or deforms during the shot
};

// One camera sample's share of every component.
struct SampleComponents {
  struct Features : VertexFeatures {
    Rgb reflectance;  // a one-sample estimate of the D lobes' directional albedo
  };
  std::vector<Rgb> color;
  std::vector<Rgb> direct;  // the part of `color` whose path has no D vertex
  Rgb movingCaustic;        // the part of the sum of `color` carried by moving caustics
  std::vector<Features> features;
  // Bit k: component k got light or features in this sample. A path reaches one to three
  // components of five, so the film adds, and the next sample clears, only these.
  uint32_t touched = 0;
  uint32_t featured = 0;  // bit k: features[k] holds this sample's features

  bool hasFeatures(size_t component) const { return (featured >> component) & 1u; }

  static constexpr int kMaxComponents = 32;  // the bits of `touched`
  void reset(int components);
  void touch(size_t component) { touched |= 1u << component; }
};

class PathDecomposer {
 public:
  PathDecomposer(const Decomposition& decomposition, SampleComponents& out);
  // Starts the next camera sample: clears `out` and puts the path at the eye.
  void begin();

  // Radiance `value` reaching the camera along the current path (an emitter hit, with
  // its MIS weight), without the path's throughput.
  void addEmission(Rgb value);
  // Next-event estimation at the current vertex (on an animated object or not): f per
  // lobe, times `lightOverPdf`.
  void addLightSample(const LobeList& lobes, const LobeValues& f, Rgb lightOverPdf, bool animatedVertex);
  // The vertex's features for the components whose first D vertex this is, and the
  // path's continuation by `sample` (nullptr: the path ends here).
  void scatter(const LobeList& lobes, const VertexFeatures& vertex, const BsdfSample* sample);
  // Russian roulette's survival scaling.
  void scale(float factor);

 private:
  static constexpr int kMaxStates = 32;
  // What follows the path's last D vertex: nothing yet, specular vertices on still objects
  // only, or a specular vertex on an animated object (a moving caustic if light ends it).
  enum class Tail : uint8_t { None, Still, Moving };
  // The throughput of the paths in one automaton state, apart for paths that have met a D
  // vertex and paths that have not (the latter's light is directly seen), and by tail.
  struct StateWeight {
    int state;
    bool diffuse;
    Tail tail;
    Rgb weight;
  };
  // The tail after a lobe of `symbol` at a vertex (animated or not) of a path in `from`.
  static Tail tailAfter(const StateWeight& from, PathSymbol symbol, bool animatedVertex);
  // `value` to the component that accepts `state`; also directly seen unless `diffuse`,
  // and a moving caustic with a moving tail.
  void addTo(int state, bool diffuse, Tail tail, Rgb value);
  void recordFeatures(const LobeList& lobes, const VertexFeatures& vertex, const BsdfSample* sample);

  const Decomposition& decomposition_;
  const LpeAutomaton& automaton_;
  SampleComponents& out_;
  // Two buffers of state weights, swapped at every bounce (no copying, no construction);
  // each state may hold a directly seen entry and a diffuse one per tail.
  std::array<StateWeight, 4 * kMaxStates> buffers_[2];
  int current_ = 0;
  int count_ = 0;
  int sampledState_;  // the automaton along the sampled lobes only, for features
};

}  // namespace pathfarm
