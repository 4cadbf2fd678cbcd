// PLY reader (Turk 1994 format): ascii, binary little- and big-endian.

#include "core/error.h"
#include "geometry/mesh_io_detail.h"

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace sylva::mesh_io_detail {

namespace {

enum class PlyType : uint8_t { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };
enum class PlyFormat : uint8_t { Ascii, BinaryLittle, BinaryBig };

std::optional<PlyType> ply_type_from_name(std::string_view s) {
  if (s == "char" || s == "int8") return PlyType::Int8;
  if (s == "uchar" || s == "uint8") return PlyType::UInt8;
  if (s == "short" || s == "int16") return PlyType::Int16;
  if (s == "ushort" || s == "uint16") return PlyType::UInt16;
  if (s == "int" || s == "int32") return PlyType::Int32;
  if (s == "uint" || s == "uint32") return PlyType::UInt32;
  if (s == "float" || s == "float32") return PlyType::Float32;
  if (s == "double" || s == "float64") return PlyType::Float64;
  return std::nullopt;
}

size_t ply_type_size(PlyType t) {
  switch (t) {
    case PlyType::Int8:
    case PlyType::UInt8:
      return 1;
    case PlyType::Int16:
    case PlyType::UInt16:
      return 2;
    case PlyType::Int32:
    case PlyType::UInt32:
    case PlyType::Float32:
      return 4;
    case PlyType::Float64:
      return 8;
  }
  return 1;
}

bool ply_type_is_integer(PlyType t) { return t != PlyType::Float32 && t != PlyType::Float64; }

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::Float32;
  bool is_list = false;
  PlyType count_type = PlyType::UInt8;
};

struct PlyElement {
  std::string name;
  uint64_t count = 0;
  std::vector<PlyProperty> properties;
  int line = 0;
};

struct PlyHeader {
  PlyFormat format = PlyFormat::Ascii;
  std::vector<PlyElement> elements;
  size_t data_offset = 0;  // first byte after end_header's newline
  int data_line = 1;       // line number of the first data line (ascii)
};

std::vector<std::string_view> split_words(std::string_view line) {
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

PlyHeader parse_header(const std::filesystem::path& file, std::string_view bytes) {
  PlyHeader h;
  size_t pos = 0;
  int line = 0;
  bool have_format = false;
  auto next_line = [&]() -> std::optional<std::string_view> {
    if (pos >= bytes.size()) return std::nullopt;
    const size_t nl = bytes.find('\n', pos);
    const size_t stop = nl == std::string_view::npos ? bytes.size() : nl;
    std::string_view l = bytes.substr(pos, stop - pos);
    if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
    pos = nl == std::string_view::npos ? bytes.size() : nl + 1;
    ++line;
    return l;
  };
  const auto magic = next_line();
  if (!magic || *magic != "ply") throw ParseError(file, 1, "expected the PLY magic line 'ply'");
  while (true) {
    const auto l = next_line();
    if (!l) throw ParseError(file, line, "expected 'end_header' before the end of the file");
    const auto w = split_words(*l);
    if (w.empty()) continue;
    if (w[0] == "end_header") break;
    if (w[0] == "comment" || w[0] == "obj_info") continue;
    if (w[0] == "format") {
      if (w.size() != 3) throw ParseError(file, line, "expected 'format <type> 1.0'");
      if (w[1] == "ascii")
        h.format = PlyFormat::Ascii;
      else if (w[1] == "binary_little_endian")
        h.format = PlyFormat::BinaryLittle;
      else if (w[1] == "binary_big_endian")
        h.format = PlyFormat::BinaryBig;
      else
        throw ParseError(file, line,
                         "expected format ascii, binary_little_endian or "
                         "binary_big_endian, found " +
                             printable(w[1]));
      have_format = true;
    } else if (w[0] == "element") {
      PlyElement e;
      if (w.size() != 3) throw ParseError(file, line, "expected 'element <name> <count>'");
      e.name = std::string(w[1]);
      const auto [p, ec] = std::from_chars(w[2].data(), w[2].data() + w[2].size(), e.count);
      if (ec != std::errc() || p != w[2].data() + w[2].size())
        throw ParseError(file, line, "expected a non-negative element count, found " + printable(w[2]));
      e.line = line;
      h.elements.push_back(std::move(e));
    } else if (w[0] == "property") {
      if (h.elements.empty()) throw ParseError(file, line, "expected an 'element' line before 'property'");
      PlyProperty prop;
      if (w.size() == 5 && w[1] == "list") {
        const auto ct = ply_type_from_name(w[2]);
        const auto it = ply_type_from_name(w[3]);
        if (!ct || !ply_type_is_integer(*ct))
          throw ParseError(file, line, "expected an integer list count type, found " + printable(w[2]));
        if (!it) throw ParseError(file, line, "expected a PLY type, found " + printable(w[3]));
        prop.is_list = true;
        prop.count_type = *ct;
        prop.type = *it;
        prop.name = std::string(w[4]);
      } else if (w.size() == 3) {
        const auto t = ply_type_from_name(w[1]);
        if (!t) throw ParseError(file, line, "expected a PLY type, found " + printable(w[1]));
        prop.type = *t;
        prop.name = std::string(w[2]);
      } else {
        throw ParseError(file, line,
                         "expected 'property <type> <name>' or "
                         "'property list <count type> <type> <name>'");
      }
      h.elements.back().properties.push_back(std::move(prop));
    } else {
      throw ParseError(file, line,
                       "unknown PLY header line " + printable(w[0]) +
                           " (expected format, element, property, comment or end_header)");
    }
  }
  if (!have_format) throw ParseError(file, line, "expected a 'format' line in the PLY header");
  h.data_offset = pos;
  h.data_line = line + 1;
  return h;
}

// Names a value for error messages ("x of vertex 12"); the string is built only on failure.
struct ValueName {
  const char* part;
  std::string_view property;
  std::string_view element;
  uint64_t index;
  std::string str() const {
    return std::string(part) + std::string(property) + " of " + std::string(element) + " " + std::to_string(index);
  }
};

// Reads the values of the data section, one at a time, as double (exact for every PLY type).
class PlyData {
 public:
  PlyData(const std::filesystem::path& file, std::string_view bytes, const PlyHeader& h)
      : file_(file), bytes_(bytes), pos_(h.data_offset), format_(h.format), line_(h.data_line) {}

  bool ascii() const { return format_ == PlyFormat::Ascii; }
  size_t remaining() const { return bytes_.size() - pos_; }

  double read(PlyType t, const ValueName& what) { return ascii() ? read_ascii(t, what) : read_binary(t, what); }

  // Skips n binary values of type t, or n ascii tokens.
  void skip(PlyType t, uint64_t n, const ValueName& what) {
    if (ascii()) {
      for (uint64_t i = 0; i < n; ++i) read_ascii(t, what);
      return;
    }
    const size_t size = ply_type_size(t);
    if (n > remaining() / size) truncated(what);
    pos_ += static_cast<size_t>(n) * size;
  }

  // The ascii data must end after the last element; binary trailing bytes are ignored.
  void finish() {
    if (!ascii()) return;
    skip_space();
    if (pos_ < bytes_.size()) fail("unexpected " + printable(token()) + " after the last PLY element");
  }

  [[noreturn]] void fail(const std::string& what) const {
    if (ascii()) throw ParseError(file_, line_, what);
    throw ParseError(file_, 0, "at byte " + std::to_string(pos_) + ": " + what);
  }

 private:
  [[noreturn]] void truncated(const ValueName& what) const {
    throw ParseError(file_, 0,
                     "truncated binary PLY data at byte " + std::to_string(pos_) + " of " +
                         std::to_string(bytes_.size()) + ": expected " + what.str());
  }

  void skip_space() {
    while (pos_ < bytes_.size()) {
      const char c = bytes_[pos_];
      if (c == '\n')
        ++line_;
      else if (c != ' ' && c != '\t' && c != '\r')
        break;
      ++pos_;
    }
  }

  std::string_view token() const {
    size_t q = pos_;
    while (q < bytes_.size() && bytes_[q] != ' ' && bytes_[q] != '\t' && bytes_[q] != '\r' && bytes_[q] != '\n') ++q;
    return bytes_.substr(pos_, q - pos_);
  }

  double read_ascii(PlyType t, const ValueName& what) {
    skip_space();
    if (pos_ >= bytes_.size()) fail("expected " + what.str() + ", found the end of the file");
    const std::string_view tok = token();
    const char* first = tok.data();
    const char* last = tok.data() + tok.size();
    if (first < last && *first == '+') ++first;
    double value = 0;
    bool ok = false;
    if (ply_type_is_integer(t)) {
      int64_t i = 0;
      const auto [p, ec] = std::from_chars(first, last, i);
      ok = ec == std::errc() && p == last;
      value = static_cast<double>(i);
      if (ok) ok = in_range(t, value);
    } else {
      const auto [p, ec] = std::from_chars(first, last, value);
      ok = ec == std::errc() && p == last && std::isfinite(value);
    }
    if (!ok) fail("expected " + what.str() + ", found " + printable(tok));
    pos_ += tok.size();
    return value;
  }

  static bool in_range(PlyType t, double v) {
    switch (t) {
      case PlyType::Int8:
        return v >= -128 && v <= 127;
      case PlyType::UInt8:
        return v >= 0 && v <= 255;
      case PlyType::Int16:
        return v >= -32768 && v <= 32767;
      case PlyType::UInt16:
        return v >= 0 && v <= 65535;
      case PlyType::Int32:
        return v >= -2147483648.0 && v <= 2147483647.0;
      case PlyType::UInt32:
        return v >= 0 && v <= 4294967295.0;
      default:
        return true;
    }
  }

  template <typename T>
  T load() {
    std::array<unsigned char, sizeof(T)> raw;
    std::memcpy(raw.data(), bytes_.data() + pos_, sizeof(T));
    const bool file_little = format_ == PlyFormat::BinaryLittle;
    if (file_little != (std::endian::native == std::endian::little)) std::reverse(raw.begin(), raw.end());
    T value;
    std::memcpy(&value, raw.data(), sizeof(T));
    pos_ += sizeof(T);
    return value;
  }

  double read_binary(PlyType t, const ValueName& what) {
    if (ply_type_size(t) > remaining()) truncated(what);
    double v = 0;
    switch (t) {
      case PlyType::Int8:
        v = load<int8_t>();
        break;
      case PlyType::UInt8:
        v = load<uint8_t>();
        break;
      case PlyType::Int16:
        v = load<int16_t>();
        break;
      case PlyType::UInt16:
        v = load<uint16_t>();
        break;
      case PlyType::Int32:
        v = load<int32_t>();
        break;
      case PlyType::UInt32:
        v = load<uint32_t>();
        break;
      case PlyType::Float32:
        v = load<float>();
        break;
      case PlyType::Float64:
        v = load<double>();
        break;
    }
    return v;
  }

  const std::filesystem::path& file_;
  std::string_view bytes_;
  size_t pos_;
  PlyFormat format_;
  int line_;
};

int find_property(const PlyElement& e, std::string_view name) {
  for (size_t i = 0; i < e.properties.size(); ++i)
    if (e.properties[i].name == name && !e.properties[i].is_list) return static_cast<int>(i);
  return -1;
}

// Which vertex property feeds which attribute slot: x y z, nx ny nz, u v.
struct VertexSlots {
  std::array<int, 8> slot;
  bool has_normals = false;
  bool has_uvs = false;
};

// The vertex element's slots: x, y and z required, normals and a uv pair (four spellings) if all there.
VertexSlots vertex_slots(const std::filesystem::path& file, const PlyElement& vertex) {
  VertexSlots vs;
  std::array<int, 8>& slot = vs.slot;
  slot.fill(-1);
  const std::array<const char*, 6> xyz_n{"x", "y", "z", "nx", "ny", "nz"};
  for (size_t s = 0; s < xyz_n.size(); ++s) slot[s] = find_property(vertex, xyz_n[s]);
  if (slot[0] < 0 || slot[1] < 0 || slot[2] < 0)
    throw ParseError(file, vertex.line, "expected scalar properties x, y and z in 'element vertex'");
  vs.has_normals = slot[3] >= 0 && slot[4] >= 0 && slot[5] >= 0;
  for (const auto& [u, v] : {std::pair{"u", "v"}, std::pair{"s", "t"}, std::pair{"texture_u", "texture_v"},
                             std::pair{"texture_s", "texture_t"}}) {
    if (vs.has_uvs) break;
    slot[6] = find_property(vertex, u);
    slot[7] = find_property(vertex, v);
    vs.has_uvs = slot[6] >= 0 && slot[7] >= 0;
  }
  return vs;
}

// The index of the face element's vertex-index list, checked to be of an integer type.
int face_index_list(const std::filesystem::path& file, const PlyElement& e) {
  int index_list = -1;
  for (size_t i = 0; i < e.properties.size(); ++i)
    if (e.properties[i].is_list && (e.properties[i].name == "vertex_indices" || e.properties[i].name == "vertex_index"))
      index_list = static_cast<int>(i);
  if (index_list < 0) throw ParseError(file, e.line, "expected a list property 'vertex_indices' in 'element face'");
  if (!ply_type_is_integer(e.properties[static_cast<size_t>(index_list)].type))
    throw ParseError(file, e.line, "expected an integer type for the face vertex indices");
  return index_list;
}

// Reads the data section's elements into a mesh.
struct PlyMeshReader {
  PlyData& data;
  const PlyElement* vertex;
  VertexSlots slots;
  uint64_t vertex_count;
  TriangleMesh mesh;
  std::vector<uint32_t> polygon;

  // Face k's polygon of n vertex indices (list property `prop` of element e), fanned into triangles.
  void read_polygon(const PlyElement& e, const PlyProperty& prop, uint64_t k, uint64_t n) {
    if (n < 3)
      data.fail("expected at least 3 vertex indices in " + e.name + " " + std::to_string(k) + ", found " +
                std::to_string(n));
    polygon.clear();
    for (uint64_t j = 0; j < n; ++j) {
      const double idx = data.read(prop.type, ValueName{"a vertex index in ", prop.name, e.name, k});
      if (idx < 0 || idx >= static_cast<double>(vertex_count))
        data.fail("vertex index " + std::to_string(static_cast<int64_t>(idx)) + " in " + e.name + " " +
                  std::to_string(k) + " out of range (" + std::to_string(vertex_count) + " vertices)");
      polygon.push_back(static_cast<uint32_t>(idx));
    }
    for (size_t j = 1; j + 1 < polygon.size(); ++j) mesh.triangles.push_back({polygon[0], polygon[j], polygon[j + 1]});
  }

  // Instance k of element e: its properties in order, a vertex's into `values` by slot.
  void read_instance(const PlyElement& e, uint64_t k, int index_list, std::array<double, 8>& values) {
    const bool is_vertex = &e == vertex;
    for (size_t pi = 0; pi < e.properties.size(); ++pi) {
      const PlyProperty& prop = e.properties[pi];
      auto what = [&](const char* part) { return ValueName{part, prop.name, e.name, k}; };
      if (prop.is_list) {
        const double count = data.read(prop.count_type, what("the list length of "));
        if (count < 0) data.fail("expected a non-negative list length for " + what("").str());
        const auto n = static_cast<uint64_t>(count);
        if (static_cast<int>(pi) != index_list) {
          data.skip(prop.type, n, what("the items of "));
          continue;
        }
        read_polygon(e, prop, k, n);
        continue;
      }
      const double v = data.read(prop.type, what(""));
      if (!is_vertex) continue;
      for (size_t s = 0; s < slots.slot.size(); ++s) {
        if (slots.slot[s] != static_cast<int>(pi)) continue;
        if (!std::isfinite(static_cast<float>(v))) data.fail("expected a finite float value for " + what("").str());
        values[s] = v;
      }
    }
  }

  // Every instance of element e; `reserve_cap` bounds what its count may reserve.
  void read_element(const std::filesystem::path& file, const PlyElement& e, uint64_t reserve_cap) {
    if (e.properties.empty()) return;  // nothing stored per instance
    const bool is_vertex = &e == vertex;
    const bool is_face = e.name == "face";
    const int index_list = is_face ? face_index_list(file, e) : -1;
    if (is_vertex) {
      const size_t n = static_cast<size_t>(std::min(e.count, reserve_cap));
      mesh.positions.reserve(n);
      if (slots.has_normals) mesh.normals.reserve(n);
      if (slots.has_uvs) mesh.uvs.reserve(n);
    }
    if (is_face) mesh.triangles.reserve(static_cast<size_t>(std::min(e.count, reserve_cap)));
    std::array<double, 8> values{};
    for (uint64_t k = 0; k < e.count; ++k) {
      read_instance(e, k, index_list, values);
      if (is_vertex) {
        auto f = [&](size_t s) { return static_cast<float>(values[s]); };
        mesh.positions.push_back({f(0), f(1), f(2)});
        if (slots.has_normals) mesh.normals.push_back({f(3), f(4), f(5)});
        if (slots.has_uvs) mesh.uvs.push_back({f(6), f(7)});
      }
    }
  }
};

}  // namespace

TriangleMesh parse_ply(const std::filesystem::path& file, std::string_view bytes) {
  const PlyHeader h = parse_header(file, bytes);

  const PlyElement* vertex = nullptr;
  for (const PlyElement& e : h.elements)
    if (e.name == "vertex") vertex = &e;
  if (vertex == nullptr) throw ParseError(file, 0, "expected an 'element vertex' in the PLY header");
  const VertexSlots slots = vertex_slots(file, *vertex);
  const uint64_t vertex_count = vertex->count;
  if (vertex_count > std::numeric_limits<uint32_t>::max())
    throw ParseError(file, vertex->line, "expected at most 2^32 - 1 vertices");

  PlyData data(file, bytes, h);
  PlyMeshReader reader{data, vertex, slots, vertex_count, {}, {}};
  // No value takes less than one byte, so the data size bounds what a count can honestly claim.
  const uint64_t reserve_cap = data.remaining();
  for (const PlyElement& e : h.elements) reader.read_element(file, e, reserve_cap);
  data.finish();
  return std::move(reader.mesh);
}

}  // namespace sylva::mesh_io_detail
