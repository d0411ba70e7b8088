#include "renderer/decomposition/path_decomposer.h"

#include <algorithm>
#include <bit>
#include <stdexcept>

namespace pathfarm {
namespace {

PathSymbol symbolOf(LobeSymbol s) {
  switch (s) {
    case LobeSymbol::D: return PathSymbol::D;
    case LobeSymbol::R: return PathSymbol::R;
    case LobeSymbol::T: return PathSymbol::T;
  }
  return PathSymbol::D;
}

bool hasDiffuseLobe(const LobeList& lobes) {
  for (int l = 0; l < lobes.count; ++l)
    if (lobes.lobes[l].symbol == LobeSymbol::D) return true;
  return false;
}

}  // namespace

void SampleComponents::reset(int components) {
  const auto n = static_cast<size_t>(components);
  if (color.size() != n) {  // the first sample; afterwards only what the last one touched is cleared
    color.assign(n, Rgb());
    direct.assign(n, Rgb());
    features.resize(n);
    touched = 0;
  }
  for (uint32_t bits = touched; bits != 0; bits &= bits - 1) {
    const auto k = static_cast<size_t>(std::countr_zero(bits));
    color[k] = Rgb();
    direct[k] = Rgb();
  }
  touched = 0;
  featured = 0;
  movingCaustic = Rgb();
}

PathDecomposer::PathDecomposer(const Decomposition& decomposition, SampleComponents& out)
    : decomposition_(decomposition), automaton_(decomposition.automaton()), out_(out) {
  if (automaton_.stateCount() > kMaxStates)
    throw std::invalid_argument("the decomposition's automaton has more than " + std::to_string(kMaxStates) +
                                " states");
  if (decomposition.size() > SampleComponents::kMaxComponents)
    throw std::invalid_argument("the decomposition has more than " + std::to_string(SampleComponents::kMaxComponents) +
                                " components");
  begin();
}

void PathDecomposer::begin() {
  out_.reset(decomposition_.size());
  sampledState_ = automaton_.next(automaton_.initial(), PathSymbol::E);
  current_ = 0;
  buffers_[0][0] = {sampledState_, false, Tail::None, Rgb(1.0f)};
  count_ = 1;
}

PathDecomposer::Tail PathDecomposer::tailAfter(const StateWeight& from, PathSymbol symbol, bool animatedVertex) {
  if (symbol == PathSymbol::D || !from.diffuse) return Tail::None;
  return animatedVertex || from.tail == Tail::Moving ? Tail::Moving : Tail::Still;
}

void PathDecomposer::addTo(int state, bool diffuse, Tail tail, Rgb value) {
  const auto component = static_cast<size_t>(automaton_.accepting(state));
  out_.touch(component);
  out_.color[component] += value;
  if (!diffuse) out_.direct[component] += value;
  if (tail == Tail::Moving) out_.movingCaustic += value;
}

void PathDecomposer::addEmission(Rgb value) {
  const auto& states = buffers_[current_];
  for (int i = 0; i < count_; ++i) addTo(states[i].state, states[i].diffuse, states[i].tail, states[i].weight * value);
}

void PathDecomposer::addLightSample(const LobeList& lobes, const LobeValues& f, Rgb lightOverPdf,
                                    bool animatedVertex) {
  for (int l = 0; l < lobes.count; ++l) {
    if (f.value[l].isBlack()) continue;
    const Rgb contribution = f.value[l] * lightOverPdf;
    const PathSymbol symbol = symbolOf(lobes.lobes[l].symbol);
    const bool diffuse = symbol == PathSymbol::D;
    const auto& states = buffers_[current_];
    for (int i = 0; i < count_; ++i)
      addTo(automaton_.next(states[i].state, symbol), states[i].diffuse || diffuse,
            tailAfter(states[i], symbol, animatedVertex), states[i].weight * contribution);
  }
}

void PathDecomposer::recordFeatures(const LobeList& lobes, const VertexFeatures& vertex, const BsdfSample* sample) {
  // This vertex is component k's first non-specular vertex when k, still alive, reads
  // D here and had no features yet; the residual takes the sampled path's first D vertex.
  const int afterD = automaton_.next(sampledState_, PathSymbol::D);
  Rgb reflectance;
  if (sample) {
    for (int l = 0; l < lobes.count; ++l)
      if (lobes.lobes[l].symbol == LobeSymbol::D) reflectance += sample->lobeWeight[l];
  }
  const auto alive = static_cast<uint32_t>(automaton_.aliveSet(afterD)) | (1u << decomposition_.residual());
  for (uint32_t bits = alive & ~out_.featured; bits != 0; bits &= bits - 1) {
    const auto k = static_cast<size_t>(std::countr_zero(bits));
    SampleComponents::Features& features = out_.features[k];
    static_cast<VertexFeatures&>(features) = vertex;
    features.reflectance = reflectance;
    out_.featured |= 1u << k;
    out_.touch(k);
  }
}

void PathDecomposer::scatter(const LobeList& lobes, const VertexFeatures& vertex, const BsdfSample* sample) {
  if (hasDiffuseLobe(lobes)) recordFeatures(lobes, vertex, sample);
  if (!sample) {
    count_ = 0;
    return;
  }
  const auto& states = buffers_[current_];
  auto& next = buffers_[1 - current_];
  int nextCount = 0;
  for (int l = 0; l < lobes.count; ++l) {
    if (sample->lobeWeight[l].isBlack()) continue;
    const PathSymbol symbol = symbolOf(lobes.lobes[l].symbol);
    for (int i = 0; i < count_; ++i) {
      const int state = automaton_.next(states[i].state, symbol);
      const bool diffuse = states[i].diffuse || symbol == PathSymbol::D;
      const Tail tail = tailAfter(states[i], symbol, vertex.animated);
      const Rgb weight = states[i].weight * sample->lobeWeight[l];
      int j = 0;
      while (j < nextCount && (next[j].state != state || next[j].diffuse != diffuse || next[j].tail != tail)) ++j;
      if (j == nextCount) next[nextCount++] = {state, diffuse, tail, Rgb()};
      next[j].weight += weight;
    }
  }
  current_ = 1 - current_;
  count_ = nextCount;
  sampledState_ = automaton_.next(sampledState_, symbolOf(lobes.lobes[sample->lobe].symbol));
}

void PathDecomposer::scale(float factor) {
  auto& states = buffers_[current_];
  for (int i = 0; i < count_; ++i) states[i].weight *= factor;
}

}  // namespace pathfarm
