#pragma once
// Light-path expressions (Heckbert 1990) over the vertex symbols E, D, R, T, compiled
// together into one deterministic automaton. A path is read as the string of its vertex
// symbols from the eye (E) on; the light vertex is implicit at the end. An expression
// uses `.` (any of D, R, T), `*` (zero or more), `+` (one or more), `|`, parentheses
// and concatenation. Where several expressions accept one path, the first listed wins.
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace pathfarm {

enum class PathSymbol : uint8_t { E = 0, D = 1, R = 2, T = 3 };
inline constexpr int kPathSymbols = 4;

// A malformed expression; the message names the expression and the position (0-based).
class LpeError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

class LpeAutomaton {
 public:
  // Throws LpeError for a malformed expression.
  explicit LpeAutomaton(const std::vector<std::string>& expressions);
  LpeAutomaton() : LpeAutomaton(std::vector<std::string>{}) {}

  // The state before any symbol; paths start by reading E.
  int initial() const { return 0; }
  int next(int state, PathSymbol symbol) const {
    return transitions_[static_cast<size_t>(state) * kPathSymbols + static_cast<size_t>(symbol)];
  }
  // The expression a path ending in `state` belongs to (first listed wins), or
  // expressionCount() when none accepts it: the residual.
  int accepting(int state) const { return accepting_[static_cast<size_t>(state)]; }
  // Whether expression `k` can still accept some continuation of a path in `state`.
  bool alive(int state, int k) const {
    return (alive_[static_cast<size_t>(state)] >> k) & 1u;
  }
  // The same for every expression at once: bit k is alive(state, k).
  uint64_t aliveSet(int state) const { return alive_[static_cast<size_t>(state)]; }
  int expressionCount() const { return expressionCount_; }
  int stateCount() const { return static_cast<int>(accepting_.size()); }

 private:
  int expressionCount_ = 0;
  std::vector<int> transitions_;   // stateCount x kPathSymbols
  std::vector<int> accepting_;     // per state
  std::vector<uint64_t> alive_;    // per state, a bit per expression
};

}  // namespace pathfarm
