#include "scenes/sidecar.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "render/coverage.h"
#include "render/primitives/primitive.h"
#include "scenes/view_metadata.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <ostream>

namespace sylva {

std::string json_string(std::string_view s) {
  std::string out = "\"";
  for (const char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += ch;
    } else if (c < 0x20) {
      out += fmt::format("\\u{:04x}", c);
    } else {
      out += ch;
    }
  }
  return out + "\"";
}

namespace {

// A finite number in the shortest form that reads back exactly; JSON has no NaN or infinity, so
// those are written as null.
std::string number(double v) { return std::isfinite(v) ? fmt::format("{}", v) : "null"; }
std::string number(float v) { return std::isfinite(v) ? fmt::format("{}", v) : "null"; }

std::string vec3(const Vec3& v) { return fmt::format("[{}, {}, {}]", number(v.x), number(v.y), number(v.z)); }

std::string bounds(const Bounds3& b) {
  if (b.empty()) return "null";
  return fmt::format("{{\"min\": {}, \"max\": {}}}", vec3(b.lo), vec3(b.hi));
}

// What the image shows of one object id: visible pixels and their box (inclusive pixel bounds).
struct Coverage {
  uint64_t pixels = 0;
  int x0 = 0, y0 = 0, x1 = -1, y1 = -1;
  void add(int x, int y) {
    if (pixels++ == 0) {
      x0 = x1 = x;
      y0 = y1 = y;
    }
    x0 = std::min(x0, x);
    x1 = std::max(x1, x);
    y0 = std::min(y0, y);
    y1 = std::max(y1, y);
  }
};

// An object of the sidecar: an object id with its instances' union of world bounds.
struct ObjectEntry {
  uint32_t first_instance = 0;
  Bounds3 world;
};

// Visible pixels of every object id in the image.
std::map<uint32_t, Coverage> visible_objects(const Image& image, int object_channel) {
  std::map<uint32_t, Coverage> visible;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const auto id = static_cast<uint32_t>(image.at(x, y, object_channel));
      if (id != 0) visible[id].add(x, y);
    }
  return visible;
}

// The objects listed: those visible, and every target, with their first instance and world bounds.
// One pass over the instances.
std::map<uint32_t, ObjectEntry> listed_objects(const SceneFile& file, const std::map<uint32_t, Coverage>& visible) {
  const Scene& scene = file.scene;
  std::map<uint32_t, ObjectEntry> objects;
  for (const auto& [id, c] : visible) objects[id];
  for (const TargetInfo& t : file.targets) objects[t.object_id];
  std::vector<Bounds3> proto_bounds(scene.prototypes.size());
  std::vector<bool> proto_done(scene.prototypes.size(), false);
  std::map<uint32_t, bool> seen;
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    auto found = objects.find(inst.object_id);
    if (found == objects.end()) continue;
    if (!proto_done[inst.prototype]) {
      proto_bounds[inst.prototype] = prototype_bounds(scene.prototypes[inst.prototype]);
      proto_done[inst.prototype] = true;
    }
    if (!seen[inst.object_id]) {
      found->second.first_instance = static_cast<uint32_t>(i);
      seen[inst.object_id] = true;
    }
    const Bounds3 b = transformed(proto_bounds[inst.prototype], inst.world_from_object);
    if (!b.empty()) {
      found->second.world.extend(b.lo);
      found->second.world.extend(b.hi);
    }
  }
  return objects;
}

// The image, the scene, the AOV names, and the class and variant tables.
std::string header_json(const SceneFile& file, const RenderSettings& settings, const Image& image,
                        const std::filesystem::path& exr) {
  const Scene& scene = file.scene;
  std::string out = "{\n";
  out += "  \"format\": \"sylva-labels\",\n  \"version\": 1,\n";
  out += fmt::format("  \"image\": {{\"file\": {}, \"width\": {}, \"height\": {}}},\n",
                     json_string(exr.filename().string()), image.width, image.height);
  out += fmt::format("  \"scene\": {},\n  \"scene_hash\": {},\n  \"seed\": {},\n",
                     json_string(file.path.empty() ? "<default scene>" : file.path.filename().string()),
                     json_string(file.content_hash), settings.seed);
  out += "  \"aovs\": {\"object\": \"id.object\", \"class\": \"id.class\", \"variant\": \"id.variant\"},\n";
  out += view_json(scene, image.width, image.height) + ",\n";
  std::string bands;
  for (const Band& b : settings.bands) bands += (bands.empty() ? "" : ", ") + json_string(b.name);
  out += "  \"bands\": [" + bands + "],\n";

  out += "  \"classes\": [";
  bool first = true;
  for (const auto& [id, name] : scene.class_names) {
    out += fmt::format("{}\n    {{\"id\": {}, \"name\": {}}}", first ? "" : ",", id, json_string(name));
    first = false;
  }
  out += "\n  ],\n";

  out += "  \"variants\": [";
  for (size_t i = 0; i < file.variants.size(); ++i) {
    const VariantInfo& v = file.variants[i];
    out += fmt::format(
        "{}\n    {{\"id\": {}, \"kind\": {}, \"name\": {}, \"source\": {}, \"seed\": {}, \"class\": {}}}", i ? "," : "",
        i + 1, json_string(v.kind), json_string(v.name), json_string(v.source), v.seed, v.class_id);
  }
  out += "\n  ],\n";
  return out;
}

// Every listed object: its name, labels, source, position, bounds and visible pixels.
std::string objects_json(const SceneFile& file, const std::map<uint32_t, ObjectEntry>& objects,
                         const std::map<uint32_t, Coverage>& visible) {
  const Scene& scene = file.scene;
  const auto object_name = [&](uint32_t id, const Instance& inst) {
    for (const TargetInfo& t : file.targets)
      if (t.object_id == id) return t.name;
    if (inst.variant_id > 0) return file.variants[inst.variant_id - 1].name;
    return scene.prototypes[inst.prototype].name;
  };
  std::string out = "  \"objects\": [";
  bool first = true;
  for (const auto& [id, entry] : objects) {
    const Instance& inst = scene.instances[entry.first_instance];
    const auto v = visible.find(id);
    std::string variant = "null", seed = "null", source = "null";
    if (inst.variant_id > 0) {
      const VariantInfo& info = file.variants[inst.variant_id - 1];
      variant = std::to_string(inst.variant_id);
      source = json_string(info.source);
      if (info.kind == "tree") seed = std::to_string(info.seed);
    }
    out += fmt::format(
        "{}\n    {{\"id\": {}, \"name\": {}, \"class\": {}, \"class_name\": {}, \"variant\": {}, \"source\": {}, "
        "\"seed\": {}, \"position\": {}, \"bounds\": {}, \"visible_pixels\": {}}}",
        first ? "" : ",", id, json_string(object_name(id, inst)), inst.class_id,
        json_string(scene.class_names.at(inst.class_id)), variant, source, seed, vec3(Vec3(inst.world_from_object[3])),
        bounds(entry.world), v == visible.end() ? 0 : v->second.pixels);
    first = false;
  }
  out += "\n  ],\n";
  return out;
}

// Every target: its labels, placement, image box, visible and unoccluded pixels (each target
// rendered alone, render/coverage.h) and occlusion.
std::string targets_json(const SceneFile& file, const RenderSettings& settings, const Image& image,
                         const std::map<uint32_t, ObjectEntry>& objects, const std::map<uint32_t, Coverage>& visible) {
  const Scene& scene = file.scene;
  std::vector<uint32_t> target_instances;
  for (const TargetInfo& t : file.targets) target_instances.push_back(t.instance);
  const std::vector<uint64_t> alone =
      unoccluded_pixels(scene, target_instances, image.width, image.height, settings.threads);
  std::string out = "  \"targets\": [";
  for (size_t i = 0; i < file.targets.size(); ++i) {
    const TargetInfo& t = file.targets[i];
    const auto v = visible.find(t.object_id);
    const Coverage c = v == visible.end() ? Coverage{} : v->second;
    const std::string box =
        c.pixels == 0 ? "null"
                      : fmt::format("{{\"x0\": {}, \"y0\": {}, \"x1\": {}, \"y1\": {}}}", c.x0, c.y0, c.x1, c.y1);
    const double fraction = alone[i] > 0 ? static_cast<double>(c.pixels) / static_cast<double>(alone[i]) : 0.0;
    out += fmt::format(
        "{}\n    {{\"name\": {}, \"object\": {}, \"label\": {}, \"class\": {}, \"variant\": {}, \"position\": {}, "
        "\"heading\": {}, \"bounds\": {}, \"image_box\": {}, \"visible_pixels\": {}, \"unoccluded_pixels\": {}, "
        "\"visible_fraction\": {}, \"occluded_fraction\": {}}}",
        i ? "," : "", json_string(t.name), t.object_id, json_string(scene.class_names.at(t.class_id)), t.class_id,
        t.variant_id, vec3(t.position), number(t.heading_deg), bounds(objects.at(t.object_id).world), box, c.pixels,
        alone[i], alone[i] > 0 ? number(fraction) : "null", alone[i] > 0 ? number(1.0 - fraction) : "null");
  }
  out += "\n  ]\n}\n";
  return out;
}

}  // namespace

std::filesystem::path sidecar_path(const std::filesystem::path& exr) {
  std::filesystem::path out = exr;
  return out.replace_extension(".json");
}

std::string make_sidecar(const SceneFile& file, const RenderSettings& settings, const Image& image,
                         const std::filesystem::path& exr) {
  const int object_channel = image.find_channel("id.object");
  if (object_channel < 0) throw Error("the label sidecar needs the id.object AOV");
  const std::map<uint32_t, Coverage> visible = visible_objects(image, object_channel);
  const std::map<uint32_t, ObjectEntry> objects = listed_objects(file, visible);
  return header_json(file, settings, image, exr) + objects_json(file, objects, visible) +
         targets_json(file, settings, image, objects, visible);
}

void write_sidecar(const std::filesystem::path& path, const SceneFile& file, const RenderSettings& settings,
                   const Image& image, const std::filesystem::path& exr) {
  const std::string text = make_sidecar(file, settings, image, exr);
  write_file_atomic(path, [&](std::ostream& out) { out << text; });
}

}  // namespace sylva
