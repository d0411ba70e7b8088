#include "renderer/scene/mesh_io.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

namespace pathfarm {
namespace {

namespace fs = std::filesystem;

// Each test writes its inputs into a fresh directory under the system temp dir.
class MeshIoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("pathfarm_mesh_io_" + std::to_string(::getpid()) + "_" +
                                        info->test_suite_name() + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  fs::path write(const std::string& name, const std::string& bytes) const {
    const fs::path path = dir_ / name;
    fs::remove(path);
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    EXPECT_TRUE(out.good()) << path;
    return path;
  }

  // Loading `path` fails with a MeshError whose message starts with the path and
  // mentions `expected`.
  static void expectMeshError(const fs::path& path, const std::string& expected) {
    try {
      loadMesh(path);
      ADD_FAILURE() << path << ": loaded, expected an error mentioning '" << expected << "'";
    } catch (const MeshError& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.rfind(path.string(), 0), 0u) << message;
      EXPECT_NE(message.find(expected), std::string::npos)
          << "message '" << message << "' lacks '" << expected << "'";
    }
  }

  fs::path dir_;
};

// ---------------------------------------------------------------------------------------
// PLY writing helpers. The same logical data is written in every format.

struct PlyVertex {
  float x, y;
  double z;
  uint8_t red;
  float nx, ny, nz, u, v;
};

const std::vector<PlyVertex> kPlyVertices = {
    {0.0f, 0.0f, 0.0, 10, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f},
    {1.0f, 0.0f, 0.0, 20, 0.0f, 0.6f, 0.8f, 1.0f, 0.0f},
    {1.0f, 1.0f, 0.0, 30, 0.0f, 0.0f, 1.0f, 1.0f, 1.0f},
    {0.0f, 1.0f, 0.0, 40, 0.6f, 0.0f, 0.8f, 0.0f, 1.0f},
    {2.0f, 0.5f, 0.25, 50, 1.0f, 0.0f, 0.0f, 0.75f, 0.125f},
};
const std::vector<std::vector<int32_t>> kPlyFaces = {{0, 1, 2, 3}, {1, 4, 2}};
const std::vector<uint32_t> kPlyTriangles = {0, 1, 2, 0, 2, 3, 1, 4, 2};

class PlyWriter {
 public:
  explicit PlyWriter(const std::string& format) : format_(format) {}

  template <typename T>
  void put(T value) {
    if (format_ == "ascii") {
      char buf[64];
      std::to_chars_result r;
      if constexpr (sizeof(T) == 1) {
        r = std::to_chars(buf, buf + sizeof buf, static_cast<int>(value));
      } else {
        r = std::to_chars(buf, buf + sizeof buf, value);  // shortest round-trip for floats
      }
      out_.append(buf, r.ptr);
      out_ += ' ';
      return;
    }
    unsigned char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    if (format_ == "binary_big_endian") std::reverse(bytes, bytes + sizeof(T));
    out_.append(reinterpret_cast<const char*>(bytes), sizeof(T));
  }
  void endLine() {
    if (format_ == "ascii") out_.back() = '\n';
  }
  std::string& text() { return out_; }

 private:
  std::string format_;
  std::string out_;
};

// A PLY with mixed scalar types, an ignored vertex property, an unknown element with a
// list property between vertices and faces, and an extra per-face property.
std::string makePly(const std::string& format) {
  std::string header = "ply\nformat " + format +
                       " 1.0\n"
                       "comment written by the pathfarm tests\n"
                       "obj_info nothing to see\n"
                       "element vertex " +
                       std::to_string(kPlyVertices.size()) +
                       "\n"
                       "property float x\nproperty float32 y\nproperty double z\n"
                       "property uchar red\n"
                       "property float nx\nproperty float ny\nproperty float nz\n"
                       "property float u\nproperty float v\n"
                       "element material 2\n"
                       "property list uchar float params\n"
                       "property int id\n"
                       "element face " +
                       std::to_string(kPlyFaces.size()) +
                       "\n"
                       "property list uchar int vertex_indices\n"
                       "property ushort flags\n"
                       "end_header\n";
  PlyWriter w(format);
  w.text() = header;
  for (const PlyVertex& v : kPlyVertices) {
    w.put(v.x), w.put(v.y), w.put(v.z), w.put(v.red);
    w.put(v.nx), w.put(v.ny), w.put(v.nz), w.put(v.u), w.put(v.v);
    w.endLine();
  }
  for (int m = 0; m < 2; ++m) {
    w.put(static_cast<uint8_t>(3));
    for (int k = 0; k < 3; ++k) w.put(static_cast<float>(m + k) * 0.5f);
    w.put(static_cast<int32_t>(m));
    w.endLine();
  }
  for (const auto& face : kPlyFaces) {
    w.put(static_cast<uint8_t>(face.size()));
    for (int32_t i : face) w.put(i);
    w.put(static_cast<uint16_t>(7));
    w.endLine();
  }
  return w.text();
}

void expectReferencePlyMesh(const TriangleMesh& m) {
  ASSERT_EQ(m.positions.size(), kPlyVertices.size());
  ASSERT_EQ(m.normals.size(), kPlyVertices.size());
  ASSERT_EQ(m.uvs.size(), kPlyVertices.size());
  for (size_t i = 0; i < kPlyVertices.size(); ++i) {
    const PlyVertex& v = kPlyVertices[i];
    EXPECT_EQ(m.positions[i], (Vec3f{v.x, v.y, static_cast<float>(v.z)})) << i;
    EXPECT_EQ(m.normals[i], (Vec3f{v.nx, v.ny, v.nz})) << i;
    EXPECT_EQ(m.uvs[i].x, v.u) << i;
    EXPECT_EQ(m.uvs[i].y, v.v) << i;
  }
  EXPECT_EQ(m.indices, kPlyTriangles);
}

void expectSameMesh(const TriangleMesh& a, const TriangleMesh& b) {
  ASSERT_EQ(a.positions.size(), b.positions.size());
  for (size_t i = 0; i < a.positions.size(); ++i) EXPECT_EQ(a.positions[i], b.positions[i]);
  ASSERT_EQ(a.normals.size(), b.normals.size());
  for (size_t i = 0; i < a.normals.size(); ++i) EXPECT_EQ(a.normals[i], b.normals[i]);
  ASSERT_EQ(a.uvs.size(), b.uvs.size());
  for (size_t i = 0; i < a.uvs.size(); ++i) {
    EXPECT_EQ(a.uvs[i].x, b.uvs[i].x);
    EXPECT_EQ(a.uvs[i].y, b.uvs[i].y);
  }
  EXPECT_EQ(a.indices, b.indices);
}

// Structural sanity of anything a loader returns.
void expectWellFormed(const TriangleMesh& m) {
  ASSERT_EQ(m.indices.size() % 3, 0u);
  ASSERT_FALSE(m.indices.empty());
  for (uint32_t i : m.indices) ASSERT_LT(i, m.positions.size());
  EXPECT_TRUE(m.normals.empty() || m.normals.size() == m.positions.size());
  EXPECT_TRUE(m.uvs.empty() || m.uvs.size() == m.positions.size());
  for (const Vec3f& p : m.positions) ASSERT_TRUE(isFinite(p));
}

// ---------------------------------------------------------------------------------------
// PLY

TEST_F(MeshIoTest, PlyAsciiAndBinaryGiveTheSameMesh) {
  const TriangleMesh ascii = loadPly(write("a.ply", makePly("ascii")));
  const TriangleMesh little = loadPly(write("le.ply", makePly("binary_little_endian")));
  const TriangleMesh big = loadPly(write("be.ply", makePly("binary_big_endian")));
  expectReferencePlyMesh(ascii);
  expectReferencePlyMesh(little);
  expectSameMesh(ascii, little);
  expectSameMesh(ascii, big);
}

TEST_F(MeshIoTest, PlyCrlfHeaderAndTypeAliases) {
  const std::string text =
      "ply\r\nformat ascii 1.0\r\n"
      "element vertex 4\r\n"
      "property int16 x\r\nproperty int8 y\r\nproperty uint8 z\r\n"
      "property float32 s\r\nproperty float64 t\r\n"
      "element face 1\r\n"
      "property list int uint16 vertex_index\r\n"
      "end_header\r\n"
      "0 0 0 0 0\r\n"
      "-2 0 1 1 0\r\n"
      "-2 3 1 1 1\r\n"
      "0 3 0 0 1\r\n"
      "4 0 1 2 3\r\n";
  const TriangleMesh m = loadMesh(write("aliases.PLY", text));
  ASSERT_EQ(m.positions.size(), 4u);
  EXPECT_EQ(m.positions[1], (Vec3f{-2, 0, 1}));
  EXPECT_EQ(m.positions[2], (Vec3f{-2, 3, 1}));
  EXPECT_TRUE(m.normals.empty());
  ASSERT_EQ(m.uvs.size(), 4u);
  EXPECT_EQ(m.uvs[2].x, 1.0f);
  EXPECT_EQ(m.uvs[2].y, 1.0f);
  EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
}

TEST_F(MeshIoTest, PlyWithoutNormalsOrUvsLeavesThemEmpty) {
  const std::string text =
      "ply\nformat ascii 1.0\nelement vertex 3\n"
      "property float x\nproperty float y\nproperty float z\nproperty float nx\n"
      "element face 1\nproperty list uchar uint vertex_indices\nend_header\n"
      "0 0 0 1\n1 0 0 1\n0 1 0 1\n3 0 1 2\n";
  const TriangleMesh m = loadPly(write("plain.ply", text));
  EXPECT_EQ(m.positions.size(), 3u);
  EXPECT_TRUE(m.normals.empty());  // nx alone is not a normal
  EXPECT_TRUE(m.uvs.empty());
  EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 1, 2}));
}

// The header of a small valid binary PLY whose body the tests below corrupt.
const char* kTriangleHeader =
    "ply\nformat binary_little_endian 1.0\nelement vertex 3\n"
    "property float x\nproperty float y\nproperty float z\n"
    "element face 1\nproperty list uchar int vertex_indices\nend_header\n";

std::string triangleBody(float badCoordinate = 0.0f, int32_t lastIndex = 2) {
  PlyWriter w("binary_little_endian");
  const float coords[9] = {badCoordinate, 0, 0, 1, 0, 0, 0, 1, 0};
  for (float c : coords) w.put(c);
  w.put(static_cast<uint8_t>(3));
  w.put(static_cast<int32_t>(0)), w.put(static_cast<int32_t>(1)), w.put(lastIndex);
  return w.text();
}

TEST_F(MeshIoTest, PlyMinimalBinaryLoads) {
  const TriangleMesh m = loadPly(write("tri.ply", kTriangleHeader + triangleBody()));
  EXPECT_EQ(m.positions.size(), 3u);
  EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 1, 2}));
}

TEST_F(MeshIoTest, MissingFileIsAnError) {
  expectMeshError(dir_ / "does_not_exist.ply", "no such file");
  expectMeshError(dir_ / "does_not_exist.obj", "no such file");
  const fs::path sub = dir_ / "folder.ply";
  fs::create_directory(sub);
  expectMeshError(sub, "directory");
}

TEST_F(MeshIoTest, UnknownExtensionIsAnError) {
  expectMeshError(write("mesh.stl", "solid x\n"), ".stl");
  expectMeshError(write("mesh", "ply\n"), "extension");
}

TEST_F(MeshIoTest, PlyBadMagic) {
  expectMeshError(write("magic.ply", std::string("plx\nformat ascii 1.0\nend_header\n")), "magic");
  expectMeshError(write("empty.ply", ""), "magic");
  expectMeshError(write("obj_in_disguise.ply", "v 0 0 0\n"), "magic");
}

TEST_F(MeshIoTest, PlyUnsupportedFormatOrVersion) {
  expectMeshError(write("middle.ply", "ply\nformat binary_middle_endian 1.0\nend_header\n"),
                  "unsupported PLY format");
  expectMeshError(write("version.ply", "ply\nformat ascii 2.0\nend_header\n"),
                  "unsupported PLY version");
  expectMeshError(write("noformat.ply", "ply\nelement vertex 0\nend_header\n"), "format");
  expectMeshError(
      write("type.ply",
            "ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nend_header\n"),
      "unknown property type");
  expectMeshError(write("noend.ply", "ply\nformat ascii 1.0\nelement vertex 1\n"), "end_header");
}

TEST_F(MeshIoTest, PlyTruncatedData) {
  const std::string full = kTriangleHeader + triangleBody();
  // Cut inside the vertices and inside the face list.
  expectMeshError(write("cut_vertex.ply", full.substr(0, full.size() - 20)), "truncated");
  expectMeshError(write("cut_face.ply", full.substr(0, full.size() - 2)), "truncated");
  const std::string ascii =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float "
      "z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 "
      "0 1";
  expectMeshError(write("cut_ascii.ply", ascii), "truncated");
}

TEST_F(MeshIoTest, PlyHugeCountsFailCleanlyAndFast) {
  const auto start = std::chrono::steady_clock::now();
  const std::string binaryHeader =
      "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\n"
      "property float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  expectMeshError(write("huge_binary.ply", binaryHeader + triangleBody()), "truncated");
  std::string asciiHeader = binaryHeader;
  asciiHeader.replace(asciiHeader.find("binary_little_endian"), 20, "ascii");
  std::string billion = binaryHeader;
  billion.replace(billion.find("1000000000000"), 13, "1000000000");
  expectMeshError(write("billion_binary.ply", billion + triangleBody()),
                  "claims 1000000000 entries");
  expectMeshError(write("huge_ascii.ply", asciiHeader + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
                  "truncated");
  // A count beyond 64 bits, and a list that claims four billion entries.
  expectMeshError(write("overflow.ply",
                        "ply\nformat ascii 1.0\nelement vertex 99999999999999999999999\n"
                        "property float x\nend_header\n"),
                  "bad element count");
  std::string hugeList = kTriangleHeader;
  hugeList.replace(hugeList.find("list uchar"), 10, "list uint");
  PlyWriter w("binary_little_endian");
  for (int i = 0; i < 9; ++i) w.put(static_cast<float>(i));
  w.put(static_cast<uint32_t>(0xFFFFFFFFu));
  w.put(static_cast<int32_t>(0));
  expectMeshError(write("huge_list.ply", hugeList + w.text()), "truncated");
  // Unknown elements with huge counts are bounded too, with and without lists.
  const std::string unknown =
      "ply\nformat binary_little_endian 1.0\nelement blob 4000000000000\nproperty list uint int "
      "data\n"
      "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  expectMeshError(write("huge_unknown.ply", unknown + std::string(64, '\0')), "truncated");
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 0.5);
}

TEST_F(MeshIoTest, PlyMissingCoordinate) {
  const std::string text =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0\n1 0\n0 1\n3 0 1 "
      "2\n";
  expectMeshError(write("no_z.ply", text), "'z'");
  expectMeshError(write("no_vertex.ply",
                        "ply\nformat ascii 1.0\nelement face 0\n"
                        "property list uchar int vertex_indices\nend_header\n"),
                  "vertex");
}

TEST_F(MeshIoTest, PlyFaceIndexOutOfRange) {
  expectMeshError(write("range.ply", kTriangleHeader + triangleBody(0.0f, 7)),
                  "face 0 refers to vertex 7 of 3");
  expectMeshError(write("negative.ply", kTriangleHeader + triangleBody(0.0f, -1)),
                  "refers to vertex -1 of 3");
}

TEST_F(MeshIoTest, PlyWithoutFaces) {
  const std::string noFaces =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float "
      "z\n"
      "element face 0\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n";
  expectMeshError(write("zero_faces.ply", noFaces), "no faces");
  const std::string pointCloud =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float "
      "z\n"
      "end_header\n0 0 0\n1 0 0\n0 1 0\n";
  expectMeshError(write("points.ply", pointCloud), "no faces");
  const std::string degenerate =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float "
      "z\n"
      "element face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n2 "
      "0 1\n0\n";
  expectMeshError(write("degenerate.ply", degenerate), "no faces");
  const std::string noIndexList =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float "
      "z\n"
      "element face 1\nproperty list uchar int corners\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  expectMeshError(write("no_index_list.ply", noIndexList), "vertex_indices");
}

TEST_F(MeshIoTest, PlyNonFiniteCoordinates) {
  expectMeshError(
      write("inf.ply", kTriangleHeader + triangleBody(std::numeric_limits<float>::infinity())),
      "vertex 0 has a non-finite position");
  expectMeshError(
      write("nan.ply", kTriangleHeader + triangleBody(std::numeric_limits<float>::quiet_NaN())),
      "non-finite");
  const std::string ascii =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty float y\nproperty "
      "float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1e300 0 0\n0 nan "
      "0\n3 0 1 2\n";
  expectMeshError(write("ascii_inf.ply", ascii), "vertex 1 has a non-finite position");
  const std::string garbage =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float "
      "z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 zero 0\n0 1 "
      "0\n3 0 1 2\n";
  expectMeshError(write("ascii_garbage.ply", garbage), "bad number 'zero'");
}

// ---------------------------------------------------------------------------------------
// OBJ

const char* kTwoQuadsObj =
    "# two unit quads side by side, in two objects\n"
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n"
    "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.25\n"
    "vn 0 0 1\n"
    "o first\n"
    "f 1/1/1 2/2/1 3/3/1 4/4/1\n"
    "o second\n"
    "f 2/2/1 5/5/1 6/3/1 3/3/1\n";

TEST_F(MeshIoTest, ObjQuadsWithNormalsAndUvs) {
  const TriangleMesh m = loadMesh(write("quads.OBJ", kTwoQuadsObj));
  expectWellFormed(m);
  // Six distinct (position, uv, normal) corners; corners 2 and 3 are shared between the
  // two objects.
  EXPECT_EQ(m.positions.size(), 6u);
  EXPECT_EQ(m.triangleCount(), 4u);
  ASSERT_EQ(m.normals.size(), 6u);
  ASSERT_EQ(m.uvs.size(), 6u);

  auto expectedUv = [](Vec3f p) -> Vec2f {
    if (p == Vec3f{0, 0, 0}) return {0, 0};
    if (p == Vec3f{1, 0, 0}) return {1, 0};
    if (p == Vec3f{1, 1, 0}) return {1, 1};
    if (p == Vec3f{0, 1, 0}) return {0, 1};
    if (p == Vec3f{2, 0, 0}) return {0.5f, 0.25f};
    return {1, 1};  // (2, 1, 0)
  };
  for (size_t i = 0; i < m.positions.size(); ++i) {
    EXPECT_EQ(m.normals[i], (Vec3f{0, 0, 1}));
    const Vec2f uv = expectedUv(m.positions[i]);
    EXPECT_EQ(m.uvs[i].x, uv.x) << i;
    EXPECT_EQ(m.uvs[i].y, uv.y) << i;
  }
  double area = 0;
  for (size_t t = 0; t < m.triangleCount(); ++t) {
    const Vec3f p0 = m.positions[m.indices[3 * t]];
    const Vec3f g =
        cross(m.positions[m.indices[3 * t + 1]] - p0, m.positions[m.indices[3 * t + 2]] - p0);
    EXPECT_GT(g.z, 0.0f) << "triangulation must keep the winding";
    area += 0.5 * length(g);
  }
  EXPECT_NEAR(area, 2.0, 1e-6);
}

TEST_F(MeshIoTest, ObjDropsAttributesSomeCornersLack) {
  const std::string text =
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\n"
      "f 1/1/1 2/2/1 3/3/1\n"
      "f 1//1 3//1 4//1\n";
  const TriangleMesh m = loadObj(write("mixed.obj", text));
  expectWellFormed(m);
  EXPECT_EQ(m.positions.size(), 4u);  // uvs dropped, so corners merge by position+normal
  EXPECT_EQ(m.normals.size(), 4u);
  EXPECT_TRUE(m.uvs.empty());
  EXPECT_EQ(m.triangleCount(), 2u);

  const std::string noNormals =
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
      "f 1/1/1 2/2/1 3/3/1\n"
      "f 1/1 3/3 4/4\n";
  const TriangleMesh n = loadObj(write("mixed_normals.obj", noNormals));
  expectWellFormed(n);
  EXPECT_EQ(n.positions.size(), 4u);
  EXPECT_TRUE(n.normals.empty());
  ASSERT_EQ(n.uvs.size(), 4u);
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(n.uvs[i].x, n.positions[i].x);
    EXPECT_EQ(n.uvs[i].y, n.positions[i].y);
  }
}

TEST_F(MeshIoTest, ObjPentagonIsTriangulated) {
  const std::string text = "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 2 0\nv 0 1 0\nf 1 2 3 4 5\n";
  const TriangleMesh m = loadObj(write("pentagon.obj", text));
  expectWellFormed(m);
  EXPECT_EQ(m.positions.size(), 5u);
  EXPECT_EQ(m.triangleCount(), 3u);
  EXPECT_TRUE(m.normals.empty());
  EXPECT_TRUE(m.uvs.empty());
}

TEST_F(MeshIoTest, ObjErrors) {
  expectMeshError(write("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"), "vertex 9 of 3");
  expectMeshError(write("range_quad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3 9\n"), "vertex");
  expectMeshError(write("negative.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n"), "vertex");
  expectMeshError(write("normal.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//2\n"),
                  "normal 2 of 1");
  expectMeshError(write("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"), "malformed OBJ");
  expectMeshError(write("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"), "no faces");
  expectMeshError(write("empty.obj", ""), "no faces");
  expectMeshError(write("huge.obj", "v 1e39 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"), "non-finite");
  // tinyobjloader would read these as 0 without a word.
  expectMeshError(write("nan.obj", "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"), "line 1: \"nan\" is not a finite number");
  expectMeshError(write("word.obj", "v 0 0 0\nv 1 x 0\nv 0 1 0\nf 1 2 3\n"), "line 2: \"x\" is not a finite number");
  expectMeshError(write("nan_uv.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 inf\nf 1/1 2/1 3/1\n"), "line 4: \"inf\"");
}

TEST_F(MeshIoTest, ObjIgnoresMaterialLibraries) {
  // The mtllib must not be opened; the geometry still loads.
  const std::string text =
      "mtllib /nonexistent/dir/lib.mtl\nusemtl red\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  const TriangleMesh m = loadObj(write("materials.obj", text));
  EXPECT_EQ(m.triangleCount(), 1u);
}

// bench/fuzz.sh --target mesh_readers found "vw 0 1e35 1": tinyobjloader's skin-weight
// lines (its own extension) convert a joint id to int unchecked, which is undefined
// behaviour that only the sanitizers see. pathfarm has no use for skin weights and no
// longer lets tinyobjloader read them: whatever they hold, even a negative joint id that
// it refused the whole file for, the geometry loads.
TEST_F(MeshIoTest, ObjSkinWeightsAreNotRead) {
  const std::string text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvw 0 1e35 1\n  vw\t1 -1 0.5\nf 1 2 3\n";
  const TriangleMesh m = loadObj(write("weights.obj", text));
  expectWellFormed(m);
  EXPECT_EQ(m.triangleCount(), 1u);
}

// Lines end at "\n", "\r" or "\r\n", as tinyobjloader reads them; a file with old Mac line
// ends was refused, and a number it would read as 0 could hide behind a lone "\r".
TEST_F(MeshIoTest, ObjLinesEndWhereTinyobjloaderEndsThem) {
  const TriangleMesh m = loadObj(write("cr.obj", "v 0 0 0\rv 1 0 0\r\nv 0 1 0\rf 1 2 3\r"));
  EXPECT_EQ(m.triangleCount(), 1u);
  expectMeshError(write("cr_nan.obj", "v 0 0 0\nv 1 0 0\rv nan 1 0\nf 1 2 3\n"), "line 3: \"nan\"");
}

// ---------------------------------------------------------------------------------------
// Fuzz-style robustness: damaged files either load into a well-formed mesh or throw
// MeshError, never anything else.

std::string mutate(const std::string& original, std::mt19937& rng, size_t protectPrefix) {
  std::string bytes = original;
  const uint32_t kind = rng() % 4;
  auto position = [&](size_t size) { return size == 0 ? 0 : rng() % size; };
  if (kind == 0 || kind == 3) {
    bytes.resize(position(bytes.size() + 1));  // truncate anywhere, including to nothing
  }
  if (kind >= 1) {
    const uint32_t flips = 1 + rng() % 4;
    for (uint32_t i = 0; i < flips && !bytes.empty(); ++i) {
      // Mostly hit the part after the magic so the deeper parsers get exercised.
      const size_t lo = std::min(protectPrefix, bytes.size() - 1);
      const size_t at = lo + position(bytes.size() - lo);
      static constexpr char kInteresting[] = {'\0', '\n', ' ', '-',    '9',
                                              '/',  '.',  'e', '\xff', '\x7f'};
      if (rng() % 2 == 0) {
        bytes[at] = static_cast<char>(bytes[at] ^ static_cast<char>(1u << (rng() % 8)));
      } else {
        bytes[at] = kInteresting[rng() % sizeof kInteresting];
      }
    }
  }
  return bytes;
}

void fuzzOne(const fs::path& path, const std::string& bytes) {
  {
    // A fresh file each time: truncating one in place makes ext4 flush it to disk on
    // close, which is slow on a busy machine.
    fs::remove(path);
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  }
  try {
    const TriangleMesh m = loadMesh(path);
    expectWellFormed(m);
  } catch (const MeshError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(path.string(), 0), 0u) << e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "unexpected exception type: " << e.what();
  }
}

TEST_F(MeshIoTest, FuzzedFilesNeverCrash) {
  std::mt19937 rng(20240607u);
  struct Base {
    std::string name;
    std::string bytes;
  };
  const Base bases[] = {
      {"fuzz_le.ply", makePly("binary_little_endian")},
      {"fuzz_be.ply", makePly("binary_big_endian")},
      {"fuzz_ascii.ply", makePly("ascii")},
      {"fuzz.obj", kTwoQuadsObj},
  };
  for (const Base& base : bases) {
    const fs::path path = dir_ / base.name;
    for (int i = 0; i < 200; ++i) {
      SCOPED_TRACE(base.name + " iteration " + std::to_string(i));
      fuzzOne(path, mutate(base.bytes, rng, 4));
      if (HasFatalFailure()) return;
    }
  }
}

}  // namespace
}  // namespace pathfarm
