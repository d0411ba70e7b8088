#pragma once
// A path-space decomposition (Zimmer et al. 2015): an ordered list of named light-path
// expressions plus the automatic `residual`, which receives every path no expression
// accepts. Overlapping expressions resolve first-listed-wins.
#include <string>
#include <vector>

#include "renderer/decomposition/lpe_automaton.h"

namespace pathfarm {

struct Component {
  std::string name;
  std::string expression;
};

class Decomposition {
 public:
  // diffuse_direct: ED, diffuse_indirect: ED.+, reflection: ERD.*, transmission: ETTD.*
  static Decomposition standard();
  // "default", or "name=EXPR,name=EXPR,..." (the residual is added; a listed
  // "residual" is skipped, so describe()'s text parses back). Throws LpeError
  // (std::invalid_argument) for a malformed list or expression.
  static Decomposition parse(const std::string& spec);
  explicit Decomposition(std::vector<Component> components);

  // The listed components and then the residual.
  int size() const { return static_cast<int>(components_.size()) + 1; }
  int residual() const { return static_cast<int>(components_.size()); }
  const std::string& name(int component) const;
  const std::vector<Component>& components() const { return components_; }
  const LpeAutomaton& automaton() const { return automaton_; }
  // A named component is specular when its expression cannot take the camera's first
  // vertex as its non-specular one (reflection ERD.*, transmission ETTD.*): what it
  // shows lies beyond a mirror or glass, and its motion is the manifold walk's.
  bool isSpecular(int component) const;
  // The specular components' names, comma-separated ("reflection,transmission"): what the
  // EXR header records as `pathfarm.specular_components`.
  std::string describeSpecular() const;
  // "diffuse_direct=ED,...,residual": what the EXR header records.
  std::string describe() const;

 private:
  std::vector<Component> components_;
  LpeAutomaton automaton_;
};

}  // namespace pathfarm
