// Wavefront OBJ reader: a single pass over the file's bytes with std::from_chars.

#include "core/error.h"
#include "geometry/mesh_io_detail.h"

#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace sylva::mesh_io_detail {

namespace {

constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();

struct Corner {
  uint32_t v = kNone;
  uint32_t vt = kNone;
  uint32_t vn = kNone;
};

inline bool is_blank(char c) { return c == ' ' || c == '\t'; }
inline bool is_eol(char c) { return c == '\n' || c == '\r'; }

class ObjParser {
 public:
  ObjParser(const std::filesystem::path& file, std::string_view text)
      : file_(file), p_(text.data()), end_(text.data() + text.size()) {}

  TriangleMesh parse() {
    reserve();
    while (p_ < end_) {
      skip_blanks();
      if (p_ == end_) break;
      if (is_eol(*p_) || *p_ == '#') {
        skip_line();
        continue;
      }
      const char* kw = p_;
      while (p_ < end_ && !is_blank(*p_) && !is_eol(*p_)) ++p_;
      const std::string_view keyword(kw, static_cast<size_t>(p_ - kw));
      if (keyword == "v") {
        parse_vertex();
      } else if (keyword == "vt") {
        parse_texcoord();
      } else if (keyword == "vn") {
        Vec3 n;
        n.x = number("a normal x after 'vn'");
        n.y = number("a normal y after 'vn'");
        n.z = number("a normal z after 'vn'");
        end_of_statement("vn");
        vn_.push_back(n);
      } else if (keyword == "f") {
        parse_face();
      } else if (keyword == "o" || keyword == "g" || keyword == "usemtl" || keyword == "mtllib" || keyword == "s" ||
                 keyword == "l" || keyword == "p" || keyword == "vp") {
        skip_line();
        continue;
      } else {
        fail("unknown OBJ statement " + printable(keyword) + " (expected v, vt, vn, f, o, g, s, usemtl, mtllib or #)");
      }
      skip_line();
    }
    return build();
  }

 private:
  // Reserves the arrays from statement counts in evenly spread samples of the file (all of it
  // when small), so a file of millions of triangles grows its arrays about once instead of
  // reallocating repeatedly. Over-estimates only reserve untouched address space.
  void reserve() {
    constexpr size_t kChunks = 64;
    constexpr size_t kChunkBytes = 8192;
    const auto size = static_cast<size_t>(end_ - p_);
    const bool whole = size <= kChunks * kChunkBytes;
    std::array<size_t, 4> n{};  // v, vt, vn, f
    size_t sampled = 0;
    for (size_t c = 0; c < (whole ? 1 : kChunks); ++c) {
      const char* q = whole ? p_ : p_ + c * (size / kChunks);
      const char* stop = whole ? end_ : q + kChunkBytes;
      sampled += static_cast<size_t>(stop - q);
      bool line_start = whole && c == 0;
      for (; q + 1 < stop; ++q) {
        if (line_start) {
          if (q[0] == 'v') {
            n[0] += is_blank(q[1]);
            n[1] += q[1] == 't';
            n[2] += q[1] == 'n';
          }
          n[3] += q[0] == 'f' && is_blank(q[1]);
        }
        line_start = q[0] == '\n';
      }
    }
    const double scale = whole ? 1.0 : 1.1 * static_cast<double>(size) / static_cast<double>(sampled);
    auto estimate = [&](size_t k) { return static_cast<size_t>(static_cast<double>(n[k]) * scale) + 16; };
    v_.reserve(estimate(0));
    vt_.reserve(estimate(1));
    vn_.reserve(estimate(2));
    tri_v_.reserve(estimate(3));
  }

  [[noreturn]] void fail(const std::string& what) const { throw ParseError(file_, line_, what); }

  void skip_blanks() {
    while (p_ < end_ && is_blank(*p_)) ++p_;
  }

  // Skips to just past the end of the current line, counting it.
  void skip_line() {
    while (p_ < end_ && *p_ != '\n') ++p_;
    if (p_ < end_) {
      ++p_;
      ++line_;
    }
  }

  bool at_statement_end() const { return p_ == end_ || is_eol(*p_) || *p_ == '#'; }

  void end_of_statement(std::string_view keyword) {
    skip_blanks();
    if (!at_statement_end())
      fail("unexpected " + printable(token_here()) + " at the end of the '" + std::string(keyword) + "' statement");
  }

  std::string_view token_here() const {
    const char* q = p_;
    while (q < end_ && !is_blank(*q) && !is_eol(*q)) ++q;
    return {p_, static_cast<size_t>(q - p_)};
  }

  bool has_more_on_line() {
    skip_blanks();
    return !at_statement_end();
  }

  float number(const char* what) {
    skip_blanks();
    if (at_statement_end()) fail(std::string("expected ") + what + ", found end of line");
    const char* start = p_;
    if (*p_ == '+') ++p_;
    float value = 0.0f;
    const auto [next, ec] = std::from_chars(p_, end_, value);
    if (ec != std::errc() || (next < end_ && !is_blank(*next) && !is_eol(*next)) || !std::isfinite(value)) {
      p_ = start;
      fail(std::string("expected ") + what + ", found " + printable(token_here()));
    }
    p_ = next;
    return value;
  }

  void parse_vertex() {
    Vec3 v;
    v.x = number("a vertex x after 'v'");
    v.y = number("a vertex y after 'v'");
    v.z = number("a vertex z after 'v'");
    // Optional w, or r g b vertex colours: read and ignored.
    for (int extra = 0; extra < 3 && has_more_on_line(); ++extra) number("a number after 'v x y z'");
    end_of_statement("v");
    v_.push_back(v);
  }

  void parse_texcoord() {
    Vec2 t;
    t.x = number("a texture u after 'vt'");
    t.y = has_more_on_line() ? number("a texture v after 'vt u'") : 0.0f;
    if (has_more_on_line()) number("a texture w after 'vt u v'");
    end_of_statement("vt");
    vt_.push_back(t);
  }

  // An OBJ index (1-based, negative relative) into a list of `count` elements.
  uint32_t index(size_t count, const char* what) {
    // Hand-rolled: faces are most of an OBJ file. At most 18 digits, so no overflow.
    const char* start = p_;
    const bool negative = p_ < end_ && *p_ == '-';
    const char* q = p_ + (negative ? 1 : 0);
    const char* digits = q;
    int64_t i = 0;
    while (q < end_ && static_cast<unsigned>(*q - '0') < 10u && q - digits < 18) i = 10 * i + (*q++ - '0');
    if (q == digits || (q < end_ && static_cast<unsigned>(*q - '0') < 10u))
      fail(std::string("expected a ") + what + " index in the face, found " + printable(token_here()));
    if (negative) i = -i;
    p_ = q;
    const int64_t n = static_cast<int64_t>(count);
    int64_t resolved = -1;
    if (i > 0 && i <= n) resolved = i - 1;
    if (i < 0 && -i <= n) resolved = n + i;
    if (resolved < 0) {
      p_ = start;
      fail(std::string(what) + " index " + std::to_string(i) + " out of range (" + std::to_string(count) +
           " defined so far; OBJ indices start at 1)");
    }
    return static_cast<uint32_t>(resolved);
  }

  Corner corner() {
    Corner c;
    c.v = index(v_.size(), "vertex");
    if (p_ < end_ && *p_ == '/') {
      ++p_;
      if (p_ < end_ && *p_ != '/') c.vt = index(vt_.size(), "texture coordinate");
      if (p_ < end_ && *p_ == '/') {
        ++p_;
        c.vn = index(vn_.size(), "normal");
      }
    }
    if (p_ < end_ && !is_blank(*p_) && !is_eol(*p_) && *p_ != '#')
      fail("expected a face corner v, v/vt, v//vn or v/vt/vn, found " + printable(token_here()));
    return c;
  }

  void parse_face() {
    polygon_.clear();
    while (has_more_on_line()) polygon_.push_back(corner());
    if (polygon_.size() < 3) fail("expected at least 3 vertices in the face, found " + std::to_string(polygon_.size()));
    for (const Corner& c : polygon_) {
      any_vt_ |= c.vt != kNone;
      all_vt_ &= c.vt != kNone;
      any_vn_ |= c.vn != kNone;
      all_vn_ &= c.vn != kNone;
    }
    // Texture and normal index streams exist only once some corner uses them.
    if (any_vt_ && tri_vt_.size() < tri_v_.size()) tri_vt_.resize(tri_v_.size(), glm::uvec3(kNone));
    if (any_vn_ && tri_vn_.size() < tri_v_.size()) tri_vn_.resize(tri_v_.size(), glm::uvec3(kNone));
    const Corner& c0 = polygon_[0];
    for (size_t i = 1; i + 1 < polygon_.size(); ++i) {  // fan
      const Corner& c1 = polygon_[i];
      const Corner& c2 = polygon_[i + 1];
      tri_v_.push_back({c0.v, c1.v, c2.v});
      if (any_vt_) tri_vt_.push_back({c0.vt, c1.vt, c2.vt});
      if (any_vn_) tri_vn_.push_back({c0.vn, c1.vn, c2.vn});
    }
  }

  TriangleMesh build() {
    TriangleMesh mesh;
    const bool use_vt = any_vt_ && all_vt_;
    const bool use_vn = any_vn_ && all_vn_;
    if (!use_vt && !use_vn) {  // positions only: keep the file's vertex list as is
      mesh.positions = std::move(v_);
      mesh.triangles = std::move(tri_v_);
      return mesh;
    }
    // One output vertex per distinct (v, vt, vn). The first combination seen for position v keeps
    // index v, so files whose corners use one index for all three keep their vertex order; further
    // combinations are appended and chained from v.
    const size_t nv = v_.size();
    std::vector<Corner> variant(nv);
    std::vector<uint32_t> next(nv, kNone);
    std::vector<uint8_t> claimed(nv, 0);
    mesh.positions = std::move(v_);
    if (use_vt) mesh.uvs.assign(nv, Vec2(0));
    if (use_vn) mesh.normals.assign(nv, Vec3(0, 0, 1));
    auto vertex_of = [&](Corner c) -> uint32_t {
      auto set_attributes = [&](uint32_t k) {
        if (use_vt) mesh.uvs[k] = vt_[c.vt];
        if (use_vn) mesh.normals[k] = vn_[c.vn];
      };
      if (!claimed[c.v]) {
        claimed[c.v] = 1;
        variant[c.v] = c;
        set_attributes(c.v);
        return c.v;
      }
      for (uint32_t k = c.v; k != kNone; k = next[k])
        if (variant[k].vt == c.vt && variant[k].vn == c.vn) return k;
      const auto k = static_cast<uint32_t>(mesh.positions.size());
      mesh.positions.push_back(mesh.positions[c.v]);
      if (use_vt) mesh.uvs.emplace_back();
      if (use_vn) mesh.normals.emplace_back();
      set_attributes(k);
      variant.push_back(c);
      next.push_back(next[c.v]);
      next[c.v] = k;
      return k;
    };
    mesh.triangles.resize(tri_v_.size());
    for (size_t t = 0; t < tri_v_.size(); ++t)
      for (int k = 0; k < 3; ++k)
        mesh.triangles[t][k] =
            vertex_of({tri_v_[t][k], use_vt ? tri_vt_[t][k] : kNone, use_vn ? tri_vn_[t][k] : kNone});
    return mesh;
  }

  const std::filesystem::path& file_;
  const char* p_;
  const char* end_;
  int line_ = 1;
  std::vector<Vec3> v_;
  std::vector<Vec3> vn_;
  std::vector<Vec2> vt_;
  std::vector<glm::uvec3> tri_v_;   // per triangle: position indices
  std::vector<glm::uvec3> tri_vt_;  // texture-coordinate indices (kNone where absent)
  std::vector<glm::uvec3> tri_vn_;  // normal indices (kNone where absent)
  std::vector<Corner> polygon_;
  bool any_vt_ = false, all_vt_ = true, any_vn_ = false, all_vn_ = true;
};

}  // namespace

TriangleMesh parse_obj(const std::filesystem::path& file, std::string_view text) {
  return ObjParser(file, text).parse();
}

}  // namespace sylva::mesh_io_detail
