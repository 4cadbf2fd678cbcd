#include "geometry/mesh_io.h"

#include "core/error.h"
#include "tests/support/atomic_temporaries.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

namespace sylva {
namespace {

namespace fs = std::filesystem;

class MeshIo : public test::TempDirTest {
 protected:
  fs::path write(const std::string& name, const std::string& bytes) const {
    const fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << bytes;
    return p;
  }
  fs::path path(const std::string& name) const { return dir_ / name; }
};

std::string read_all(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Expects read_mesh to throw a ParseError whose message starts "file:line:" and contains `what`.
void expect_parse_error(const fs::path& file, int line, const std::string& what) {
  try {
    read_mesh(file);
    ADD_FAILURE() << "no error for " << file;
  } catch (const ParseError& e) {
    const std::string msg = e.what();
    const std::string prefix = file.string() + ":" + std::to_string(line) + ": ";
    EXPECT_EQ(msg.rfind(prefix, 0), 0u) << msg;
    EXPECT_NE(msg.find(what), std::string::npos) << msg;
    EXPECT_EQ(e.line(), line);
  }
}

// A triangle as the attributes of its three corners, for order-independent comparison.
using CornerKey = std::tuple<float, float, float, float, float, float, float, float>;
using TriKey = std::array<CornerKey, 3>;

std::vector<TriKey> triangle_keys(const TriangleMesh& m) {
  std::vector<TriKey> keys;
  for (const glm::uvec3& t : m.triangles) {
    TriKey k;
    for (int c = 0; c < 3; ++c) {
      const Vec3 p = m.positions[t[c]];
      const Vec3 n = m.normals.empty() ? Vec3(0) : m.normals[t[c]];
      const Vec2 uv = m.uvs.empty() ? Vec2(0) : m.uvs[t[c]];
      k[c] = {p.x, p.y, p.z, n.x, n.y, n.z, uv.x, uv.y};
    }
    keys.push_back(k);
  }
  std::sort(keys.begin(), keys.end());
  return keys;
}

// A w×h grid of quads in the z = 0.25·sin plane, two triangles each, with normals and uvs.
TriangleMesh make_grid(int w, int h, bool normals = true, bool uvs = true) {
  TriangleMesh m;
  for (int j = 0; j <= h; ++j)
    for (int i = 0; i <= w; ++i) {
      const float u = static_cast<float>(i) / static_cast<float>(w);
      const float v = static_cast<float>(j) / static_cast<float>(h);
      m.positions.push_back({u * 3.1f, v * 1.7f, 0.25f * std::sin(7.0f * u + 3.0f * v)});
      if (normals) m.normals.push_back(glm::normalize(Vec3(0.1f * u, -0.2f * v, 1.0f)));
      if (uvs) m.uvs.push_back({u, v});
    }
  const auto at = [&](int i, int j) { return static_cast<uint32_t>(j * (w + 1) + i); };
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  return m;
}

// A small tree: a 4-sided stem ring pair (8 triangles) and leaves of two shapes.
TreeMesh make_tree() {
  TreeMesh t;
  for (int ring = 0; ring < 2; ++ring)
    for (int k = 0; k < 4; ++k) {
      const float a = static_cast<float>(k) * kPi / 2.0f;
      t.stems.positions.push_back({0.1f * std::cos(a), 0.1f * std::sin(a), 1.3f * ring});
      t.stems.normals.push_back({std::cos(a), std::sin(a), 0.0f});
      t.stems.uvs.push_back({k / 4.0f, static_cast<float>(ring)});
    }
  for (uint32_t k = 0; k < 4; ++k) {
    const uint32_t k1 = (k + 1) % 4;
    t.stems.triangles.push_back({k, k1, 4 + k1});
    t.stems.triangles.push_back({k, 4 + k1, 4 + k});
  }
  const std::array<LeafShape, 5> shapes{LeafShape::Oval, LeafShape::Maple5, LeafShape::Oval, LeafShape::Maple5,
                                        LeafShape::Oval};
  for (size_t i = 0; i < shapes.size(); ++i) {
    const Vec3 o(0.3f, 0.01f * static_cast<float>(i), 1.0f + 0.1f * static_cast<float>(i));
    t.leaves.corners.push_back(o);
    t.leaves.corners.push_back(o + Vec3(0.05f, 0, 0));
    t.leaves.corners.push_back(o + Vec3(0.05f, 0.11f, 0.02f));
    t.leaves.corners.push_back(o + Vec3(0, 0.11f, 0.02f));
    t.leaves.shapes.push_back(shapes[i]);
  }
  return t;
}

// What a TreeMesh should read back as: stems, then each leaf as the fan (0,1,2), (0,2,3).
TriangleMesh expected_triangles(const TreeMesh& t) {
  TriangleMesh m = t.stems;
  const std::array<Vec2, 4> uv{Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 1)};
  for (size_t i = 0; i < t.leaves.size(); ++i) {
    const Vec3* c = &t.leaves.corners[4 * i];
    const Vec3 n = glm::normalize(glm::cross(c[1] - c[0], c[2] - c[0]) + glm::cross(c[2] - c[0], c[3] - c[0]));
    const auto base = static_cast<uint32_t>(m.positions.size());
    for (int k = 0; k < 4; ++k) {
      m.positions.push_back(c[k]);
      m.normals.push_back(n);
      m.uvs.push_back(uv[k]);
    }
    m.triangles.push_back({base, base + 1, base + 2});
    m.triangles.push_back({base, base + 2, base + 3});
  }
  return m;
}

void expect_same_triangles(const TriangleMesh& got, const TriangleMesh& want) {
  ASSERT_EQ(got.triangles.size(), want.triangles.size());
  ASSERT_EQ(got.normals.size(), got.positions.size());
  ASSERT_EQ(got.uvs.size(), got.positions.size());
  const auto a = triangle_keys(got);
  const auto b = triangle_keys(want);
  for (size_t i = 0; i < a.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      const auto& x = a[i][c];
      const auto& y = b[i][c];
      EXPECT_EQ(std::get<0>(x), std::get<0>(y));
      EXPECT_EQ(std::get<1>(x), std::get<1>(y));
      EXPECT_EQ(std::get<2>(x), std::get<2>(y));
      EXPECT_NEAR(std::get<3>(x), std::get<3>(y), 1e-6f);
      EXPECT_NEAR(std::get<4>(x), std::get<4>(y), 1e-6f);
      EXPECT_NEAR(std::get<5>(x), std::get<5>(y), 1e-6f);
      EXPECT_EQ(std::get<6>(x), std::get<6>(y));
      EXPECT_EQ(std::get<7>(x), std::get<7>(y));
    }
  }
}

// ---------------------------------------------------------------------------------------- OBJ

const char* kObjHeader =
    "# test\nmtllib x.mtl\no thing\n"
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0.5\n"
    "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
    "vn 0 0 1\nvn 0 1 0\n";

TEST_F(MeshIo, ObjPositionOnlyFaces) {
  const TriangleMesh m = read_mesh(write("a.obj", std::string(kObjHeader) + "f 1 2 3\n"));
  ASSERT_EQ(m.triangles.size(), 1u);
  EXPECT_EQ(m.triangles[0], glm::uvec3(0, 1, 2));
  EXPECT_EQ(m.positions.size(), 4u);
  EXPECT_EQ(m.positions[3], Vec3(0, 1, 0.5f));
  EXPECT_TRUE(m.normals.empty());
  EXPECT_TRUE(m.uvs.empty());
}

TEST_F(MeshIo, ObjVertexTexcoordFaces) {
  const TriangleMesh m = read_mesh(write("a.obj", std::string(kObjHeader) + "f 1/4 2/3 3/2\n"));
  ASSERT_EQ(m.triangles.size(), 1u);
  ASSERT_EQ(m.uvs.size(), m.positions.size());
  EXPECT_TRUE(m.normals.empty());
  EXPECT_EQ(m.positions[m.triangles[0][1]], Vec3(1, 0, 0));
  EXPECT_EQ(m.uvs[m.triangles[0][0]], Vec2(0, 1));
  EXPECT_EQ(m.uvs[m.triangles[0][1]], Vec2(1, 1));
  EXPECT_EQ(m.uvs[m.triangles[0][2]], Vec2(1, 0));
}

TEST_F(MeshIo, ObjVertexNormalFaces) {
  const TriangleMesh m = read_mesh(write("a.obj", std::string(kObjHeader) + "f 1//2 2//1 3//2\n"));
  ASSERT_EQ(m.triangles.size(), 1u);
  ASSERT_EQ(m.normals.size(), m.positions.size());
  EXPECT_TRUE(m.uvs.empty());
  EXPECT_EQ(m.normals[m.triangles[0][0]], Vec3(0, 1, 0));
  EXPECT_EQ(m.normals[m.triangles[0][1]], Vec3(0, 0, 1));
}

TEST_F(MeshIo, ObjFullFacesShareIdenticalCorners) {
  const TriangleMesh m = read_mesh(
      write("a.obj", std::string(kObjHeader) + "f 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\nf 1/1/2 3/3/1 4/4/1\n"));
  ASSERT_EQ(m.triangles.size(), 3u);
  // (1,1,1) (2,2,1) (3,3,1) (4,4,1) and (1,1,2): five distinct corners.
  EXPECT_EQ(m.positions.size(), 5u);
  EXPECT_EQ(m.triangles[0][0], m.triangles[1][0]);
  EXPECT_NE(m.triangles[2][0], m.triangles[1][0]);
  EXPECT_EQ(m.positions[m.triangles[2][0]], m.positions[m.triangles[1][0]]);
  EXPECT_EQ(m.normals[m.triangles[2][0]], Vec3(0, 1, 0));
}

TEST_F(MeshIo, ObjNegativeIndicesAreRelative) {
  const std::string text =
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0.5 0.25\nvn 0 0 1\nf -3/-1/-1 -2/-1/-1 -1/-1/-1\n"
      "v 5 5 5\nf -4 -3 -1\n";
  const TriangleMesh m = read_mesh(write("n.obj", text));
  ASSERT_EQ(m.triangles.size(), 2u);
  // Mixed corner forms across faces: attributes are dropped, positions kept.
  EXPECT_TRUE(m.uvs.empty());
  EXPECT_TRUE(m.normals.empty());
  EXPECT_EQ(m.positions[m.triangles[0][0]], Vec3(0, 0, 0));
  EXPECT_EQ(m.positions[m.triangles[0][2]], Vec3(1, 1, 0));
  EXPECT_EQ(m.positions[m.triangles[1][1]], Vec3(1, 0, 0));
  EXPECT_EQ(m.positions[m.triangles[1][2]], Vec3(5, 5, 5));

  const TriangleMesh full = read_mesh(write("n2.obj",
                                            "v 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0.5 0.25\nvn 0 0 1\n"
                                            "f -3/-1/-1 -2/-1/-1 -1/-1/-1\n"));
  ASSERT_EQ(full.uvs.size(), 3u);
  EXPECT_EQ(full.uvs[0], Vec2(0.5f, 0.25f));
  EXPECT_EQ(full.normals[2], Vec3(0, 0, 1));
}

TEST_F(MeshIo, ObjPolygonsAreFanTriangulated) {
  const std::string text = "v 0 0 0\nv 1 0 0\nv 2 1 0\nv 1 2 0\nv 0 1 0\nf 1 2 3 4\nf 1 2 3 4 5\n";
  const TriangleMesh m = read_mesh(write("p.obj", text));
  ASSERT_EQ(m.triangles.size(), 2u + 3u);
  EXPECT_EQ(m.triangles[0], glm::uvec3(0, 1, 2));
  EXPECT_EQ(m.triangles[1], glm::uvec3(0, 2, 3));
  EXPECT_EQ(m.triangles[2], glm::uvec3(0, 1, 2));
  EXPECT_EQ(m.triangles[3], glm::uvec3(0, 2, 3));
  EXPECT_EQ(m.triangles[4], glm::uvec3(0, 3, 4));
}

TEST_F(MeshIo, ObjAcceptsIgnoredStatementsCrlfAndComments) {
  const std::string text =
      "# comment\r\nmtllib a.mtl\r\no obj\r\ng group one\r\nusemtl bark\r\ns off\r\n\r\n"
      "   v  0 0 0   # trailing\r\nv 1 0 0 1\r\nv 0 1 0 0.5 0.5 0.5\r\nvt 0.5\r\nvt 0.25 0.75 0\r\n"
      "\tf 1 2 3 # done\r\nl 1 2\r\ns 1\r\nv +1.5e0 -2.5E-1 .5";
  const TriangleMesh m = read_mesh(write("c.obj", text));
  ASSERT_EQ(m.triangles.size(), 1u);
  ASSERT_EQ(m.positions.size(), 4u);
  EXPECT_EQ(m.positions[3], Vec3(1.5f, -0.25f, 0.5f));
}

TEST_F(MeshIo, ObjUppercaseExtension) {
  const TriangleMesh m = read_mesh(write("UP.OBJ", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"));
  EXPECT_EQ(m.triangles.size(), 1u);
}

TEST_F(MeshIo, ObjErrorsNameFileAndLine) {
  expect_parse_error(write("bad_number.obj", "v 0 0 0\nv 1 0 0\nv 0 1.2.3 0\n"), 3,
                     "expected a vertex y after 'v', found '1.2.3'");
  expect_parse_error(write("short_v.obj", "v 0 0\n"), 1, "expected a vertex z after 'v'");
  expect_parse_error(write("nan.obj", "v 0 nan 0\n"), 1, "found 'nan'");
  expect_parse_error(write("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 4\n"), 5,
                     "vertex index 4 out of range (3 defined so far");
  expect_parse_error(write("neg_range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n"), 4,
                     "vertex index -4 out of range");
  expect_parse_error(write("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"), 4, "vertex index 0 out of range");
  expect_parse_error(write("vt_range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/2 2/1 3/1\n"), 5,
                     "texture coordinate index 2 out of range");
  expect_parse_error(write("vn_range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//1 2//1 3//1\n"), 4,
                     "normal index 1 out of range (0 defined");
  expect_parse_error(write("two.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n"), 3,
                     "expected at least 3 vertices in the face, found 2");
  expect_parse_error(write("corner.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3x\n"), 4,
                     "expected a face corner v, v/vt, v//vn or v/vt/vn, found 'x'");
  expect_parse_error(write("word.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 two 3\n"), 4,
                     "expected a vertex index in the face, found 'two'");
  expect_parse_error(write("extra.obj", "vn 0 0 1 7\n"), 1, "unexpected '7' at the end of the 'vn'");
  expect_parse_error(write("stmt.obj", "v 0 0 0\ncurv 0 1\n"), 2, "unknown OBJ statement 'curv'");
  expect_parse_error(write("overflow.obj", "v 1e99 0 0\n"), 1, "found '1e99'");
}

TEST_F(MeshIo, UnknownFormatAndMissingFile) {
  expect_parse_error(write("mesh.stl", "solid x\n"), 0, "unknown mesh format '.stl' (expected .obj or .ply)");
  expect_parse_error(write("noext", "v 0 0 0\n"), 0, "unknown mesh format");
  expect_parse_error(path("missing.obj"), 0, "cannot open");
}

// ---------------------------------------------------------------------------------------- PLY

TEST_F(MeshIo, PlyAsciiWithNormalsUvsAndSkippedData) {
  const std::string text =
      "ply\nformat ascii 1.0\ncomment made by hand\nobj_info x\n"
      "element material 1\nproperty uchar red\nproperty list uchar float weights\n"
      "element vertex 5\nproperty float x\nproperty float y\nproperty float z\nproperty uchar "
      "quality\nproperty float nx\nproperty float ny\nproperty float nz\nproperty float s\n"
      "property float t\n"
      "element face 2\nproperty uchar flags\nproperty list uchar int vertex_indices\n"
      "property list uchar float texcoord\n"
      "element edge 1\nproperty int vertex1\nproperty int vertex2\n"
      "end_header\n"
      "255 2 0.5 0.25\n"
      "0 0 0 7 0 0 1 0 0\n1 0 0 7 0 0 1 1 0\n1 1 0 7 0 0 1 1 1\n0 1 0 7 0 0 1 0 1\n"
      "0.5 0.5 -1e-3 7 0 1 0 0.5 0.5\n"
      "0 3 0 1 2 0\n1 4 0 2 3 4 2 0.5 0.5\n"
      "0 1\n";
  const TriangleMesh m = read_mesh(write("a.ply", text));
  ASSERT_EQ(m.positions.size(), 5u);
  ASSERT_EQ(m.normals.size(), 5u);
  ASSERT_EQ(m.uvs.size(), 5u);
  EXPECT_EQ(m.positions[4], Vec3(0.5f, 0.5f, -1e-3f));
  EXPECT_EQ(m.normals[4], Vec3(0, 1, 0));
  EXPECT_EQ(m.uvs[2], Vec2(1, 1));
  ASSERT_EQ(m.triangles.size(), 3u);
  EXPECT_EQ(m.triangles[0], glm::uvec3(0, 1, 2));
  EXPECT_EQ(m.triangles[1], glm::uvec3(0, 2, 3));
  EXPECT_EQ(m.triangles[2], glm::uvec3(0, 3, 4));
}

TEST_F(MeshIo, PlyUvNamesAndVertexIndexAlias) {
  for (const auto& [u, v] :
       {std::pair{"u", "v"}, std::pair{"texture_u", "texture_v"}, std::pair{"texture_s", "texture_t"}}) {
    const std::string text = std::string(
                                 "ply\r\nformat ascii 1.0\r\nelement vertex 3\r\n"
                                 "property double x\r\nproperty double y\r\nproperty double z\r\n"
                                 "property float ") +
                             u + "\r\nproperty float " + v +
                             "\r\nelement face 1\r\nproperty list uint8 uint32 vertex_index\r\n"
                             "end_header\r\n0 0 0 0.25 0.5\r\n1 0 0 1 0\r\n0 1 0 0 1\r\n3 2 1 0\r\n";
    const TriangleMesh m = read_mesh(write("uv.ply", text));
    ASSERT_EQ(m.uvs.size(), 3u) << u;
    EXPECT_EQ(m.uvs[0], Vec2(0.25f, 0.5f));
    EXPECT_TRUE(m.normals.empty());
    ASSERT_EQ(m.triangles.size(), 1u);
    EXPECT_EQ(m.triangles[0], glm::uvec3(2, 1, 0));
  }
}

// Builds a binary PLY body value by value.
class Bytes {
 public:
  explicit Bytes(bool little) : little_(little) {}
  template <typename T>
  Bytes& put(T v) {
    std::array<char, sizeof(T)> raw;
    std::memcpy(raw.data(), &v, sizeof(T));
    if (little_ != (std::endian::native == std::endian::little)) std::reverse(raw.begin(), raw.end());
    s_.append(raw.data(), raw.size());
    return *this;
  }
  const std::string& str() const { return s_; }

 private:
  bool little_;
  std::string s_;
};

std::string binary_ply(bool little) {
  std::string header = std::string("ply\nformat ") + (little ? "binary_little_endian" : "binary_big_endian") +
                       " 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float "
                       "z\nproperty double nx\nproperty double ny\nproperty double nz\n"
                       "property uchar red\nproperty float u\nproperty float v\n"
                       "element face 2\nproperty list ushort short vertex_indices\nproperty int flags\n"
                       "element extra 2\nproperty list int char stuff\n"
                       "end_header\n";
  Bytes b(little);
  const float pos[4][3] = {{0, 0, 0}, {1.5f, 0, 0}, {1.5f, 2, 0}, {0, 2, -0.125f}};
  for (int i = 0; i < 4; ++i) {
    b.put(pos[i][0]).put(pos[i][1]).put(pos[i][2]);
    b.put(0.0).put(0.0).put(1.0);
    b.put(uint8_t{200});
    b.put(static_cast<float>(i) / 4.0f).put(1.0f - static_cast<float>(i) / 4.0f);
  }
  b.put(uint16_t{4}).put(int16_t{0}).put(int16_t{1}).put(int16_t{2}).put(int16_t{3}).put(int32_t{-1});
  b.put(uint16_t{3}).put(int16_t{3}).put(int16_t{2}).put(int16_t{1}).put(int32_t{7});
  b.put(int32_t{2}).put(int8_t{1}).put(int8_t{2});
  b.put(int32_t{0});
  return header + b.str();
}

TEST_F(MeshIo, PlyBinaryBothEndians) {
  for (const bool little : {true, false}) {
    const TriangleMesh m = read_mesh(write(little ? "le.ply" : "be.ply", binary_ply(little)));
    ASSERT_EQ(m.positions.size(), 4u);
    EXPECT_EQ(m.positions[2], Vec3(1.5f, 2, 0));
    EXPECT_EQ(m.positions[3], Vec3(0, 2, -0.125f));
    ASSERT_EQ(m.normals.size(), 4u);
    EXPECT_EQ(m.normals[1], Vec3(0, 0, 1));
    ASSERT_EQ(m.uvs.size(), 4u);
    EXPECT_EQ(m.uvs[3], Vec2(0.75f, 0.25f));
    ASSERT_EQ(m.triangles.size(), 3u);
    EXPECT_EQ(m.triangles[1], glm::uvec3(0, 2, 3));
    EXPECT_EQ(m.triangles[2], glm::uvec3(3, 2, 1));
  }
}

TEST_F(MeshIo, PlyErrors) {
  const std::string good = binary_ply(true);
  // Cut inside the second face.
  const size_t cut = good.size() - 6 - 1 - 4 - 8;
  expect_parse_error(write("trunc.ply", good.substr(0, cut)), 0, "truncated binary PLY data at byte");
  expect_parse_error(write("trunc2.ply", good.substr(0, cut)), 0, "of face 1");
  expect_parse_error(write("nohdr.ply", "ply\nformat ascii 1.0\nelement vertex 1\n"), 3,
                     "expected 'end_header' before the end of the file");
  expect_parse_error(write("magic.ply", "PLY\nformat ascii 1.0\nend_header\n"), 1, "expected the PLY magic");
  expect_parse_error(write("fmt.ply", "ply\nformat binary_middle_endian 1.0\nend_header\n"), 2,
                     "expected format ascii, binary_little_endian or binary_big_endian");
  expect_parse_error(write("type.ply",
                           "ply\nformat ascii 1.0\nelement vertex 1\nproperty float32x x\n"
                           "end_header\n"),
                     4, "expected a PLY type, found 'float32x'");
  expect_parse_error(write("noxyz.ply",
                           "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                           "end_header\n0\n"),
                     3, "expected scalar properties x, y and z");
  const std::string ascii_head =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float "
      "z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  expect_parse_error(write("num.ply", ascii_head + "0 0 0\n1 0 0\n0 1 zero\n3 0 1 2\n"), 12,
                     "expected z of vertex 2, found 'zero'");
  expect_parse_error(write("idx.ply", ascii_head + "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"), 13,
                     "vertex index 3 in face 0 out of range (3 vertices)");
  expect_parse_error(write("cnt.ply", ascii_head + "0 0 0\n1 0 0\n0 1 0\n300 0 1 2\n"), 13,
                     "expected the list length of vertex_indices of face 0, found '300'");
  expect_parse_error(write("short.ply", ascii_head + "0 0 0\n1 0 0\n0 1 0\n3 0 1"), 13,
                     "expected a vertex index in vertex_indices of face 0, found the end of the file");
  expect_parse_error(write("more.ply", ascii_head + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n9\n"), 14,
                     "unexpected '9' after the last PLY element");
  expect_parse_error(write("two.ply", ascii_head + "0 0 0\n1 0 0\n0 1 0\n2 0 1\n"), 13,
                     "expected at least 3 vertex indices in face 0");
  std::string bad_index = good;
  // First face's first index (after 4 vertices of 3·4 + 3·8 + 1 + 2·4 = 45 bytes and a ushort).
  const size_t first_index = good.find("end_header\n") + 11 + 4 * 45 + 2;
  bad_index[first_index] = 9;
  expect_parse_error(write("bidx.ply", bad_index), 0, "vertex index 9 in face 0 out of range (4 vertices)");
}

// ------------------------------------------------------------------------------- round trips

TEST_F(MeshIo, TreeMeshObjRoundTrip) {
  const TreeMesh tree = make_tree();
  const fs::path file = path("tree.obj");
  write_obj(file, tree);
  EXPECT_TRUE(test::atomic_temporaries_in(dir_).empty());
  const std::string text = read_all(file);
  EXPECT_NE(text.find("g stems\n"), std::string::npos);
  EXPECT_NE(text.find("g leaves_" + std::string(leaf_shape_name(LeafShape::Oval)) + "\nusemtl leaves_" +
                      std::string(leaf_shape_name(LeafShape::Oval)) + "\n"),
            std::string::npos);
  EXPECT_NE(text.find("g leaves_" + std::string(leaf_shape_name(LeafShape::Maple5))), std::string::npos);
  EXPECT_EQ(text.find("g leaves_" + std::string(leaf_shape_name(LeafShape::Triangle))), std::string::npos);
  // Leaves are written as quads.
  EXPECT_NE(text.find("f 9/9/9 10/10/9 11/11/9 12/12/9\n"), std::string::npos);

  const TriangleMesh m = read_mesh(file);
  EXPECT_EQ(m.triangles.size(), tree.stems.triangles.size() + 2 * tree.leaves.size());
  expect_same_triangles(m, expected_triangles(tree));
}

TEST_F(MeshIo, TreeMeshPlyRoundTrip) {
  const TreeMesh tree = make_tree();
  const fs::path file = path("tree.ply");
  write_ply(file, tree);
  EXPECT_TRUE(test::atomic_temporaries_in(dir_).empty());
  const std::string bytes = read_all(file);
  EXPECT_NE(bytes.find("format binary_little_endian 1.0\n"), std::string::npos);
  EXPECT_NE(bytes.find("property list uchar int vertex_indices\nproperty uchar leaf_shape\n"), std::string::npos);
  // Face records: stems (1 + 12 + 1 bytes) then leaves (1 + 16 + 1 bytes), leaf_shape last.
  const size_t leaf_faces = tree.leaves.size() * 18;
  const size_t faces_begin = bytes.size() - leaf_faces - tree.stems.triangles.size() * 14;
  EXPECT_EQ(static_cast<uint8_t>(bytes[faces_begin + 13]), 255);
  for (size_t i = 0; i < tree.leaves.size(); ++i) {
    const size_t rec = bytes.size() - leaf_faces + 18 * i;
    EXPECT_EQ(static_cast<uint8_t>(bytes[rec]), 4);
    EXPECT_EQ(static_cast<uint8_t>(bytes[rec + 17]), static_cast<uint8_t>(tree.leaves.shapes[i]));
  }
  const TriangleMesh m = read_mesh(file);
  EXPECT_EQ(m.positions.size(), tree.stems.positions.size() + tree.leaves.corners.size());
  EXPECT_EQ(m.triangles.size(), tree.stems.triangles.size() + 2 * tree.leaves.size());
  expect_same_triangles(m, expected_triangles(tree));
  // PLY keeps vertex order: leaf i's corners follow the stems with uv (0,0),(1,0),(1,1),(0,1).
  const size_t base = tree.stems.positions.size();
  EXPECT_EQ(m.positions[base + 4 * 3 + 2], tree.leaves.corners[4 * 3 + 2]);
  EXPECT_EQ(m.uvs[base + 4 * 3 + 3], Vec2(0, 1));
}

TEST_F(MeshIo, TreeMeshWithoutStemNormalsOrUvs) {
  TreeMesh tree = make_tree();
  tree.stems.normals.clear();
  tree.stems.uvs.clear();
  for (const char* name : {"bare.obj", "bare.ply"}) {
    const fs::path file = path(name);
    name[5] == 'o' ? write_obj(file, tree) : write_ply(file, tree);
    const TriangleMesh m = read_mesh(file);
    ASSERT_EQ(m.normals.size(), m.positions.size()) << name;
    ASSERT_EQ(m.uvs.size(), m.positions.size()) << name;
    for (const Vec3& n : m.normals) EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f);
    EXPECT_EQ(m.triangles.size(), tree.stems.triangles.size() + 2 * tree.leaves.size());
  }
}

TEST_F(MeshIo, TriangleMeshObjRoundTrip) {
  for (const bool normals : {false, true})
    for (const bool uvs : {false, true}) {
      const TriangleMesh grid = make_grid(7, 5, normals, uvs);
      const fs::path file = path("grid.obj");
      write_obj(file, grid);
      const TriangleMesh m = read_mesh(file);
      EXPECT_EQ(m.positions, grid.positions);  // exact: shortest round-trip floats
      EXPECT_EQ(m.normals, grid.normals);
      EXPECT_EQ(m.uvs, grid.uvs);
      EXPECT_EQ(m.triangles, grid.triangles);
    }
}

TEST_F(MeshIo, WritesAreAtomic) {
  const TreeMesh tree = make_tree();
  // A missing directory: the writer throws sylva::Error and leaves nothing behind.
  EXPECT_THROW(write_obj(path("no/such/dir/t.obj"), tree), Error);
  EXPECT_THROW(write_ply(path("no/such/dir/t.ply"), tree), Error);
  // An inconsistent mesh is refused before anything is written.
  TreeMesh bad = tree;
  bad.stems.triangles.push_back({0, 1, 99});
  EXPECT_THROW(write_obj(path("bad.obj"), bad), Error);
  EXPECT_FALSE(fs::exists(path("bad.obj")));
  EXPECT_TRUE(test::atomic_temporaries_in(dir_).empty());
  TreeMesh nan_leaf = tree;
  nan_leaf.leaves.corners[2].y = std::nanf("");
  EXPECT_THROW(write_ply(path("nan.ply"), nan_leaf), Error);
  EXPECT_FALSE(fs::exists(path("nan.ply")));
  // Overwriting replaces the old file.
  write("over.obj", "old");
  write_obj(path("over.obj"), tree);
  EXPECT_EQ(read_mesh(path("over.obj")).triangles.size(), 18u);
  EXPECT_TRUE(test::atomic_temporaries_in(dir_).empty());
}

// ------------------------------------------------------------------------------- robustness

// Reading must either succeed with valid indices or throw ParseError; never crash or hang.
void expect_robust(const fs::path& file) {
  try {
    const TriangleMesh m = read_mesh(file);
    for (const glm::uvec3& t : m.triangles)
      for (int c = 0; c < 3; ++c) ASSERT_LT(t[c], m.positions.size());
    if (!m.normals.empty()) {
      ASSERT_EQ(m.normals.size(), m.positions.size());
    }
    if (!m.uvs.empty()) {
      ASSERT_EQ(m.uvs.size(), m.positions.size());
    }
  } catch (const ParseError&) {
  }
}

TEST_F(MeshIo, GarbageAndTruncationsNeverCrash) {
  std::mt19937 rng(12345);
  TreeMesh tree = make_tree();
  write_obj(path("v.obj"), tree);
  write_ply(path("v.ply"), tree);
  std::string ascii_ply =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float "
      "z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 "
      "0 1 2\n";
  const std::vector<std::pair<std::string, std::string>> valid{{".obj", read_all(path("v.obj"))},
                                                               {".ply", read_all(path("v.ply"))},
                                                               {".ply", ascii_ply},
                                                               {".ply", binary_ply(false)}};
  const std::string alphabet = "0123456789 -+./\n\tvtnf#eE";
  int n = 0;
  for (int iter = 0; iter < 160; ++iter) {
    for (const auto& [ext, text] : valid) {
      std::string s = text;
      switch (iter % 4) {
        case 0:  // truncation
          s.resize(rng() % (s.size() + 1));
          break;
        case 1:  // random byte flips
          for (int k = 0; k < 1 + static_cast<int>(rng() % 8); ++k)
            s[rng() % s.size()] = static_cast<char>(rng() & 0xff);
          break;
        case 2:  // OBJ/PLY-ish token soup after a valid prefix
          s.resize(rng() % (s.size() + 1));
          for (int k = 0; k < 200; ++k) s += alphabet[rng() % alphabet.size()];
          break;
        default:  // pure garbage
          s.assign(rng() % 400, '\0');
          for (char& c : s) c = static_cast<char>(rng() & 0xff);
          if (rng() % 2)
            s = (ext == ".ply" ? "ply\nformat binary_little_endian 1.0\nelement vertex 3\n"
                                 "property float x\nproperty float y\nproperty float z\n"
                                 "element face 4000000000\nproperty list uint int "
                                 "vertex_indices\nend_header\n"
                               : "v 1 2 3\nf ") +
                s;
      }
      expect_robust(write("fuzz" + std::to_string(n++ % 7) + ext, s));
    }
  }
}

TEST_F(MeshIo, ObjReadThroughput) {
  const TriangleMesh grid = make_grid(300, 300);  // 180k triangles with normals and uvs
  const fs::path file = path("big.obj");
  write_obj(file, grid);
  const auto t0 = std::chrono::steady_clock::now();
  const TriangleMesh m = read_mesh(file);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(m.triangles.size(), grid.triangles.size());
  EXPECT_EQ(m.positions, grid.positions);
  std::printf("OBJ read: %zu triangles (v/vt/vn) in %.3f s = %.1f M triangles/s\n", m.triangles.size(), s,
              static_cast<double>(m.triangles.size()) / s * 1e-6);
}

}  // namespace
}  // namespace sylva
