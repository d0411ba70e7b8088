#include "renderer/scene/json_node.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace pathfarm {

nlohmann::json parseJsonDocument(std::string_view text, const std::string& label) {
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw SceneError(label + ": invalid JSON: " + e.what());
  }
}
namespace {

std::string typeName(const nlohmann::json& v) {
  if (v.is_number()) return "a number";
  if (v.is_string()) return "a string";
  if (v.is_object()) return "an object";
  if (v.is_array()) return "an array";
  if (v.is_boolean()) return "a boolean";
  return "null";
}

std::string formatNumber(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

}  // namespace

void JsonNode::fail(const std::string& message) const {
  throw SceneError(file_ + ": " + (path_.empty() ? std::string("(top level)") : path_) + ": " +
                   message);
}

std::string JsonNode::childPath(const std::string& key) const {
  return path_.empty() ? key : path_ + "." + key;
}

bool JsonNode::has(const char* key) const { return value_.is_object() && value_.contains(key); }

JsonNode JsonNode::operator[](const char* key) const {
  if (!value_.is_object()) fail("expected an object, found " + typeName(value_));
  const auto it = value_.find(key);
  if (it == value_.end()) fail(std::string("missing key \"") + key + "\"");
  return {*it, childPath(key), file_};
}

std::optional<JsonNode> JsonNode::optional(const char* key) const {
  if (!has(key)) {
    if (!value_.is_object()) fail("expected an object, found " + typeName(value_));
    return std::nullopt;
  }
  return (*this)[key];
}

void JsonNode::expectKeys(const std::vector<const char*>& known) const {
  if (!value_.is_object()) fail("expected an object, found " + typeName(value_));
  for (const auto& item : value_.items()) {
    const bool isKnown = std::any_of(known.begin(), known.end(),
                                     [&](const char* k) { return item.key() == k; });
    if (!isKnown) {
      std::string list;
      for (const char* k : known) list += (list.empty() ? "" : ", ") + std::string(k);
      JsonNode(item.value(), childPath(item.key()), file_)
          .fail("unknown key (expected one of: " + list + ")");
    }
  }
}

std::vector<JsonNode> JsonNode::elements() const {
  if (!value_.is_array()) fail("expected an array, found " + typeName(value_));
  std::vector<JsonNode> out;
  for (size_t i = 0; i < value_.size(); ++i)
    out.emplace_back(value_[i], path_ + "[" + std::to_string(i) + "]", file_);
  return out;
}

std::vector<std::pair<std::string, JsonNode>> JsonNode::members() const {
  if (!value_.is_object()) fail("expected an object, found " + typeName(value_));
  std::vector<std::pair<std::string, JsonNode>> out;
  for (const auto& item : value_.items())
    out.emplace_back(item.key(), JsonNode(item.value(), childPath(item.key()), file_));
  return out;
}

double JsonNode::number(double min, double max) const {
  if (!value_.is_number()) fail("expected a number, found " + typeName(value_));
  const double v = value_.get<double>();
  if (!std::isfinite(v) || v < min || v > max)
    fail(formatNumber(v) + " is out of range [" + formatNumber(min) + ", " + formatNumber(max) +
         "]");
  return v;
}

int JsonNode::integer(int min, int max) const {
  const double v = number(min, max);
  if (v != std::floor(v)) fail("expected a whole number, found " + formatNumber(v));
  return static_cast<int>(v);
}

std::string JsonNode::string() const {
  if (!value_.is_string()) fail("expected a string, found " + typeName(value_));
  return value_.get<std::string>();
}

bool JsonNode::boolean() const {
  if (!value_.is_boolean()) fail("expected true or false, found " + typeName(value_));
  return value_.get<bool>();
}

std::vector<double> JsonNode::numbers(size_t count) const {
  if (!value_.is_array() || value_.size() != count)
    fail("expected an array of " + std::to_string(count) + " numbers");
  std::vector<double> out;
  for (const JsonNode& e : elements()) out.push_back(e.number(-1e30, 1e30));
  return out;
}

Vec3f JsonNode::vec3() const { return vec3(-1e30f, 1e30f); }

Vec3f JsonNode::vec3(float min, float max) const {
  if (!value_.is_array() || value_.size() != 3) fail("expected an array of 3 numbers");
  const auto e = elements();
  return {static_cast<float>(e[0].number(min, max)), static_cast<float>(e[1].number(min, max)),
          static_cast<float>(e[2].number(min, max))};
}

Rgb JsonNode::rgb(float min, float max) const {
  if (value_.is_number()) return Rgb(static_cast<float>(number(min, max)));
  const Vec3f v = vec3(min, max);
  return {v.x, v.y, v.z};
}

}  // namespace pathfarm
