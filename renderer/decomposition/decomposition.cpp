#include "renderer/decomposition/decomposition.h"

#include <algorithm>
#include <cctype>
#include <set>

namespace pathfarm {
namespace {

const std::string kResidual = "residual";

std::vector<std::string> expressionsOf(const std::vector<Component>& components) {
  std::vector<std::string> out;
  for (const Component& c : components) out.push_back(c.expression);
  return out;
}

bool isValidName(const std::string& name) {
  if (name.empty()) return false;
  for (char c : name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  return true;
}

}  // namespace

Decomposition::Decomposition(std::vector<Component> components)
    : components_(std::move(components)), automaton_(expressionsOf(components_)) {
  std::set<std::string> names{kResidual};
  for (const Component& c : components_) {
    // Names become EXR layer names: "<name>.color.R".
    if (!isValidName(c.name)) throw LpeError("component name \"" + c.name + "\": use letters, digits and _");
    if (!names.insert(c.name).second) throw LpeError("component name \"" + c.name + "\" is used twice");
  }
}

Decomposition Decomposition::standard() {
  return Decomposition({{"diffuse_direct", "ED"},
                        {"diffuse_indirect", "ED.+"},
                        {"reflection", "ERD.*"},
                        {"transmission", "ETTD.*"}});
}

Decomposition Decomposition::parse(const std::string& spec) {
  if (spec == "default") return standard();
  std::vector<Component> components;
  size_t start = 0;
  while (start <= spec.size()) {
    const size_t comma = std::min(spec.find(',', start), spec.size());
    const std::string item = spec.substr(start, comma - start);
    start = comma + 1;
    if (item == kResidual) continue;  // always there; describe() lists it
    const size_t equals = item.find('=');
    if (equals == std::string::npos)
      throw LpeError("decomposition \"" + spec + "\": expected name=EXPRESSION, found \"" + item + "\"");
    components.push_back({item.substr(0, equals), item.substr(equals + 1)});
  }
  return Decomposition(std::move(components));
}

const std::string& Decomposition::name(int component) const {
  return component == residual() ? kResidual : components_[static_cast<size_t>(component)].name;
}

bool Decomposition::isSpecular(int component) const {
  if (component == residual()) return false;
  const int eye = automaton_.next(automaton_.initial(), PathSymbol::E);
  return automaton_.alive(eye, component) && !automaton_.alive(automaton_.next(eye, PathSymbol::D), component);
}

std::string Decomposition::describeSpecular() const {
  std::string text;
  for (int k = 0; k < residual(); ++k)
    if (isSpecular(k)) text += (text.empty() ? "" : ",") + name(k);
  return text;
}

std::string Decomposition::describe() const {
  std::string text;
  for (const Component& c : components_) text += c.name + "=" + c.expression + ",";
  return text + kResidual;
}

}  // namespace pathfarm
