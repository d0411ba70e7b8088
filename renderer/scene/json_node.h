#pragma once
// A position inside a parsed scene file: the JSON value plus its key path, so every
// error names the file and the exact key (`scene.json: shapes[3].radius: ...`).
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "renderer/math/vecmath.h"
#include "renderer/scene/scene_error.h"

namespace pathfarm {

// A JSON document parsed from `text`; anything nlohmann refuses (a syntax error, a number
// beyond double's range) is a SceneError "label: invalid JSON: ...".
nlohmann::json parseJsonDocument(std::string_view text, const std::string& label);

class JsonNode {
 public:
  JsonNode(const nlohmann::json& value, std::string path, const std::string& fileLabel)
      : value_(value), path_(std::move(path)), file_(fileLabel) {}

  [[noreturn]] void fail(const std::string& message) const;

  const std::string& path() const { return path_; }
  bool has(const char* key) const;
  // A required member of an object.
  JsonNode operator[](const char* key) const;
  std::optional<JsonNode> optional(const char* key) const;
  // Rejects members not in `known`, which catches misspelled keys.
  void expectKeys(const std::vector<const char*>& known) const;
  std::vector<JsonNode> elements() const;  // of an array
  std::vector<std::pair<std::string, JsonNode>> members() const;  // of an object

  bool isNumber() const { return value_.is_number(); }
  bool isString() const { return value_.is_string(); }
  bool isObject() const { return value_.is_object(); }
  bool isArray() const { return value_.is_array(); }

  double number(double min, double max) const;
  int integer(int min, int max) const;
  std::string string() const;
  bool boolean() const;
  Vec3f vec3() const;
  Vec3f vec3(float min, float max) const;
  Rgb rgb(float min, float max) const;  // [r,g,b] or a single number for grey
  std::vector<double> numbers(size_t count) const;

 private:
  std::string childPath(const std::string& key) const;
  const nlohmann::json& value_;
  std::string path_;
  const std::string& file_;
};

}  // namespace pathfarm
