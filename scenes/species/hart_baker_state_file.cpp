#include "scenes/species/hart_baker_state_file.h"

#include "core/error.h"

#include <fmt/core.h>

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <vector>

namespace sylva {

namespace {

constexpr std::string_view kMagic = "sylva-hart-baker-state";

std::vector<std::string_view> split(std::string_view line) {
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    const size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
  return out;
}

struct LineReader {
  const std::filesystem::path& file;
  int line;
  [[noreturn]] void fail(const std::string& what) const { throw ParseError(file, line, what); }
  float real(std::string_view s) const {
    float v = 0.0f;
    const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || ptr != s.data() + s.size() || !std::isfinite(v))
      fail(fmt::format("expected a number, got \"{}\"", s));
    return v;
  }
  int64_t integer(std::string_view s, int64_t lo, int64_t hi) const {
    int64_t v = 0;
    const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || ptr != s.data() + s.size() || v < lo || v > hi)
      fail(fmt::format("expected a whole number in [{}, {}], got \"{}\"", lo, hi, s));
    return v;
  }
  Vec3 vec3(const std::vector<std::string_view>& f, size_t at) const {
    return Vec3(real(f[at]), real(f[at + 1]), real(f[at + 2]));
  }
};

}  // namespace

HartBakerStateFile parse_hart_baker_state(const std::string& text, const std::filesystem::path& file) {
  HartBakerStateFile out;
  HartBakerTree& t = out.tree;
  std::istringstream in(text);
  std::string raw;
  int line = 0;
  bool have_magic = false, have_species = false, have_seed = false, have_year = false;
  while (std::getline(in, raw)) {
    ++line;
    const LineReader r{file, line};
    const std::vector<std::string_view> f = split(raw);
    if (f.empty() || f[0].front() == '#') continue;
    if (!have_magic) {
      if (f.size() != 2 || f[0] != kMagic || f[1] != "1")
        r.fail(fmt::format("not a Hart-Baker state file (expected \"{} 1\")", kMagic));
      have_magic = true;
      continue;
    }
    const std::string_view key = f[0];
    if (key == "species") {
      if (f.size() < 2) r.fail("species: expected a path");
      const size_t start = raw.find("species") + 7;
      std::string path = raw.substr(start);
      path.erase(0, path.find_first_not_of(" \t"));
      path.erase(path.find_last_not_of(" \t\r") + 1);
      out.species = path;
      have_species = true;
    } else if (key == "seed") {
      if (f.size() != 2) r.fail("seed: expected one whole number");
      t.seed = static_cast<uint64_t>(r.integer(f[1], 0, INT64_MAX));
      have_seed = true;
    } else if (key == "year") {
      if (f.size() != 2) r.fail("year: expected one whole number");
      t.year = static_cast<int>(r.integer(f[1], 0, 100000));
      have_year = true;
    } else if (key == "limb") {
      if (f.size() != 18) r.fail(fmt::format("limb: expected 17 values, got {}", f.size() - 1));
      const int32_t id = static_cast<int32_t>(t.size());
      const int64_t parent = r.integer(f[1], -1, id - 1);
      if ((id == 0) != (parent == -1)) r.fail("limb: the first limb (the trunk) and only it has parent -1");
      t.parent.push_back(static_cast<int32_t>(parent));
      t.order.push_back(static_cast<uint8_t>(r.integer(f[2], 0, 255)));
      t.alive.push_back(static_cast<uint8_t>(r.integer(f[3], 0, 1)));
      t.born.push_back(static_cast<int32_t>(r.integer(f[4], 0, 100000)));
      t.base.push_back(r.vec3(f, 5));
      Vec3 dir = r.vec3(f, 8);
      if (std::abs(glm::length(dir) - 1.0f) > 1e-3f) r.fail("limb: the direction must be a unit vector");
      t.direction.push_back(dir);
      const float length = r.real(f[11]), radius = r.real(f[12]);
      if (!(length >= 0.0f) || !(radius > 0.0f)) r.fail("limb: length must be ≥ 0 and radius > 0");
      t.length_m.push_back(length);
      t.radius_m.push_back(radius);
      t.apex.push_back(static_cast<int32_t>(r.integer(f[13], -1, INT32_MAX)));
      t.lit.push_back(r.real(f[14]));
      t.reaction_m.push_back(r.vec3(f, 15));
      t.ring_radius_m.emplace_back();
      t.ring_length_m.emplace_back();
      t.ring_offset_m.emplace_back();
    } else if (key == "ring") {
      if (t.size() == 0) r.fail("ring before any limb");
      if (f.size() != 6) r.fail(fmt::format("ring: expected 5 values, got {}", f.size() - 1));
      t.ring_radius_m.back().push_back(r.real(f[1]));
      t.ring_length_m.back().push_back(r.real(f[2]));
      t.ring_offset_m.back().push_back(r.vec3(f, 3));
    } else {
      r.fail(fmt::format("unknown record \"{}\" (expected species, seed, year, limb or ring)", key));
    }
  }
  if (!have_magic) throw ParseError(file, 1, fmt::format("empty file (expected \"{} 1\")", kMagic));
  if (!have_species || !have_seed || !have_year || t.size() == 0)
    throw ParseError(file, line, "incomplete state: species, seed, year and at least one limb are required");
  return out;
}

HartBakerStateFile load_hart_baker_state(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw ParseError(file, 0, "cannot open state file");
  std::ostringstream ss;
  ss << in.rdbuf();
  HartBakerStateFile state = parse_hart_baker_state(ss.str(), file);
  if (!state.species.is_absolute()) state.species = file.parent_path() / state.species;
  return state;
}

std::string format_hart_baker_state(const HartBakerTree& t, const std::filesystem::path& species) {
  std::string s = fmt::format("{} 1\nspecies {}\nseed {}\nyear {}\n", kMagic, species.generic_string(), t.seed, t.year);
  for (size_t i = 0; i < t.size(); ++i) {
    const Vec3 b = t.base[i], d = t.direction[i], q = t.reaction_m[i];
    s += fmt::format(
        "limb {} {} {} {} {:.9g} {:.9g} {:.9g} {:.9g} {:.9g} {:.9g} {:.9g} {:.9g} {} {:.9g} {:.9g} {:.9g} {:.9g}\n",
        t.parent[i], t.order[i], t.alive[i], t.born[i], b.x, b.y, b.z, d.x, d.y, d.z, t.length_m[i], t.radius_m[i],
        t.apex[i], t.lit[i], q.x, q.y, q.z);
    if (!t.alive[i]) continue;  // a dead limb's rings are never read again
    for (size_t y = 0; y < t.ring_radius_m[i].size(); ++y) {
      const Vec3 o = t.ring_offset_m[i][y];
      s += fmt::format("ring {:.9g} {:.9g} {:.9g} {:.9g} {:.9g}\n", t.ring_radius_m[i][y], t.ring_length_m[i][y], o.x,
                       o.y, o.z);
    }
  }
  return s;
}

}  // namespace sylva
