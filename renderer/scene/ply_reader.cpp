// Stanford PLY reader: ascii and binary (little and big endian) bodies.
#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "renderer/scene/mesh_io.h"
#include "renderer/scene/mesh_io_detail.h"

namespace pathfarm {

namespace fs = std::filesystem;

using mesh_io_detail::fail;
using mesh_io_detail::quoteText;
using mesh_io_detail::readWholeFile;

namespace {

enum class ScalarType : uint8_t { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

size_t sizeOf(ScalarType t) {
  switch (t) {
    case ScalarType::Int8:
    case ScalarType::UInt8:
      return 1;
    case ScalarType::Int16:
    case ScalarType::UInt16:
      return 2;
    case ScalarType::Int32:
    case ScalarType::UInt32:
    case ScalarType::Float32:
      return 4;
    case ScalarType::Float64:
      return 8;
  }
  return 1;
}

bool isInteger(ScalarType t) { return t != ScalarType::Float32 && t != ScalarType::Float64; }

std::optional<ScalarType> parseScalarType(std::string_view name) {
  static constexpr std::pair<std::string_view, ScalarType> kNames[] = {
      {"char", ScalarType::Int8},      {"int8", ScalarType::Int8},
      {"uchar", ScalarType::UInt8},    {"uint8", ScalarType::UInt8},
      {"short", ScalarType::Int16},    {"int16", ScalarType::Int16},
      {"ushort", ScalarType::UInt16},  {"uint16", ScalarType::UInt16},
      {"int", ScalarType::Int32},      {"int32", ScalarType::Int32},
      {"uint", ScalarType::UInt32},    {"uint32", ScalarType::UInt32},
      {"float", ScalarType::Float32},  {"float32", ScalarType::Float32},
      {"double", ScalarType::Float64}, {"float64", ScalarType::Float64},
  };
  for (const auto& [n, t] : kNames) {
    if (n == name) return t;
  }
  return std::nullopt;
}

struct PlyProperty {
  std::string name;
  ScalarType type = ScalarType::Float32;  // the item type for lists
  bool isList = false;
  ScalarType countType = ScalarType::UInt8;
};

struct PlyElement {
  std::string name;
  uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

enum class PlyFormat { Ascii, BinaryLittleEndian, BinaryBigEndian };

struct PlyHeader {
  PlyFormat format = PlyFormat::Ascii;
  std::vector<PlyElement> elements;
  size_t bodyOffset = 0;
};

std::vector<std::string_view> splitWords(std::string_view line) {
  std::vector<std::string_view> words;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    const size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > start) words.push_back(line.substr(start, i - start));
  }
  return words;
}

std::optional<uint64_t> parseCount(std::string_view text) {
  uint64_t value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

PlyHeader parsePlyHeader(const fs::path& file, std::string_view data) {
  // Magic: the first line is exactly "ply" (LF or CRLF line ends).
  if (!(data.starts_with("ply\n") || data.starts_with("ply\r\n"))) {
    fail(file, "not a PLY file (bad magic, expected 'ply' on the first line)");
  }
  PlyHeader header;
  bool haveFormat = false;
  size_t pos = data.find('\n') + 1;
  size_t lineNumber = 1;
  while (true) {
    const size_t eol = data.find('\n', pos);
    if (eol == std::string_view::npos) fail(file, "truncated header (no end_header line)");
    std::string_view line = data.substr(pos, eol - pos);
    pos = eol + 1;
    ++lineNumber;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    const std::vector<std::string_view> words = splitWords(line);
    if (words.empty()) continue;
    const std::string_view keyword = words[0];
    const std::string where = "header line " + std::to_string(lineNumber) + ": ";

    if (keyword == "end_header") {
      if (words.size() != 1) fail(file, where + "unexpected text after end_header");
      break;
    }
    if (keyword == "comment" || keyword == "obj_info") continue;
    if (keyword == "format") {
      if (words.size() != 3) fail(file, where + "malformed format line " + quoteText(line));
      if (words[1] == "ascii") {
        header.format = PlyFormat::Ascii;
      } else if (words[1] == "binary_little_endian") {
        header.format = PlyFormat::BinaryLittleEndian;
      } else if (words[1] == "binary_big_endian") {
        header.format = PlyFormat::BinaryBigEndian;
      } else {
        fail(file, where + "unsupported PLY format " + quoteText(words[1]));
      }
      if (words[2] != "1.0") fail(file, where + "unsupported PLY version " + quoteText(words[2]));
      haveFormat = true;
      continue;
    }
    if (keyword == "element") {
      if (words.size() != 3) fail(file, where + "malformed element line " + quoteText(line));
      const std::optional<uint64_t> count = parseCount(words[2]);
      if (!count) fail(file, where + "bad element count " + quoteText(words[2]));
      header.elements.push_back({std::string(words[1]), *count, {}});
      continue;
    }
    if (keyword == "property") {
      if (header.elements.empty()) fail(file, where + "property before any element");
      PlyProperty property;
      if (words.size() >= 2 && words[1] == "list") {
        if (words.size() != 5) fail(file, where + "malformed list property " + quoteText(line));
        const auto countType = parseScalarType(words[2]);
        const auto itemType = parseScalarType(words[3]);
        if (!countType) fail(file, where + "unknown property type " + quoteText(words[2]));
        if (!itemType) fail(file, where + "unknown property type " + quoteText(words[3]));
        if (!isInteger(*countType)) {
          fail(file, where + "list count type must be an integer type, not " + quoteText(words[2]));
        }
        property.isList = true;
        property.countType = *countType;
        property.type = *itemType;
        property.name = std::string(words[4]);
      } else {
        if (words.size() != 3) fail(file, where + "malformed property line " + quoteText(line));
        const auto type = parseScalarType(words[1]);
        if (!type) fail(file, where + "unknown property type " + quoteText(words[1]));
        property.type = *type;
        property.name = std::string(words[2]);
      }
      header.elements.back().properties.push_back(std::move(property));
      continue;
    }
    fail(file, where + "unexpected header line " + quoteText(line));
  }
  if (!haveFormat) fail(file, "header has no format line");
  header.bodyOffset = pos;
  return header;
}

// Thrown by the body readers; turned into a MeshError with context by the caller.
struct PlyTruncated {};
struct PlyBadNumber {
  std::string text;
};

class PlyBinaryReader {
 public:
  PlyBinaryReader(std::string_view body, bool bigEndian)
      : p_(reinterpret_cast<const unsigned char*>(body.data())),
        end_(p_ + body.size()),
        swap_(bigEndian != (std::endian::native == std::endian::big)) {}

  double read(ScalarType type) {
    const size_t n = sizeOf(type);
    if (remaining() < n) throw PlyTruncated{};
    unsigned char b[8];
    std::memcpy(b, p_, n);
    p_ += n;
    if (swap_) std::reverse(b, b + n);
    switch (type) {
      case ScalarType::Int8:
        return fromBytes<int8_t>(b);
      case ScalarType::UInt8:
        return fromBytes<uint8_t>(b);
      case ScalarType::Int16:
        return fromBytes<int16_t>(b);
      case ScalarType::UInt16:
        return fromBytes<uint16_t>(b);
      case ScalarType::Int32:
        return fromBytes<int32_t>(b);
      case ScalarType::UInt32:
        return fromBytes<uint32_t>(b);
      case ScalarType::Float32:
        return fromBytes<float>(b);
      case ScalarType::Float64:
        return fromBytes<double>(b);
    }
    return 0;
  }

  void skip(uint64_t count, ScalarType type) {
    const uint64_t n = sizeOf(type);
    if (count > remaining() / n) throw PlyTruncated{};
    p_ += count * n;
  }

  // Fast path for elements without lists: skips `count` fixed-size instances.
  bool trySkipFixed(const PlyElement& element) {
    uint64_t size = 0;
    for (const PlyProperty& p : element.properties) {
      if (p.isList) return false;
      size += sizeOf(p.type);
    }
    if (size != 0 && element.count > remaining() / size) throw PlyTruncated{};
    p_ += element.count * size;
    return true;
  }

 private:
  template <typename T>
  static double fromBytes(const unsigned char* b) {
    T value;
    std::memcpy(&value, b, sizeof(T));
    return static_cast<double>(value);
  }
  uint64_t remaining() const { return static_cast<uint64_t>(end_ - p_); }

  const unsigned char* p_;
  const unsigned char* end_;
  bool swap_;
};

class PlyAsciiReader {
 public:
  explicit PlyAsciiReader(std::string_view body)
      : p_(body.data()), end_(body.data() + body.size()) {}

  double read(ScalarType /*type*/) {
    const std::string_view token = nextToken();
    const char* first = token.data();
    const char* last = token.data() + token.size();
    if (first != last && *first == '+') ++first;
    double value = 0;
    const auto [end, ec] = std::from_chars(first, last, value);
    if (ec == std::errc::result_out_of_range && end == last) {
      // Overflow or underflow: strtod rounds these to +-HUGE_VAL or zero.
      const std::string copy(token);
      return std::strtod(copy.c_str(), nullptr);
    }
    if (ec != std::errc() || end != last) throw PlyBadNumber{std::string(token)};
    return value;
  }

  void skip(uint64_t count, ScalarType type) {
    for (uint64_t i = 0; i < count; ++i) read(type);
  }

  bool trySkipFixed(const PlyElement& /*element*/) { return false; }

 private:
  static bool isSpace(char c) {
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v';
  }
  std::string_view nextToken() {
    while (p_ != end_ && isSpace(*p_)) ++p_;
    if (p_ == end_) throw PlyTruncated{};
    const char* start = p_;
    while (p_ != end_ && !isSpace(*p_)) ++p_;
    return {start, static_cast<size_t>(p_ - start)};
  }

  const char* p_;
  const char* end_;
};

// Before anything is allocated: the smallest possible encoding of all the elements the
// header declares must fit in the data that follows it.
void checkPlyCountsFit(const fs::path& file, const PlyHeader& header, uint64_t bodySize) {
  const bool ascii = header.format == PlyFormat::Ascii;
  // In ascii every value takes a character and a separator, except possibly the last.
  uint64_t budget = ascii ? bodySize + 1 : bodySize;
  for (const PlyElement& element : header.elements) {
    uint64_t perEntry = 0;
    for (const PlyProperty& p : element.properties) {
      perEntry += ascii ? 2 : sizeOf(p.isList ? p.countType : p.type);
    }
    if (perEntry == 0) continue;
    if (element.count > budget / perEntry) {
      fail(file, "truncated data: element '" + element.name + "' claims " +
                     std::to_string(element.count) + " entries, more than the remaining " +
                     std::to_string(bodySize) + " bytes can hold");
    }
    budget -= element.count * perEntry;
  }
}

// What a vertex property means to us.
enum VertexRole : int { kX, kY, kZ, kNx, kNy, kNz, kU, kV, kRoleCount, kIgnored = -1 };

int vertexRole(std::string_view name) {
  if (name == "x") return kX;
  if (name == "y") return kY;
  if (name == "z") return kZ;
  if (name == "nx") return kNx;
  if (name == "ny") return kNy;
  if (name == "nz") return kNz;
  if (name == "u" || name == "s" || name == "texture_u" || name == "texture_s") return kU;
  if (name == "v" || name == "t" || name == "texture_v" || name == "texture_t") return kV;
  return kIgnored;
}

struct PlyLayout {
  size_t vertexElement = 0;
  size_t faceElement = 0;
  std::vector<int> vertexRoles;  // per vertex property
  bool hasNormals = false;
  bool hasUvs = false;
  size_t indexProperty = 0;  // within the face element
};

PlyLayout planPly(const fs::path& file, const PlyHeader& header) {
  PlyLayout layout;
  std::optional<size_t> vertex, face;
  for (size_t i = 0; i < header.elements.size(); ++i) {
    const std::string& name = header.elements[i].name;
    std::optional<size_t>* slot = name == "vertex" ? &vertex : name == "face" ? &face : nullptr;
    if (!slot) continue;
    if (*slot) fail(file, "more than one '" + name + "' element");
    *slot = i;
  }
  if (!vertex) fail(file, "no 'vertex' element");
  if (!face) fail(file, "no faces ('face' element missing)");
  layout.vertexElement = *vertex;
  layout.faceElement = *face;

  const PlyElement& v = header.elements[*vertex];
  if (v.count > std::numeric_limits<uint32_t>::max()) {
    fail(file, "too many vertices (" + std::to_string(v.count) + ")");
  }
  std::array<bool, kRoleCount> present{};
  for (const PlyProperty& p : v.properties) {
    const int role = p.isList ? kIgnored : vertexRole(p.name);
    layout.vertexRoles.push_back(role);
    if (role != kIgnored) present[static_cast<size_t>(role)] = true;
  }
  for (const auto& [role, name] : {std::pair{kX, "x"}, std::pair{kY, "y"}, std::pair{kZ, "z"}}) {
    if (!present[static_cast<size_t>(role)]) {
      fail(file, std::string("vertex element has no '") + name + "' property");
    }
  }
  layout.hasNormals = present[kNx] && present[kNy] && present[kNz];
  layout.hasUvs = present[kU] && present[kV];

  const PlyElement& f = header.elements[*face];
  std::optional<size_t> indices, index;
  for (size_t i = 0; i < f.properties.size(); ++i) {
    const PlyProperty& p = f.properties[i];
    if (!p.isList) continue;
    if (p.name == "vertex_indices" && !indices) indices = i;
    if (p.name == "vertex_index" && !index) index = i;
  }
  if (!indices && !index) fail(file, "face element has no 'vertex_indices' list property");
  layout.indexProperty = indices ? *indices : *index;
  return layout;
}

// Reads a list length from the data, which must be a non-negative integer.
template <typename Reader>
uint64_t readListCount(Reader& reader, const PlyProperty& property, const PlyElement& element,
                       uint64_t instance, const fs::path& file) {
  const double count = reader.read(property.countType);
  if (!(count >= 0) || count != std::floor(count) || count > 4294967295.0) {
    fail(file, element.name + " " + std::to_string(instance) +
                   ": invalid list length for property " + quoteText(property.name));
  }
  return static_cast<uint64_t>(count);
}

// One vertex's values by role (0 for a role it lacks); list properties are skipped.
template <typename Reader>
std::array<double, kRoleCount> readVertexRoles(const fs::path& file, const PlyElement& element,
                                               const PlyLayout& layout, Reader& reader,
                                               uint64_t instance) {
  std::array<double, kRoleCount> values{};
  for (size_t p = 0; p < element.properties.size(); ++p) {
    const PlyProperty& property = element.properties[p];
    if (property.isList) {
      reader.skip(readListCount(reader, property, element, instance, file), property.type);
      continue;
    }
    const double value = reader.read(property.type);
    if (layout.vertexRoles[p] != kIgnored) {
      values[static_cast<size_t>(layout.vertexRoles[p])] = value;
    }
  }
  return values;
}

// Stores vertex `instance` in the mesh: its position, and its normal and uv where the
// layout has them, each of which must be finite.
void storeVertex(const fs::path& file, const PlyLayout& layout,
                 const std::array<double, kRoleCount>& values, uint64_t instance,
                 TriangleMesh& mesh) {
  const Vec3f position{static_cast<float>(values[kX]), static_cast<float>(values[kY]),
                       static_cast<float>(values[kZ])};
  if (!isFinite(position)) {
    fail(file, "vertex " + std::to_string(instance) + " has a non-finite position");
  }
  mesh.positions[instance] = position;
  if (layout.hasNormals) {
    const Vec3f n{static_cast<float>(values[kNx]), static_cast<float>(values[kNy]),
                  static_cast<float>(values[kNz])};
    if (!isFinite(n)) {
      fail(file, "vertex " + std::to_string(instance) + " has a non-finite normal");
    }
    mesh.normals[instance] = n;
  }
  if (layout.hasUvs) {
    const Vec2f uv{static_cast<float>(values[kU]), static_cast<float>(values[kV])};
    if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) {
      fail(file, "vertex " + std::to_string(instance) + " has a non-finite uv");
    }
    mesh.uvs[instance] = uv;
  }
}

// The vertex element. Like the element readers below, it keeps the entry being read in
// `instance`, which the caller's messages name.
template <typename Reader>
void readVertices(const fs::path& file, const PlyElement& element, const PlyLayout& layout,
                  Reader& reader, uint64_t& instance, TriangleMesh& mesh) {
  mesh.positions.resize(element.count);
  if (layout.hasNormals) mesh.normals.resize(element.count);
  if (layout.hasUvs) mesh.uvs.resize(element.count);
  for (; instance < element.count; ++instance) {
    storeVertex(file, layout, readVertexRoles(file, element, layout, reader, instance), instance,
                mesh);
  }
}

// The `count` vertex indices of face `instance`, each an integer naming one of the
// `vertexCount` vertices.
template <typename Reader>
void readPolygon(const fs::path& file, const PlyProperty& property, uint64_t count,
                 uint32_t vertexCount, uint64_t instance, Reader& reader,
                 std::vector<uint32_t>& polygon) {
  polygon.clear();
  for (uint64_t k = 0; k < count; ++k) {
    const double index = reader.read(property.type);
    if (index != std::floor(index)) {
      fail(file, "face " + std::to_string(instance) + " has a non-integer vertex index");
    }
    if (!(index >= 0 && index < static_cast<double>(vertexCount))) {
      const std::string shown = std::abs(index) < 1e18
                                    ? std::to_string(static_cast<long long>(index))
                                    : std::string("(out of any range)");
      fail(file, "face " + std::to_string(instance) + " refers to vertex " + shown + " of " +
                     std::to_string(vertexCount));
    }
    polygon.push_back(static_cast<uint32_t>(index));
  }
}

// Fan triangulation; polygons with fewer than three corners add nothing.
void addFan(const std::vector<uint32_t>& polygon, std::vector<uint32_t>& indices) {
  for (size_t k = 1; k + 1 < polygon.size(); ++k) {
    indices.push_back(polygon[0]);
    indices.push_back(polygon[k]);
    indices.push_back(polygon[k + 1]);
  }
}

// The face element: its index list triangulated, every other property read past.
template <typename Reader>
void readFaces(const fs::path& file, const PlyElement& element, const PlyLayout& layout,
               uint32_t vertexCount, Reader& reader, uint64_t& instance, TriangleMesh& mesh) {
  std::vector<uint32_t> polygon;
  for (; instance < element.count; ++instance) {
    for (size_t p = 0; p < element.properties.size(); ++p) {
      const PlyProperty& property = element.properties[p];
      if (!property.isList) {
        reader.read(property.type);
        continue;
      }
      const uint64_t count = readListCount(reader, property, element, instance, file);
      if (p != layout.indexProperty) {
        reader.skip(count, property.type);
        continue;
      }
      readPolygon(file, property, count, vertexCount, instance, reader, polygon);
      addFan(polygon, mesh.indices);
    }
  }
}

// An element the mesh does not use, read past.
template <typename Reader>
void skipElement(const fs::path& file, const PlyElement& element, Reader& reader,
                 uint64_t& instance) {
  if (reader.trySkipFixed(element)) return;
  for (; instance < element.count; ++instance) {
    for (const PlyProperty& property : element.properties) {
      if (property.isList) {
        reader.skip(readListCount(reader, property, element, instance, file), property.type);
      } else {
        reader.read(property.type);
      }
    }
  }
}

template <typename Reader>
void readPlyBody(const fs::path& file, const PlyHeader& header, const PlyLayout& layout,
                 Reader& reader, TriangleMesh& mesh) {
  const auto vertexCount = static_cast<uint32_t>(header.elements[layout.vertexElement].count);

  for (size_t e = 0; e < header.elements.size(); ++e) {
    const PlyElement& element = header.elements[e];
    if (element.properties.empty()) continue;  // nothing stored, whatever the count
    // checkPlyCountsFit has bounded element.count by the file size already.
    uint64_t instance = 0;
    try {
      if (e == layout.vertexElement) {
        readVertices(file, element, layout, reader, instance, mesh);
      } else if (e == layout.faceElement) {
        readFaces(file, element, layout, vertexCount, reader, instance, mesh);
      } else {
        skipElement(file, element, reader, instance);
      }
    } catch (const PlyTruncated&) {
      fail(file, "truncated data: file ends inside element '" + element.name + "' (entry " +
                     std::to_string(instance) + " of " + std::to_string(element.count) + ")");
    } catch (const PlyBadNumber& bad) {
      fail(file, "bad number " + quoteText(bad.text) + " in element '" + element.name +
                     "' (entry " + std::to_string(instance) + ")");
    }
  }
}

}  // namespace

TriangleMesh loadPly(const fs::path& file) { return parsePly(readWholeFile(file), file); }

TriangleMesh parsePly(std::string_view data, const fs::path& file) {
  const PlyHeader header = parsePlyHeader(file, data);
  const std::string_view body = data.substr(header.bodyOffset);
  checkPlyCountsFit(file, header, body.size());
  const PlyLayout layout = planPly(file, header);

  TriangleMesh mesh;
  if (header.format == PlyFormat::Ascii) {
    PlyAsciiReader reader(body);
    readPlyBody(file, header, layout, reader, mesh);
  } else {
    PlyBinaryReader reader(body, header.format == PlyFormat::BinaryBigEndian);
    readPlyBody(file, header, layout, reader, mesh);
  }
  if (mesh.indices.empty()) fail(file, "no faces (no polygon has three or more vertices)");
  return mesh;
}

}  // namespace pathfarm
