#pragma once
// Writes small glTF 2.0 files for the importer's tests, independently of the library
// that reads them: the JSON is assembled here and the binary data goes to a .bin file
// beside it, so a test states exactly which bytes the file holds.
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace pathfarm::gltftest {

class GltfBuilder {
 public:
  GltfBuilder() {
    doc_ = {{"asset", {{"version", "2.0"}}}, {"buffers", nlohmann::json::array()},
            {"bufferViews", nlohmann::json::array()}, {"accessors", nlohmann::json::array()}};
  }

  nlohmann::json& doc() { return doc_; }

  // An accessor of float components ("SCALAR", "VEC2", "VEC3", "VEC4", "MAT4"), with
  // min and max for POSITION when `withBounds`.
  int floats(const std::vector<float>& values, const std::string& type, bool withBounds = false) {
    const int view = appendView(values.data(), values.size() * sizeof(float));
    const int width = type == "SCALAR" ? 1 : type == "MAT4" ? 16 : type[3] - '0';
    nlohmann::json accessor = {{"bufferView", view}, {"componentType", 5126},
                               {"count", values.size() / static_cast<size_t>(width)}, {"type", type}};
    if (withBounds) {
      std::vector<float> lo(static_cast<size_t>(width), 1e30f), hi(static_cast<size_t>(width), -1e30f);
      for (size_t i = 0; i < values.size(); ++i) {
        lo[i % static_cast<size_t>(width)] = std::min(lo[i % static_cast<size_t>(width)], values[i]);
        hi[i % static_cast<size_t>(width)] = std::max(hi[i % static_cast<size_t>(width)], values[i]);
      }
      accessor["min"] = lo;
      accessor["max"] = hi;
    }
    doc_["accessors"].push_back(accessor);
    return static_cast<int>(doc_["accessors"].size()) - 1;
  }

  // An index accessor of unsigned shorts (componentType 5123) or ints (5125).
  template <class T>
  int indices(const std::vector<T>& values) {
    static_assert(sizeof(T) == 2 || sizeof(T) == 4);
    const int view = appendView(values.data(), values.size() * sizeof(T));
    doc_["accessors"].push_back({{"bufferView", view}, {"componentType", sizeof(T) == 2 ? 5123 : 5125},
                                 {"count", values.size()}, {"type", "SCALAR"}});
    return static_cast<int>(doc_["accessors"].size()) - 1;
  }

  // An accessor of unsigned shorts (componentType 5123) of `type`, e.g. JOINTS_0's "VEC4".
  int unsignedShorts(const std::vector<uint16_t>& values, const std::string& type) {
    const int view = appendView(values.data(), values.size() * sizeof(uint16_t));
    const size_t width = type == "SCALAR" ? 1 : static_cast<size_t>(type[3] - '0');
    doc_["accessors"].push_back(
        {{"bufferView", view}, {"componentType", 5123}, {"count", values.size() / width}, {"type", type}});
    return static_cast<int>(doc_["accessors"].size()) - 1;
  }

  // A mesh of one primitive, returning its index.
  int mesh(const nlohmann::json& attributes, int indices = -1, int material = -1) {
    nlohmann::json primitive = {{"attributes", attributes}};
    if (indices >= 0) primitive["indices"] = indices;
    if (material >= 0) primitive["material"] = material;
    doc_["meshes"].push_back({{"primitives", {primitive}}});
    return static_cast<int>(doc_["meshes"].size()) - 1;
  }

  // The unit square [-1, 1]^2 in the xy plane facing +z, with uvs (glTF convention,
  // v down) and 16-bit indices.
  int square(int material = -1) {
    const int position = floats({-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0}, "VEC3", true);
    const int normal = floats({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3");
    const int uv = floats({0, 1, 1, 1, 1, 0, 0, 0}, "VEC2");
    return mesh({{"POSITION", position}, {"NORMAL", normal}, {"TEXCOORD_0", uv}},
                indices(std::vector<uint16_t>{0, 1, 2, 0, 2, 3}), material);
  }

  int node(const nlohmann::json& node) {
    doc_["nodes"].push_back(node);
    return static_cast<int>(doc_["nodes"].size()) - 1;
  }

  // A perspective camera node at `position` looking along -z.
  int camera(const std::vector<float>& position, double yfovRadians = 0.8, double aspect = 1.0) {
    doc_["cameras"].push_back(
        {{"type", "perspective"}, {"perspective", {{"yfov", yfovRadians}, {"znear", 0.01}, {"aspectRatio", aspect}}}});
    return node({{"camera", static_cast<int>(doc_["cameras"].size()) - 1}, {"translation", position}});
  }

  // The default scene: these root nodes.
  void scene(const std::vector<int>& roots) {
    doc_["scenes"] = {{{"nodes", roots}}};
    doc_["scene"] = 0;
  }

  // Writes folder/name.gltf and folder/name.bin; returns the .gltf path.
  std::filesystem::path write(const std::filesystem::path& folder, const std::string& name) {
    std::filesystem::create_directories(folder);
    doc_["buffers"] = {{{"uri", name + ".bin"}, {"byteLength", data_.size()}}};
    std::ofstream(folder / (name + ".bin"), std::ios::binary)
        .write(reinterpret_cast<const char*>(data_.data()), static_cast<std::streamsize>(data_.size()));
    std::ofstream(folder / (name + ".gltf")) << doc_.dump(1);
    return folder / (name + ".gltf");
  }

 private:
  int appendView(const void* bytes, size_t size) {
    while (data_.size() % 4) data_.push_back(0);
    const size_t offset = data_.size();
    data_.resize(offset + size);
    std::memcpy(data_.data() + offset, bytes, size);
    doc_["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", size}});
    return static_cast<int>(doc_["bufferViews"].size()) - 1;
  }

  nlohmann::json doc_;
  std::vector<unsigned char> data_;
};

}  // namespace pathfarm::gltftest
