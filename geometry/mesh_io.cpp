#include "geometry/mesh_io.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/input_file.h"
#include "geometry/mesh_io_detail.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <system_error>

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

namespace sylva {

namespace mesh_io_detail {

std::string printable(std::string_view s) {
  constexpr size_t kMax = 40;
  std::string out = "'";
  for (size_t i = 0; i < s.size() && i < kMax; ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", c);
      out += hex;
    }
  }
  if (s.size() > kMax) out += "...";
  return out + "'";
}

}  // namespace mesh_io_detail

namespace {

namespace fs = std::filesystem;
using mesh_io_detail::printable;

// The file's bytes, memory-mapped read-only for the duration of a parse.
class MappedFile {
 public:
  explicit MappedFile(const fs::path& file) {
    uint64_t size = 0;
    fd_ = open_input_file(file, kMaxMeshFileBytes, "mesh", size);
    size_ = static_cast<size_t>(size);
    if (size_ == 0) return;
    void* p = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE | MAP_POPULATE, fd_, 0);
    if (p == MAP_FAILED) {
      const int err = errno;
      ::close(fd_);
      throw ParseError(file, 0, std::string("cannot read: ") + std::strerror(err));
    }
    data_ = static_cast<const char*>(p);
    ::madvise(p, size_, MADV_SEQUENTIAL);
  }
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;
  ~MappedFile() {
    if (data_ != nullptr) ::munmap(const_cast<char*>(data_), size_);
    ::close(fd_);
  }
  std::string_view bytes() const { return {data_ == nullptr ? "" : data_, size_}; }

 private:
  int fd_ = -1;
  const char* data_ = nullptr;
  size_t size_ = 0;
};

// Buffered output to a stream, handed over in chunks of about a megabyte (maybe_flush) and at the end
// (flush), so large meshes are neither held whole in memory nor written a number at a time.
class BufferedWriter {
 public:
  explicit BufferedWriter(std::ostream& out) : out_(out) { buf_.reserve(kFlushBytes + 4096); }

  void put(std::string_view s) {
    buf_.append(s);
    maybe_flush();
  }
  void put(char c) { buf_.push_back(c); }
  void put(float v) {
    char tmp[32];
    const auto r = std::to_chars(tmp, tmp + sizeof tmp, v == 0.0f ? 0.0f : v);  // no "-0"
    buf_.append(tmp, static_cast<size_t>(r.ptr - tmp));
  }
  void put(uint64_t v) {
    char tmp[24];
    const auto r = std::to_chars(tmp, tmp + sizeof tmp, v);
    buf_.append(tmp, static_cast<size_t>(r.ptr - tmp));
  }
  // Little-endian binary value.
  template <typename T>
  void put_le(T v) {
    std::array<char, sizeof(T)> raw;
    std::memcpy(raw.data(), &v, sizeof(T));
    if constexpr (std::endian::native == std::endian::big) std::reverse(raw.begin(), raw.end());
    buf_.append(raw.data(), raw.size());
  }
  void maybe_flush() {
    if (buf_.size() >= kFlushBytes) flush();
  }
  void flush() {
    out_.write(buf_.data(), static_cast<std::streamsize>(buf_.size()));
    buf_.clear();
  }

 private:
  static constexpr size_t kFlushBytes = 1 << 20;

  std::ostream& out_;
  std::string buf_;
};

// Writes `file` atomically (core/atomic_file.h) through a BufferedWriter filled by `put_all`.
template <typename PutAll>
void write_buffered(const fs::path& file, const PutAll& put_all) {
  write_file_atomic(file, [&](std::ostream& out) {
    BufferedWriter w(out);
    put_all(w);
    w.flush();
  });
}

void validate(const TriangleMesh& m, const fs::path& file) {
  const size_t n = m.positions.size();
  if (!m.normals.empty() && m.normals.size() != n)
    throw Error("cannot write " + file.string() + ": normals and positions differ in count");
  if (!m.uvs.empty() && m.uvs.size() != n)
    throw Error("cannot write " + file.string() + ": uvs and positions differ in count");
  for (const glm::uvec3& t : m.triangles)
    if (t.x >= n || t.y >= n || t.z >= n)
      throw Error("cannot write " + file.string() + ": triangle index out of range");
  const auto finite2 = [](const Vec2& v) { return std::isfinite(v.x) && std::isfinite(v.y); };
  if (!std::all_of(m.positions.begin(), m.positions.end(), is_finite) ||
      !std::all_of(m.normals.begin(), m.normals.end(), is_finite) || !std::all_of(m.uvs.begin(), m.uvs.end(), finite2))
    throw Error("cannot write " + file.string() + ": non-finite vertex data");
}

void validate(const TreeMesh& m, const fs::path& file) {
  validate(m.stems, file);
  if (m.leaves.corners.size() != 4 * m.leaves.shapes.size())
    throw Error("cannot write " + file.string() + ": leaf corners are not 4 per leaf");
  if (!std::all_of(m.leaves.corners.begin(), m.leaves.corners.end(), is_finite))
    throw Error("cannot write " + file.string() + ": non-finite leaf corner");
  for (const LeafShape s : m.leaves.shapes)
    if (static_cast<size_t>(s) >= static_cast<size_t>(LeafShape::Count))
      throw Error("cannot write " + file.string() + ": invalid leaf shape");
  const size_t vertices = m.stems.positions.size() + m.leaves.corners.size();
  if (vertices > std::numeric_limits<int32_t>::max())
    throw Error("cannot write " + file.string() + ": too many vertices");
}

Vec3 safe_normalize(const Vec3& v) {
  const float len = glm::length(v);
  return len > 0.0f && std::isfinite(len) ? v / len : Vec3(0, 0, 1);
}

// The stems' normals, or area-weighted vertex normals when the mesh has none.
std::vector<Vec3> stem_normals(const TriangleMesh& m) {
  if (!m.normals.empty()) return m.normals;
  std::vector<Vec3> n(m.positions.size(), Vec3(0));
  for (const glm::uvec3& t : m.triangles) {
    const Vec3 face = glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]);
    n[t.x] += face;
    n[t.y] += face;
    n[t.z] += face;
  }
  for (Vec3& v : n) v = safe_normalize(v);
  return n;
}

// The normal of leaf quad i, on its upper (adaxial) side.
Vec3 leaf_normal(const LeafQuads& leaves, size_t i) {
  const Vec3* c = &leaves.corners[4 * i];
  return safe_normalize(glm::cross(c[1] - c[0], c[2] - c[0]) + glm::cross(c[2] - c[0], c[3] - c[0]));
}

constexpr std::array<Vec2, 4> kLeafUvs{Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 1)};

// One OBJ statement: `tag x y [z]`, for Vec2 and Vec3.
template <int N>
void put_vec(BufferedWriter& w, std::string_view tag, const glm::vec<N, float>& v) {
  w.put(tag);
  for (int i = 0; i < N; ++i) {
    w.put(' ');
    w.put(v[i]);
  }
  w.put('\n');
  w.maybe_flush();
}

// One OBJ face corner "v[/vt][/vn]" with 0-based indices (kNoIndex for absent).
constexpr uint64_t kNoIndex = ~uint64_t{0};
void put_corner(BufferedWriter& w, uint64_t v, uint64_t vt, uint64_t vn) {
  w.put(' ');
  w.put(v + 1);
  if (vt == kNoIndex && vn == kNoIndex) return;
  w.put('/');
  if (vt != kNoIndex) w.put(vt + 1);
  if (vn == kNoIndex) return;
  w.put('/');
  w.put(vn + 1);
}

}  // namespace

TriangleMesh read_mesh(const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext != ".obj" && ext != ".ply")
    throw ParseError(file, 0, "unknown mesh format " + printable(ext) + " (expected .obj or .ply)");
  const MappedFile mapped(file);
  return ext == ".obj" ? mesh_io_detail::parse_obj(file, mapped.bytes())
                       : mesh_io_detail::parse_ply(file, mapped.bytes());
}

void write_obj(const std::filesystem::path& file, const TriangleMesh& mesh) { write_obj(file, mesh, ObjGroups{}); }

void write_obj(const std::filesystem::path& file, const TriangleMesh& mesh, const ObjGroups& groups) {
  validate(mesh, file);
  // Without names the faces are written in mesh order; with names, by group (a counting sort), each
  // group in mesh order.
  const bool grouped = !groups.names.empty();
  std::vector<size_t> start{0, mesh.triangles.size()};
  std::vector<uint32_t> order;
  if (grouped) {
    if (groups.of_triangle.size() != mesh.triangles.size())
      throw Error("cannot write " + file.string() + ": face groups and faces differ in count");
    start.assign(groups.names.size() + 1, 0);
    for (const uint32_t g : groups.of_triangle) {
      if (g >= groups.names.size()) throw Error("cannot write " + file.string() + ": a face's group has no name");
      ++start[g + 1];
    }
    for (size_t g = 0; g + 1 < start.size(); ++g) start[g + 1] += start[g];
    order.resize(mesh.triangles.size());
    std::vector<size_t> next(start.begin(), start.end() - 1);
    for (size_t t = 0; t < mesh.triangles.size(); ++t) order[next[groups.of_triangle[t]]++] = static_cast<uint32_t>(t);
  }

  write_buffered(file, [&](BufferedWriter& w) {
    w.put("# Sylva mesh: ");
    w.put(uint64_t{mesh.positions.size()});
    w.put(" vertices, ");
    w.put(uint64_t{mesh.triangles.size()});
    w.put(" triangles\n");
    if (!groups.mtllib.empty()) w.put("mtllib " + groups.mtllib + "\n");
    for (const Vec3& p : mesh.positions) put_vec(w, "v", p);
    for (const Vec2& t : mesh.uvs) put_vec(w, "vt", t);
    for (const Vec3& n : mesh.normals) put_vec(w, "vn", n);
    const bool uv = !mesh.uvs.empty();
    const bool nrm = !mesh.normals.empty();
    for (size_t g = 0; g + 1 < start.size(); ++g) {
      if (start[g] == start[g + 1]) continue;
      if (grouped) w.put("g " + groups.names[g] + "\nusemtl " + groups.names[g] + "\n");
      for (size_t i = start[g]; i < start[g + 1]; ++i) {
        const glm::uvec3& t = mesh.triangles[grouped ? order[i] : i];
        w.put('f');
        for (int k = 0; k < 3; ++k) put_corner(w, t[k], uv ? t[k] : kNoIndex, nrm ? t[k] : kNoIndex);
        w.put('\n');
        w.maybe_flush();
      }
    }
  });
}

void write_obj(const std::filesystem::path& file, const TreeMesh& mesh) {
  validate(mesh, file);
  const TriangleMesh& stems = mesh.stems;
  const LeafQuads& leaves = mesh.leaves;
  const size_t ns = stems.positions.size();
  const std::vector<Vec3> normals = stem_normals(stems);
  write_buffered(file, [&](BufferedWriter& w) {
    w.put("# Sylva tree mesh: ");
    w.put(uint64_t{stems.triangles.size()});
    w.put(" stem triangles, ");
    w.put(uint64_t{leaves.size()});
    w.put(" leaf quads\no tree\n");
    for (const Vec3& p : stems.positions) put_vec(w, "v", p);
    for (const Vec3& p : leaves.corners) put_vec(w, "v", p);
    // Texture coordinates: per stem vertex (or one shared (0,0)), then the four leaf corners.
    size_t stem_vts = 0;
    if (ns > 0) {
      if (stems.uvs.empty()) put_vec(w, "vt", Vec2(0));
      for (const Vec2& t : stems.uvs) put_vec(w, "vt", t);
      stem_vts = stems.uvs.empty() ? 1 : ns;
    }
    if (leaves.size() > 0)
      for (const Vec2& t : kLeafUvs) put_vec(w, "vt", t);
    for (const Vec3& n : normals) put_vec(w, "vn", n);
    for (size_t i = 0; i < leaves.size(); ++i) put_vec(w, "vn", leaf_normal(leaves, i));

    if (!stems.triangles.empty()) w.put("g stems\nusemtl stems\n");
    for (const glm::uvec3& t : stems.triangles) {
      w.put('f');
      for (int k = 0; k < 3; ++k) put_corner(w, t[k], stems.uvs.empty() ? 0 : t[k], t[k]);
      w.put('\n');
      w.maybe_flush();
    }
    for (size_t s = 0; s < static_cast<size_t>(LeafShape::Count); ++s) {
      const auto shape = static_cast<LeafShape>(s);
      if (std::find(leaves.shapes.begin(), leaves.shapes.end(), shape) == leaves.shapes.end()) continue;
      const std::string name = "leaves_" + std::string(leaf_shape_name(shape));
      w.put("g " + name + "\nusemtl " + name + "\n");
      for (size_t i = 0; i < leaves.size(); ++i) {
        if (leaves.shapes[i] != shape) continue;
        w.put('f');
        for (size_t k = 0; k < 4; ++k) put_corner(w, ns + 4 * i + k, stem_vts + k, ns + i);
        w.put('\n');
        w.maybe_flush();
      }
    }
  });
}

void write_ply(const std::filesystem::path& file, const TreeMesh& mesh) {
  validate(mesh, file);
  const TriangleMesh& stems = mesh.stems;
  const LeafQuads& leaves = mesh.leaves;
  const std::vector<Vec3> normals = stem_normals(stems);
  write_buffered(file, [&](BufferedWriter& w) {
    w.put("ply\nformat binary_little_endian 1.0\ncomment Sylva tree mesh\n");
    w.put("comment leaf_shape: LeafShape of a leaf face, 255 for stem faces");
    for (size_t s = 0; s < static_cast<size_t>(LeafShape::Count); ++s) {
      w.put(s == 0 ? "; " : ", ");
      w.put(uint64_t{s});
      w.put(" = ");
      w.put(leaf_shape_name(static_cast<LeafShape>(s)));
    }
    w.put("\nelement vertex ");
    w.put(uint64_t{stems.positions.size() + leaves.corners.size()});
    w.put(
        "\nproperty float x\nproperty float y\nproperty float z\n"
        "property float nx\nproperty float ny\nproperty float nz\n"
        "property float u\nproperty float v\nelement face ");
    w.put(uint64_t{stems.triangles.size() + leaves.size()});
    w.put("\nproperty list uchar int vertex_indices\nproperty uchar leaf_shape\nend_header\n");
    auto vertex = [&](const Vec3& p, const Vec3& n, const Vec2& uv) {
      for (const float f : {p.x, p.y, p.z, n.x, n.y, n.z, uv.x, uv.y}) w.put_le(f);
      w.maybe_flush();
    };
    for (size_t i = 0; i < stems.positions.size(); ++i)
      vertex(stems.positions[i], normals[i], stems.uvs.empty() ? Vec2(0) : stems.uvs[i]);
    for (size_t i = 0; i < leaves.size(); ++i) {
      const Vec3 n = leaf_normal(leaves, i);
      for (size_t k = 0; k < 4; ++k) vertex(leaves.corners[4 * i + k], n, kLeafUvs[k]);
    }
    for (const glm::uvec3& t : stems.triangles) {
      w.put_le(uint8_t{3});
      for (int k = 0; k < 3; ++k) w.put_le(static_cast<int32_t>(t[k]));
      w.put_le(uint8_t{255});
      w.maybe_flush();
    }
    const auto ns = static_cast<int32_t>(stems.positions.size());
    for (size_t i = 0; i < leaves.size(); ++i) {
      w.put_le(uint8_t{4});
      for (int32_t k = 0; k < 4; ++k) w.put_le(static_cast<int32_t>(ns + 4 * static_cast<int32_t>(i) + k));
      w.put_le(static_cast<uint8_t>(leaves.shapes[i]));
      w.maybe_flush();
    }
  });
}

}  // namespace sylva
