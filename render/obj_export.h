#pragma once
// A scene as Wavefront OBJ for other renderers (`sylva export`, bench/compare_embree.sh): every
// instance flattened into one world-space mesh (render/flatten.h), with a material library whose
// colours are the scene's spectra seen in linear Rec.709, and the leaf outlines as alpha maps.
//
// Files, for an OBJ path DIR/NAME.obj: the OBJ; DIR/NAME.mtl; and DIR/NAME.SHAPE.ppm, one binary
// PPM (P6, grey) per leaf shape in the scene, white inside the outline, which the material of every
// leaf part of that shape names as its `map_d` (opacity) with `Tf 1 1 1`, so a renderer that reads
// opacity maps — Embree's pathtracer tutorial among them — lets rays through the cut-out as Sylva
// does. A part is one scene material (and, for leaves, one outline): `g` and `usemtl` name it.

#include "geometry/leaf_shape.h"
#include "render/flatten.h"
#include "render/scene.h"

#include <filesystem>
#include <string>
#include <vector>

namespace sylva {

// The side of each outline texture, in texels: the outline is sampled at texel centres, so it is
// placed within 1/512 of the leaf's width and length.
inline constexpr int kOutlineTextureSize = 256;

struct ObjExportFiles {
  std::filesystem::path obj;
  std::filesystem::path mtl;  // empty: a plain OBJ, no materials, leaves as full opaque quads
  std::vector<std::pair<LeafShape, std::filesystem::path>> outlines;
};

// The files exporting `scene` to `obj` writes (with `materials`, the library and one outline
// texture per leaf shape of a placed prototype), so they can be checked before the work starts.
ObjExportFiles obj_export_files(const Scene& scene, const std::filesystem::path& obj, bool materials);

// A part's diffuse colour: the material's reflectance (a leaf's upper face; its transmittance has no
// OBJ counterpart) weighted by the Rec.709 colour matching functions of the `rgb` band, each
// channel normalised by its value for a reflectance of 1 and clamped to [0, 1].
Vec3 obj_diffuse_colour(const Material& material);

// The OBJ part name of `part`: the material's name (white space replaced by '_'), then
// ".SHAPE" for a leaf outline.
std::string obj_part_name(const Scene& scene, const FlatPart& part);

// Writes every file of `files`, each atomically (core/atomic_file.h). Returns the flattened scene's
// size for a summary.
struct ObjExportSummary {
  size_t triangles = 0;
  size_t vertices = 0;
  size_t parts = 0;
};
ObjExportSummary export_obj(const Scene& scene, const ObjExportFiles& files);

}  // namespace sylva
