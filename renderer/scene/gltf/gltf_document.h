#pragma once
// A glTF 2.0 file (.gltf with its buffers and images, or .glb) parsed by tinygltf, with
// bounds-checked access to its accessors. Every problem throws SceneError naming the
// file and the JSON pointer of the offending entry ("scene.glb: /meshes/0/primitives/1:
// ...").
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <tiny_gltf.h>

#include "renderer/scene/json_node.h"

namespace pathfarm {

class GltfDocument {
 public:
  // Parses the file and its external buffers and images; refuses an entry of
  // `extensionsRequired` that pathfarm does not implement.
  explicit GltfDocument(const std::filesystem::path& file);
  // The same from the bytes of a .gltf or .glb (told apart by the GLB magic), named
  // `label` in messages; relative URIs resolve against `baseFolder`.
  GltfDocument(const unsigned char* bytes, size_t size, const std::filesystem::path& label,
               const std::filesystem::path& baseFolder);

  const tinygltf::Model& model() const { return model_; }
  const std::filesystem::path& file() const { return file_; }

  [[noreturn]] void fail(const std::string& pointer, const std::string& message) const;
  // Warnings name the file and pointer too; they go to the log.
  void warn(const std::string& pointer, const std::string& message) const;

  // Accessor `index` as `components` floats per element (VEC3: 3, ...), integer
  // components normalized as the accessor says, sparse substitutions applied. Refuses
  // an accessor of another type, out of its buffer, or with a non-finite value.
  std::vector<float> readFloats(int index, int components, const std::string& pointer) const;
  // An index accessor (SCALAR of unsigned byte, short or int), each value below
  // `vertexCount`.
  std::vector<uint32_t> readIndices(int index, size_t vertexCount, const std::string& pointer) const;
  // The number of elements accessor `index` holds (checked against a sane limit).
  size_t count(int index, const std::string& pointer) const;

 private:
  const tinygltf::Accessor& accessor(int index, const std::string& pointer) const;
  // Turns tinygltf's verdict into a SceneError, then checks extensionsRequired.
  void accept(bool loaded, std::string error, const std::string& warning);
  const tinygltf::BufferView& bufferView(int view, const std::string& pointer) const;
  // The raw bytes of `count` elements of `elementSize` bytes spaced `stride` apart from
  // `offset` in buffer view `view`, checked to lie inside the view and its buffer.
  const unsigned char* viewBytes(int view, size_t offset, size_t count, size_t elementSize, size_t stride,
                                 const std::string& pointer) const;
  // Components of one accessor element as doubles (`normalized` integers mapped to [0,1]
  // or [-1,1]).
  std::vector<double> decode(const tinygltf::Accessor& a, const std::string& pointer) const;

  std::filesystem::path file_;
  tinygltf::Model model_;
};

// "/meshes/3" style JSON pointers.
std::string gltfPointer(const char* collection, int index);

// A number member of `object` (or `object` itself when key is null), else `fallback`.
double gltfNumberOr(const tinygltf::Value& object, const char* key, double fallback);
// A number from the file, checked to be finite and within [min, max].
float gltfFactor(const GltfDocument& document, const std::string& pointer, double value, double min, double max);
// The extension object `name` of an entry, or null.
const tinygltf::Value* gltfExtension(const tinygltf::ExtensionMap& extensions, const char* name);

}  // namespace pathfarm
