#include "scenes/sections/scene_builder.h"

#include "core/error.h"
#include "core/hash.h"
#include "core/input_file.h"
#include "scenes/sections/tree_variant_cache.h"

#include <fmt/core.h>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <tuple>

namespace sylva {

uint64_t hash_text(std::string_view text) { return mix64(fnv1a64(text)); }

SceneBuilder::SceneBuilder(const Params& root, const SceneOptions& options)
    : root_(root), options_(options), tree_variants_(std::make_unique<TreeVariantCache>(*this)) {
  // `--res` replaces [render] width and height (read first, so every later section sees it).
  if (options_.resolution) std::tie(out_.render.width, out_.render.height) = *options_.resolution;
}

SceneBuilder::~SceneBuilder() = default;

uint32_t SceneBuilder::add_material(const std::string& name, Material material) {
  const uint32_t id = out_.scene.add_material(name, std::move(material));
  material_ids_[name] = id;
  return id;
}

std::optional<uint32_t> SceneBuilder::find_material(const std::string& name) const {
  auto it = material_ids_.find(name);
  if (it == material_ids_.end()) return std::nullopt;
  return it->second;
}

uint32_t SceneBuilder::material_ref(const Params& t, const char* key) const {
  const std::string name = t.string(key);
  auto it = material_ids_.find(name);
  if (it == material_ids_.end()) {
    std::string known;
    for (const auto& [k, v] : material_ids_) known += (known.empty() ? "" : ", ") + k;
    t.fail(key, "unknown material '" + name + "' (defined: " + (known.empty() ? "none" : known) + ")");
  }
  return it->second;
}

uint32_t class_id_of(std::string_view name) {
  static const std::map<uint32_t, std::string> builtins = Scene().class_names;
  for (const auto& [id, builtin] : builtins)
    if (builtin == name) return id;
  return kFirstNamedClass + static_cast<uint32_t>(fnv1a64(name) % (kMaxClassId - kFirstNamedClass));
}

uint32_t SceneBuilder::class_of(const std::string& name, const Params& at, std::string_view key) {
  const uint32_t id = class_id_of(name);
  const auto [it, added] = out_.scene.class_names.emplace(id, name);
  if (!added && it->second != name)
    at.fail(key, fmt::format("class '{}' has the id {} of class '{}' (class ids are a hash of the name); rename one",
                             name, id, it->second));
  return id;
}

uint32_t SceneBuilder::variant_of(const std::string& key, VariantInfo info) {
  auto found = variant_ids_.find(key);
  if (found != variant_ids_.end()) return found->second;
  out_.variants.push_back(std::move(info));
  return variant_ids_[key] = static_cast<uint32_t>(out_.variants.size());
}

const Species& SceneBuilder::load_species_once(const std::filesystem::path& file) {
  auto sp = species_.find(file.string());
  if (sp == species_.end()) {
    const std::string text = read_input_file(file, kMaxSpeciesFileBytes, "species file");
    dependency_hash_ = hash_ids(dependency_hash_, hash_text(text));
    sp = species_.emplace(file.string(), parse_species(text, file)).first;
    out_.warnings.insert(out_.warnings.end(), sp->second.warnings.begin(), sp->second.warnings.end());
    // A TOML species naming a TREE-MAKER template depends on the template's text too.
    const auto* tm = std::get_if<TreeMakerTemplate>(&sp->second.model);
    if (tm != nullptr && tm->source != file) {
      dependency_hash_ =
          hash_ids(dependency_hash_, hash_text(read_input_file(tm->source, kMaxSpeciesFileBytes, "template file")));
    }
  }
  return sp->second;
}

Mat4 read_transform(const Params& t) {
  const Vec3 translate = t.vec3("translate", Vec3(0.0f));
  const Vec3 rotate = t.vec3("rotate", Vec3(0.0f));
  Vec3 scale(1.0f);
  if (const ParamValue* s = t.get("scale")) {
    scale = s->is_number() ? Vec3(static_cast<float>(s->number())) : t.vec3("scale", scale);
    if (scale.x <= 0 || scale.y <= 0 || scale.z <= 0) t.fail("scale", "scale must be positive");
  }
  Mat4 m = glm::translate(Mat4(1.0f), translate);
  m = glm::rotate(m, radians(rotate.z), Vec3(0, 0, 1));
  m = glm::rotate(m, radians(rotate.y), Vec3(0, 1, 0));
  m = glm::rotate(m, radians(rotate.x), Vec3(1, 0, 0));
  return glm::scale(m, scale);
}

Vec2 read_range(const Params& t, const char* key, Vec2 fallback, double lo_limit, double hi_limit) {
  const ParamValue* v = t.get(key);
  if (v == nullptr) return fallback;
  const Vec2 r = v->is_number() ? Vec2(t.real(key, 0.0, lo_limit, hi_limit)) : t.vec2(key, fallback);
  if (!(r.x >= lo_limit && r.y <= hi_limit && r.x <= r.y))
    t.fail(key, fmt::format("{} = [min, max] needs {:g} <= min <= max <= {:g}", key, lo_limit, hi_limit));
  return r;
}

// `tile = [nx, ny]` (odd counts) repeats every placed copy on an nx × ny grid centred on itself,
// with the [plot]'s size as the spacing.
static std::vector<Vec3> tile_offsets(const Params& t, const PlotDesc& plot) {
  if (!t.has("tile")) return {Vec3(0.0f)};
  const std::vector<double> n = t.numbers("tile");
  if (n.size() != 2) t.fail("tile", "tile = [nx, ny] needs two counts");
  for (const double c : n)
    if (!(c >= 1 && c <= 99 && c == std::floor(c) && static_cast<int>(c) % 2 == 1))
      t.fail("tile", "tile counts must be odd whole numbers from 1 to 99 (the plot stays in the middle)");
  if (!plot.defined) t.fail("tile", "tile needs a [plot] with a size: the spacing of the copies");
  const Vec2 size = plot.hi - plot.lo;
  std::vector<Vec3> tiles;
  const int nx = static_cast<int>(n[0]), ny = static_cast<int>(n[1]);
  for (int j = -(ny / 2); j <= ny / 2; ++j)
    for (int i = -(nx / 2); i <= nx / 2; ++i)
      tiles.emplace_back(static_cast<float>(i) * size.x, static_cast<float>(j) * size.y, 0.0f);
  return tiles;
}

std::vector<SceneBuilder::Placed> SceneBuilder::placements(const Params& t, const std::vector<Vec3>& at) const {
  std::vector<Placed> out;
  const uint32_t object_id = static_cast<uint32_t>(t.integer("object_id", 0, 0, 1 << 24));
  const Mat4 base = read_transform(t);
  const std::vector<Vec3> tiles = tile_offsets(t, out_.scene.plot);
  const auto put = [&](const Mat4& m, uint32_t id) {
    for (const Vec3& tile : tiles)
      for (const Vec3& a : at)
        out.push_back({glm::translate(Mat4(1.0f), tile) * m * glm::translate(Mat4(1.0f), a), id});
  };
  if (t.has("instances")) {
    for (const Params* it : t.tables("instances")) {
      it->check_keys({"translate", "rotate", "scale", "object_id"});
      put(read_transform(*it) * base, static_cast<uint32_t>(it->integer("object_id", object_id, 0, 1 << 24)));
    }
  } else {
    put(base, object_id);
  }
  return out;
}

void SceneBuilder::place(const Params& t, uint32_t proto, uint32_t class_id, uint32_t variant_id,
                         const std::vector<Vec3>& at) {
  for (const Placed& c : placements(t, at))
    out_.scene.instances.push_back(Instance{proto, c.world_from_object, c.object_id, class_id, variant_id});
}

SceneFile SceneBuilder::finish() {
  if (camera_above_terrain && terrain) out_.camera_ground = std::make_shared<const HeightField>(*terrain);
  if (automatic_ranges_.empty()) return std::move(out_);
  const std::vector<Instance>& all = out_.scene.instances;
  uint64_t offset = 0;
  size_t pos = 0;
  for (const auto& [begin, end] : automatic_ranges_) {
    for (size_t i = pos; i < begin; ++i) offset = std::max<uint64_t>(offset, all[i].object_id);
    pos = end;
  }
  for (size_t i = pos; i < all.size(); ++i) offset = std::max<uint64_t>(offset, all[i].object_id);
  for (const auto& [begin, end] : automatic_ranges_) {
    uint32_t largest = 0;
    for (size_t i = begin; i < end; ++i) {
      Instance& inst = out_.scene.instances[i];
      largest = std::max(largest, inst.object_id);
      const uint64_t id = offset + inst.object_id;
      if (id > kMaxObjectId)
        root_.fail(
            fmt::format("more than {} labelled objects: object ids must stay exact in the float AOV (docs/limits.md)",
                        kMaxObjectId));
      inst.object_id = static_cast<uint32_t>(id);
    }
    offset += largest;
  }
  for (TargetInfo& target : out_.targets) target.object_id = out_.scene.instances[target.instance].object_id;
  return std::move(out_);
}

}  // namespace sylva
