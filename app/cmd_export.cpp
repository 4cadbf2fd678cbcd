// `sylva export`: flattens a scene (or the built-in default) into one world-space triangle mesh
// (OBJ, with a material library and leaf outline textures unless --no-materials:
// render/obj_export.h) and prints the camera and lights as options of Embree's `pathtracer`
// tutorial, so the same view can be rendered there (bench/compare_embree.sh).

#include "app/commands.h"
#include "core/error.h"
#include "core/output_paths.h"
#include "pipeline/scene_request.h"
#include "render/lights/lights.h"
#include "render/obj_export.h"
#include "scenes/scene_file.h"

#include <fmt/core.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <tuple>

namespace sylva {
namespace {

struct ExportOptions {
  std::string scene;
  std::string obj;
  std::string res;
  bool quiet = false;
  bool no_materials = false;
};

int run_export(const ExportOptions& opt) {
  if (opt.obj.empty()) throw Error("no output: give --obj OUT.obj");
  check_outputs({{"--obj", opt.obj}}, {opt.scene});
  SceneOptions scene_options;
  if (!opt.res.empty()) scene_options.resolution = parse_resolution(opt.res);
  const SceneFile file = opt.scene.empty() ? default_scene(scene_options) : load_scene_file(opt.scene, scene_options);
  const int width = file.render.width, height = file.render.height;
  const Scene& scene = file.scene;
  const ObjExportFiles files = obj_export_files(scene, opt.obj, !opt.no_materials);
  std::vector<OutputFile> outputs{{"--obj", files.obj}};
  if (!files.mtl.empty()) outputs.push_back({"material library", files.mtl});
  for (const auto& [shape, texture] : files.outlines) outputs.push_back({"leaf outline texture", texture});
  check_outputs(outputs, file.inputs);
  const ObjExportSummary written = export_obj(scene, files);

  // Embree's tutorial camera (right-handed by default) takes the same look-at and vertical field
  // of view. Its --distantlight takes the direction the light travels (sun → scene), an RGB
  // radiance and the disc's full opening angle in degrees; its lights are RGB, so the sun gets a
  // white radiance giving an irradiance of 0.2 at normal incidence and the sky a white ambient
  // light of 0.2: enough for a viewable image, not a photometric match.
  const CameraDesc& cam = scene.camera;
  const auto* lens = std::get_if<PerspectiveProjection>(&cam.projection);
  if (!lens) throw Error("export: Embree's pathtracer takes a perspective camera only");
  const Vec3 to_sun = sun_direction(scene.sun.azimuth_deg, scene.sun.elevation_deg);
  const float sun_solid_angle_sr = kTwoPi * (1.0f - std::cos(radians(scene.sun.angular_radius_deg)));
  const float sun_radiance = 0.2f / sun_solid_angle_sr;
  fmt::print(
      "--size {} {} --vp {} {} {} --vi {} {} {} --vu {} {} {} --fov {} --distantlight {} {} {} {} {} {} {} "
      "--ambientlight 0.2 0.2 0.2\n",
      width, height, cam.position.x, cam.position.y, cam.position.z, cam.target.x, cam.target.y, cam.target.z, cam.up.x,
      cam.up.y, cam.up.z, lens->vfov_deg, -to_sun.x, -to_sun.y, -to_sun.z, sun_radiance, sun_radiance, sun_radiance,
      2.0f * scene.sun.angular_radius_deg);
  if (lens->aperture_radius_m > 0.0f && !opt.quiet)
    fmt::print(stderr, "export: the scene's thin-lens camera is exported as a pinhole\n");
  if (!opt.quiet)
    fmt::print(stderr, "export: {} instances → {} triangles, {} vertices in {}; {}\n", scene.instances.size(),
               written.triangles, written.vertices, opt.obj,
               files.mtl.empty() ? std::string("no materials, leaves as full opaque quads")
                                 : fmt::format("{} materials in {}, {} leaf outline textures", written.parts,
                                               files.mtl.string(), files.outlines.size()));
  // Said even with --quiet: the OBJ is not the whole scene (bench/compare_embree.sh reads this).
  size_t blades = 0;
  for (const Instance& inst : scene.instances) blades += scene.prototypes[inst.prototype].curves.size();
  if (blades > 0) fmt::print(stderr, "export: {} grass blades (curves) left out\n", blades);
  return 0;
}

}  // namespace

CommandRun add_export_command(CLI::App& parent) {
  auto opt = std::make_shared<ExportOptions>();
  CLI::App* cmd = parent.add_subcommand(
      "export", "Flatten a scene into one world-space OBJ and print the camera as Embree pathtracer options");
  cmd->add_option("scene", opt->scene, "Scene file (TOML); omit for the built-in default scene");
  cmd->add_option("--obj", opt->obj, "Output OBJ (written atomically)")->required();
  cmd->add_option("--res", opt->res, "Resolution WIDTHxHEIGHT for --size (default: the scene's)");
  cmd->add_flag("--no-materials", opt->no_materials,
                "Geometry only: no material library, leaves as full opaque quads (no outline textures)");
  cmd->add_flag("-q,--quiet", opt->quiet, "No summary on stderr");
  return [opt] { return run_export(*opt); };
}

}  // namespace sylva
