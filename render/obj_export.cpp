// A scene as Wavefront OBJ with materials and leaf outlines (render/obj_export.h).

#include "render/obj_export.h"

#include "core/atomic_file.h"
#include "core/band.h"
#include "core/error.h"
#include "geometry/mesh_io.h"

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <ostream>
#include <variant>

namespace sylva {

namespace {

// The leaf shapes of the prototypes that are placed, in LeafShape order.
std::vector<LeafShape> placed_leaf_shapes(const Scene& scene) {
  std::vector<bool> placed(scene.prototypes.size(), false);
  for (const Instance& inst : scene.instances) placed[inst.prototype] = true;
  std::array<bool, static_cast<size_t>(LeafShape::Count)> used{};
  for (size_t p = 0; p < scene.prototypes.size(); ++p)
    if (placed[p])
      for (const LeafShape s : scene.prototypes[p].leaves.shapes) used[static_cast<size_t>(s)] = true;
  std::vector<LeafShape> shapes;
  for (size_t s = 0; s < used.size(); ++s)
    if (used[s]) shapes.push_back(static_cast<LeafShape>(s));
  return shapes;
}

void write_outline_texture(const std::filesystem::path& file, LeafShape shape) {
  write_file_atomic(file, [&](std::ostream& out) {
    out << "P6\n" << kOutlineTextureSize << ' ' << kOutlineTextureSize << "\n255\n";
    // Row r holds v in [r, r + 1)/size (the tutorial's texel lookup: row = floor(v · height)).
    std::vector<char> row(3 * kOutlineTextureSize);
    for (int r = 0; r < kOutlineTextureSize; ++r) {
      const float v = (static_cast<float>(r) + 0.5f) / kOutlineTextureSize;
      for (int c = 0; c < kOutlineTextureSize; ++c) {
        const float u = (static_cast<float>(c) + 0.5f) / kOutlineTextureSize;
        const char value = leaf_shape_inside(shape, u, v) ? static_cast<char>(255) : 0;
        std::fill_n(row.begin() + 3 * c, 3, value);
      }
      out.write(row.data(), static_cast<std::streamsize>(row.size()));
    }
  });
}

}  // namespace

ObjExportFiles obj_export_files(const Scene& scene, const std::filesystem::path& obj, bool materials) {
  ObjExportFiles files;
  files.obj = obj;
  if (!materials) return files;
  files.mtl = std::filesystem::path(obj).replace_extension(".mtl");
  for (const LeafShape s : placed_leaf_shapes(scene))
    files.outlines.emplace_back(
        s, std::filesystem::path(obj).replace_extension(fmt::format(".{}.ppm", leaf_shape_name(s))));
  return files;
}

Vec3 obj_diffuse_colour(const Material& material) {
  const DenseSpectrum& reflectance = display_reflectance(material);
  static const Band rgb = make_rgb_band();
  Vec3 colour;
  for (int c = 0; c < 3; ++c)
    colour[c] = std::clamp(static_cast<float>(reflectance.integral_product(rgb.weights[c]) / rgb.weights[c].integral()),
                           0.0f, 1.0f);
  return colour;
}

std::string obj_part_name(const Scene& scene, const FlatPart& part) {
  std::string name = scene.material_names[part.material];
  std::replace_if(
      name.begin(), name.end(), [](unsigned char c) { return std::isspace(c) != 0; }, '_');
  if (name.empty()) name = "material";
  if (part.outline) name += fmt::format(".{}", leaf_shape_name(*part.outline));
  return name;
}

ObjExportSummary export_obj(const Scene& scene, const ObjExportFiles& files) {
  FlatScene flat = flatten_scene(scene);
  ObjExportSummary summary{flat.mesh.triangles.size(), flat.mesh.positions.size(), flat.parts.size()};
  if (files.mtl.empty()) {
    flat.mesh.uvs = {};
    write_obj(files.obj, flat.mesh);
    return summary;
  }
  std::vector<std::string> names;
  for (const FlatPart& part : flat.parts) names.push_back(obj_part_name(scene, part));
  write_obj(files.obj, flat.mesh, ObjGroups{flat.part, names, files.mtl.filename().string()});

  write_file_atomic(files.mtl, [&](std::ostream& out) {
    out << "# Sylva materials: diffuse colours are each material's reflectance in linear Rec.709;\n"
           "# leaf outlines are opacity maps (map_d), the cut-out transparent (Tf 1 1 1).\n";
    for (size_t i = 0; i < flat.parts.size(); ++i) {
      const FlatPart& part = flat.parts[i];
      const Vec3 kd = obj_diffuse_colour(scene.materials[part.material]);
      out << fmt::format("\nnewmtl {}\nKd {} {} {}\nKs 0 0 0\n", names[i], kd.x, kd.y, kd.z);
      if (!part.outline) continue;
      const auto texture = std::find_if(files.outlines.begin(), files.outlines.end(),
                                        [&](const auto& o) { return o.first == *part.outline; });
      if (texture == files.outlines.end())
        throw Error(fmt::format("{}: no outline texture for leaf shape {}", files.mtl.string(),
                                leaf_shape_name(*part.outline)));
      out << "Tf 1 1 1\nmap_d " << texture->second.filename().string() << "\n";
    }
  });
  for (const auto& [shape, file] : files.outlines) write_outline_texture(file, shape);
  return summary;
}

}  // namespace sylva
