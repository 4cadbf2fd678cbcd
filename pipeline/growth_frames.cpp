#include "pipeline/growth_frames.h"

#include "core/error.h"
#include "core/image.h"
#include "core/progress.h"
#include "geometry/trees/hart_baker/rings.h"
#include "geometry/trees/hart_baker/surface.h"
#include "pipeline/outputs.h"
#include "render/renderer.h"
#include "scenes/scene_file.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

namespace sylva {

namespace {

// --frames: a small preview of each year through the path tracer (docs/hart_baker.md "Time-lapse").
constexpr int kFrameWidth = 320;
constexpr int kFrameHeight = 240;
constexpr int kFrameSpp = 16;
constexpr float kFrameVfovDeg = 40.0f;

// Bounds of a tree's limbs and leaves (tree space), padded by a leaf's length.
void tree_bounds(const HartBakerTree& tree, const HartBakerParams& params, Vec3& lo, Vec3& hi) {
  lo = Vec3(0.0f);
  hi = Vec3(0.0f);
  for (size_t i = 0; i < tree.size(); ++i) {
    if (!tree.alive[i]) continue;
    const Vec3 tip = tree.base[i] + tree.direction[i] * tree.length_m[i];
    lo = glm::min(lo, glm::min(tree.base[i], tip));
    hi = glm::max(hi, glm::max(tree.base[i], tip));
  }
  const float pad = params.leaf_length_m + tree.radius_m[0];
  lo -= Vec3(pad, pad, 0.0f);
  hi += Vec3(pad);
}

// The preview scene: ground, sun and clear sky, the camera from the south-west framing the box.
std::string frame_scene_text(const Vec3& lo, const Vec3& hi) {
  const Vec3 centre = 0.5f * (lo + hi);
  const float radius = 0.5f * glm::length(hi - lo);
  // Close enough that the box's bounding sphere just fits the frame's height, nearly level.
  const float distance = 0.9f * radius / std::sin(radians(0.5f * kFrameVfovDeg));
  const Vec3 eye = centre + distance * glm::normalize(Vec3(-0.55f, -0.8f, 0.08f));
  return fmt::format(
      "[render]\nwidth = {}\nheight = {}\nspp = {}\nbands = [\"rgb\"]\n[output]\nview = \"ACES\"\n"
      "[camera]\nposition = [{}, {}, {}]\ntarget = [{}, {}, {}]\nvfov = {}\n"
      "[sun]\nazimuth = 160\nelevation = 45\n[sky]\nmodel = \"cie\"\ntype = 12\n"
      "[materials.soil]\ntype = \"diffuse\"\n"
      "reflectance = {{ file = \"spectra/helios_soil_reflectance.csv\", column = \"soil_reflectivity_0002\" }}\n"
      "[materials.bark]\ntype = \"diffuse\"\n"
      "reflectance = {{ file = \"spectra/helios_bark_wood_reflectance.csv\", column = \"bark_reflectivity_0001\" }}\n"
      "[materials.leaf]\ntype = \"leaf\"\nprospect = {{ N = 1.6, Cab = 45, Car = 9, Cw = 0.012, Cm = 0.008 }}\n"
      "[[meshes]]\nname = \"ground\"\nshape = \"plane\"\nsize = [20000, 20000]\nmaterial = \"soil\"\n",
      kFrameWidth, kFrameHeight, kFrameSpp, eye.x, eye.y, eye.z, centre.x, centre.y, centre.z, kFrameVfovDeg);
}

uint32_t material_index(const Scene& scene, const std::string& name) {
  const auto it = std::find(scene.material_names.begin(), scene.material_names.end(), name);
  return static_cast<uint32_t>(it - scene.material_names.begin());
}

// One PNG per kept state, all framed on the last state's bounds so the frames do not jump.
}  // namespace

void write_growth_frames(const std::filesystem::path& dir, const std::vector<HartBakerTree>& states,
                         const HartBakerParams& params) {
  if (states.empty()) return;
  Vec3 lo, hi;
  tree_bounds(states.back(), params, lo, hi);
  const SceneFile base = parse_scene(frame_scene_text(lo, hi), "frames", dir);
  Progress progress("frames", states.size(), true, "frames");
  for (const HartBakerTree& state : states) {
    SceneFile file = base;
    TreeMesh mesh = make_hart_baker_mesh(hart_baker_tree_model(state, params), params);
    Prototype tree;
    tree.name = "tree";
    tree.triangles = std::move(mesh.stems);
    tree.triangle_material = material_index(file.scene, "bark");
    tree.leaves = std::move(mesh.leaves);
    tree.leaf_material = material_index(file.scene, "leaf");
    file.scene.instances.push_back(Instance{file.scene.add_prototype(std::move(tree)), Mat4(1.0f), 0});
    RenderSettings settings = render_settings(file);
    settings.progress = false;
    Renderer renderer(file.scene, settings);
    Film film = renderer.make_film();
    renderer.render(film);
    write_render_preview(renderer, renderer.make_image(film), file.output,
                         dir / fmt::format("year_{:03d}.png", state.year), {});
    progress.add(1);
  }
  progress.finish();
}

void write_trunk_rings(const std::filesystem::path& png, const HartBakerTree& tree, const HartBakerParams& params,
                       float height_m) {
  const TrunkRings rings = trunk_rings(tree, params, height_m);
  if (rings.size() == 0) throw Error(fmt::format("--rings: the trunk does not reach {} m", height_m));
  write_png_rgb8(png, 512, 512, ring_image_rgb8(rings, 512));
  std::filesystem::path csv = png;
  csv.replace_extension(".csv");
  write_text_file(csv, ring_widths_csv(rings));
}

}  // namespace sylva
