#include "renderer/scene/gltf/gltf_document.h"

#include <spdlog/spdlog.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <set>

#include "renderer/scene/scene_inputs.h"

namespace pathfarm {
namespace {

// Elements per accessor beyond which a file is taken as hostile rather than large.
constexpr size_t kMaxElements = size_t{1} << 27;

// The extensions whose meaning the importer implements; a file that requires another
// one cannot be rendered as its author intended.
const std::set<std::string>& implementedExtensions() {
  static const std::set<std::string> names{"KHR_materials_emissive_strength", "KHR_materials_ior",
                                           "KHR_materials_transmission", "KHR_materials_volume",
                                           "KHR_lights_punctual", "KHR_texture_transform"};
  return names;
}

size_t componentSize(int componentType) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;
  }
}

template <class T>
T load(const unsigned char* p) {
  T value;
  std::memcpy(&value, p, sizeof(T));
  return value;
}

// One component as a double; integers normalized to [0, 1] or [-1, 1] when asked.
double component(const unsigned char* p, int componentType, bool normalized) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      const double v = load<int8_t>(p);
      return normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return load<uint8_t>(p) / (normalized ? 255.0 : 1.0);
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      const double v = load<int16_t>(p);
      return normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return load<uint16_t>(p) / (normalized ? 65535.0 : 1.0);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return load<uint32_t>(p) / (normalized ? 4294967295.0 : 1.0);
    default: return load<float>(p);
  }
}

// tinygltf's file reader, noting each file (the glTF, its buffers and images) as a scene input.
bool readNotedFile(std::vector<unsigned char>* out, std::string* error, const std::string& path, void* user) {
  if (!tinygltf::ReadWholeFile(out, error, path, user)) return false;
  noteSceneInput(path);
  return true;
}

tinygltf::TinyGLTF notingLoader() {
  tinygltf::TinyGLTF loader;
  loader.SetFsCallbacks({&tinygltf::FileExists, &tinygltf::ExpandFilePath, &readNotedFile, &tinygltf::WriteWholeFile,
                         nullptr});
  return loader;
}

}  // namespace

std::string gltfPointer(const char* collection, int index) {
  return std::string("/") + collection + "/" + std::to_string(index);
}

GltfDocument::GltfDocument(const std::filesystem::path& file) : file_(file) {
  if (!std::filesystem::is_regular_file(file)) throw SceneError(file.string() + ": cannot open the glTF file");
  tinygltf::TinyGLTF loader = notingLoader();
  std::string error, warning;
  const bool loaded = file.extension() == ".glb"
                          ? loader.LoadBinaryFromFile(&model_, &error, &warning, file.string())
                          : loader.LoadASCIIFromFile(&model_, &error, &warning, file.string());
  accept(loaded, error, warning);
}

GltfDocument::GltfDocument(const unsigned char* bytes, size_t size, const std::filesystem::path& label,
                           const std::filesystem::path& baseFolder)
    : file_(label) {
  if (size > std::numeric_limits<unsigned int>::max()) throw SceneError(label.string() + ": file too large");
  tinygltf::TinyGLTF loader = notingLoader();
  std::string error, warning;
  const auto length = static_cast<unsigned int>(size);
  const bool loaded =
      size >= 4 && std::memcmp(bytes, "glTF", 4) == 0
          ? loader.LoadBinaryFromMemory(&model_, &error, &warning, bytes, length, baseFolder.string())
          : loader.LoadASCIIFromString(&model_, &error, &warning, reinterpret_cast<const char*>(bytes), length,
                                       baseFolder.string());
  accept(loaded, error, warning);
}

void GltfDocument::accept(bool loaded, std::string error, const std::string& warning) {
  if (!loaded || !error.empty()) {
    while (!error.empty() && (error.back() == '\n' || error.back() == ' ')) error.pop_back();
    throw SceneError(file_.string() + ": not a loadable glTF 2.0 file: " + (error.empty() ? "unknown error" : error));
  }
  if (!warning.empty()) spdlog::warn("{}: {}", file_.string(), warning);
  for (size_t i = 0; i < model_.extensionsRequired.size(); ++i) {
    const std::string& name = model_.extensionsRequired[i];
    if (!implementedExtensions().count(name))
      fail("/extensionsRequired/" + std::to_string(i), "the file requires extension " + name +
                                                           ", which pathfarm does not implement");
  }
}

void GltfDocument::fail(const std::string& pointer, const std::string& message) const {
  throw SceneError(file_.string() + ": " + (pointer.empty() ? "" : pointer + ": ") + message);
}

void GltfDocument::warn(const std::string& pointer, const std::string& message) const {
  spdlog::warn("{}: {}{}", file_.string(), pointer.empty() ? "" : pointer + ": ", message);
}

const tinygltf::Accessor& GltfDocument::accessor(int index, const std::string& pointer) const {
  if (index < 0 || static_cast<size_t>(index) >= model_.accessors.size())
    fail(pointer, "accessor " + std::to_string(index) + " does not exist (the file has " +
                      std::to_string(model_.accessors.size()) + ")");
  const tinygltf::Accessor& a = model_.accessors[static_cast<size_t>(index)];
  if (a.count > kMaxElements)
    fail(gltfPointer("accessors", index), "count " + std::to_string(a.count) + " exceeds the limit of " +
                                              std::to_string(kMaxElements));
  if (componentSize(a.componentType) == 0)
    fail(gltfPointer("accessors", index), "unknown componentType " + std::to_string(a.componentType));
  return a;
}

size_t GltfDocument::count(int index, const std::string& pointer) const { return accessor(index, pointer).count; }

const tinygltf::BufferView& GltfDocument::bufferView(int view, const std::string& pointer) const {
  if (view < 0 || static_cast<size_t>(view) >= model_.bufferViews.size())
    fail(pointer, "buffer view " + std::to_string(view) + " does not exist");
  return model_.bufferViews[static_cast<size_t>(view)];
}

const unsigned char* GltfDocument::viewBytes(int view, size_t offset, size_t count, size_t elementSize,
                                             size_t stride, const std::string& pointer) const {
  const tinygltf::BufferView& v = bufferView(view, pointer);
  if (v.buffer < 0 || static_cast<size_t>(v.buffer) >= model_.buffers.size())
    fail(gltfPointer("bufferViews", view), "buffer " + std::to_string(v.buffer) + " does not exist");
  const std::vector<unsigned char>& data = model_.buffers[static_cast<size_t>(v.buffer)].data;
  if (v.byteOffset > data.size() || v.byteLength > data.size() - v.byteOffset)
    fail(gltfPointer("bufferViews", view), "bytes [" + std::to_string(v.byteOffset) + ", " +
                                               std::to_string(v.byteOffset + v.byteLength) + ") lie outside buffer " +
                                               std::to_string(v.buffer) + " of " + std::to_string(data.size()) +
                                               " bytes");
  if (count == 0) return data.data();
  // (count - 1) * stride + elementSize + offset <= byteLength, without overflow.
  const size_t last = count - 1;
  if (offset > v.byteLength || elementSize > v.byteLength - offset ||
      (stride > 0 && last > (v.byteLength - offset - elementSize) / stride))
    fail(pointer, std::to_string(count) + " elements of " + std::to_string(elementSize) + " bytes (stride " +
                      std::to_string(stride) + ") from offset " + std::to_string(offset) +
                      " overrun buffer view " + std::to_string(view) + " of " + std::to_string(v.byteLength) +
                      " bytes");
  return data.data() + v.byteOffset + offset;
}

std::vector<double> GltfDocument::decode(const tinygltf::Accessor& a, const std::string& pointer) const {
  const int components = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(a.type));
  if (components <= 0) fail(pointer, "accessor of unknown type " + std::to_string(a.type));
  const size_t width = static_cast<size_t>(components);
  const size_t size = componentSize(a.componentType);
  const size_t elementSize = width * size;
  std::vector<double> values(a.count * width, 0.0);
  if (a.bufferView >= 0) {
    const tinygltf::BufferView& view = bufferView(a.bufferView, pointer);
    size_t stride = elementSize;
    if (view.byteStride != 0) {
      if (view.byteStride < elementSize)
        fail(pointer, "byteStride " + std::to_string(view.byteStride) + " is smaller than an element (" +
                          std::to_string(elementSize) + " bytes)");
      stride = view.byteStride;
    }
    const unsigned char* bytes = viewBytes(a.bufferView, a.byteOffset, a.count, elementSize, stride, pointer);
    for (size_t i = 0; i < a.count; ++i)
      for (size_t c = 0; c < width; ++c)
        values[i * width + c] = component(bytes + i * stride + c * size, a.componentType, a.normalized);
  }
  if (a.sparse.isSparse) {
    const auto& sparse = a.sparse;
    if (sparse.count < 0 || static_cast<size_t>(sparse.count) > a.count)
      fail(pointer, "sparse count " + std::to_string(sparse.count) + " exceeds the accessor's " +
                        std::to_string(a.count) + " elements");
    const size_t n = static_cast<size_t>(sparse.count);
    const size_t indexSize = componentSize(sparse.indices.componentType);
    if (indexSize == 0 || sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT ||
        sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_BYTE ||
        sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_SHORT)
      fail(pointer, "sparse indices must be unsigned integers");
    const unsigned char* indices = viewBytes(sparse.indices.bufferView, static_cast<size_t>(sparse.indices.byteOffset),
                                             n, indexSize, indexSize, pointer + " (sparse indices)");
    const unsigned char* substitutes = viewBytes(sparse.values.bufferView, static_cast<size_t>(sparse.values.byteOffset),
                                                 n, elementSize, elementSize, pointer + " (sparse values)");
    for (size_t i = 0; i < n; ++i) {
      const auto target = static_cast<size_t>(component(indices + i * indexSize, sparse.indices.componentType, false));
      if (target >= a.count)
        fail(pointer, "sparse index " + std::to_string(target) + " is past the accessor's " +
                          std::to_string(a.count) + " elements");
      for (size_t c = 0; c < width; ++c)
        values[target * width + c] = component(substitutes + i * elementSize + c * size, a.componentType, a.normalized);
    }
  }
  return values;
}

std::vector<float> GltfDocument::readFloats(int index, int components, const std::string& pointer) const {
  const tinygltf::Accessor& a = accessor(index, pointer);
  const int actual = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(a.type));
  if (actual != components)
    fail(pointer, "accessor " + std::to_string(index) + " has " + std::to_string(actual) +
                      " components per element where " + std::to_string(components) + " are expected");
  const std::vector<double> values = decode(a, pointer);
  std::vector<float> result(values.size());
  for (size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i]) || std::abs(values[i]) > 3.0e38)
      fail(pointer, "accessor " + std::to_string(index) + " holds a non-finite value at element " +
                        std::to_string(i / static_cast<size_t>(components)));
    result[i] = static_cast<float>(values[i]);
  }
  return result;
}

std::vector<uint32_t> GltfDocument::readIndices(int index, size_t vertexCount, const std::string& pointer) const {
  const tinygltf::Accessor& a = accessor(index, pointer);
  if (a.type != TINYGLTF_TYPE_SCALAR || a.normalized ||
      (a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
       a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
       a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
    fail(pointer, "indices must be a SCALAR accessor of unsigned byte, short or int");
  const std::vector<double> values = decode(a, pointer);
  std::vector<uint32_t> result(values.size());
  for (size_t i = 0; i < values.size(); ++i) {
    if (values[i] >= static_cast<double>(vertexCount))
      fail(pointer, "index " + std::to_string(static_cast<uint64_t>(values[i])) + " at position " + std::to_string(i) +
                        " is past the " + std::to_string(vertexCount) + " vertices");
    result[i] = static_cast<uint32_t>(values[i]);
  }
  return result;
}

double gltfNumberOr(const tinygltf::Value& object, const char* key, double fallback) {
  if (key && (!object.IsObject() || !object.Has(key))) return fallback;
  const tinygltf::Value& v = key ? object.Get(key) : object;
  return v.IsNumber() ? v.GetNumberAsDouble() : fallback;
}

float gltfFactor(const GltfDocument& document, const std::string& pointer, double value, double min, double max) {
  if (!std::isfinite(value) || value < min || value > max)
    document.fail(pointer, "value " + std::to_string(value) + " is outside [" + std::to_string(min) + ", " +
                               std::to_string(max) + "]");
  return static_cast<float>(value);
}

const tinygltf::Value* gltfExtension(const tinygltf::ExtensionMap& extensions, const char* name) {
  const auto it = extensions.find(name);
  return it == extensions.end() ? nullptr : &it->second;
}

}  // namespace pathfarm
