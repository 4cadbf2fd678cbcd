// `sylva export`: flattens a scene (or the built-in default) into one world-space triangle mesh
// (OBJ) and prints the camera and lights as options of Embree's `pathtracer` tutorial, so the same
// view can be rendered there (bench/compare_embree.sh).

#include "app/commands.h"
#include "app/render_job.h"
#include "core/error.h"
#include "core/output_paths.h"
#include "geometry/mesh_io.h"
#include "geometry/solids/solid_mesh.h"
#include "render/lights/lights.h"
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
};

// Every instance of every prototype in world space, leaf quads split into triangles (0,1,2) and
// (0,2,3), half-space solids polygonised (geometry/solids/solid_mesh.h). Normals are transformed by
// the inverse transpose when the whole scene has them (the leaves get their quad's geometric
// normal); uvs are dropped. Leaf alpha outlines are lost. Leaf discs become regular polygons of
// kDiscSides sides inscribed in the disc (their area is (n/2π)·sin(2π/n) = 95.5 % of the disc's).
// Grass curves are left out (and counted on stderr): flattened, the instanced patches would outweigh
// everything else — the default forest's 10.6 million placed blades would be 21 million triangles
// even as one quad each, about 1.5 GB of OBJ, against 23 million for its trees (leaf quads split in two) and terrain —
// and export exists to render the same view in Embree's pathtracer, whose OBJ reader has no curves.
constexpr int kDiscSides = 12;

TriangleMesh flatten_scene(const Scene& scene) {
  size_t vertex_count = 0, triangle_count = 0;
  bool normals = true;
  for (const Instance& inst : scene.instances) {
    const Prototype& proto = scene.prototypes[inst.prototype];
    vertex_count +=
        proto.triangles.positions.size() + proto.leaves.corners.size() + (kDiscSides + 1) * proto.discs.size();
    triangle_count += proto.triangles.triangles.size() + 2 * proto.leaves.size() + kDiscSides * proto.discs.size();
    if (!proto.triangles.triangles.empty() && proto.triangles.normals.empty()) normals = false;
  }
  TriangleMesh world;
  std::vector<TriangleMesh> solid_meshes(scene.prototypes.size());
  world.positions.reserve(vertex_count);
  if (normals) world.normals.reserve(vertex_count);
  world.triangles.reserve(triangle_count);

  for (const Instance& inst : scene.instances) {
    const Prototype& proto = scene.prototypes[inst.prototype];
    const Mat4& m = inst.world_from_object;
    const Mat3 normal_from_object = glm::transpose(glm::inverse(Mat3(m)));
    auto to_world = [&](const Vec3& p) { return Vec3(m * Vec4(p, 1.0f)); };
    auto to_world_normal = [&](const Vec3& n) {
      const Vec3 w = normal_from_object * n;
      const float len = glm::length(w);
      return len > 0.0f ? w / len : Vec3(0.0f, 0.0f, 1.0f);
    };

    const TriangleMesh& tri = proto.triangles;
    auto base = static_cast<uint32_t>(world.positions.size());
    for (size_t i = 0; i < tri.positions.size(); ++i) {
      world.positions.push_back(to_world(tri.positions[i]));
      if (normals) world.normals.push_back(to_world_normal(tri.normals[i]));
    }
    for (const glm::uvec3& t : tri.triangles) world.triangles.push_back(t + glm::uvec3(base));

    const LeafQuads& leaves = proto.leaves;
    for (size_t q = 0; q < leaves.size(); ++q) {
      base = static_cast<uint32_t>(world.positions.size());
      Vec3 c[4];
      for (int k = 0; k < 4; ++k) c[k] = to_world(leaves.corners[4 * q + k]);
      const Vec3 n = glm::cross(c[2] - c[0], c[3] - c[1]);
      const float len = glm::length(n);
      for (int k = 0; k < 4; ++k) {
        world.positions.push_back(c[k]);
        if (normals) world.normals.push_back(len > 0.0f ? n / len : Vec3(0.0f, 0.0f, 1.0f));
      }
      world.triangles.push_back({base, base + 1, base + 2});
      world.triangles.push_back({base, base + 2, base + 3});
    }

    const LeafDiscs& discs = proto.discs;
    for (size_t d = 0; d < discs.size(); ++d) {
      base = static_cast<uint32_t>(world.positions.size());
      const Frame frame = Frame::from_z(discs.normal[d]);
      const Vec3 n = to_world_normal(discs.normal[d]);
      world.positions.push_back(to_world(discs.centre[d]));
      if (normals) world.normals.push_back(n);
      for (int k = 0; k < kDiscSides; ++k) {
        const float a = kTwoPi * static_cast<float>(k) / kDiscSides;
        world.positions.push_back(
            to_world(discs.centre[d] + discs.radius[d] * (std::cos(a) * frame.x + std::sin(a) * frame.y)));
        if (normals) world.normals.push_back(n);
      }
      for (uint32_t k = 0; k < kDiscSides; ++k)
        world.triangles.push_back({base, base + 1 + k, base + 1 + (k + 1) % kDiscSides});
    }

    // Half-space solids (Fournier–Grindal crowns and trunks), polygonised once per prototype.
    if (!proto.solids.empty()) {
      TriangleMesh& solid = solid_meshes[inst.prototype];
      if (solid.triangles.empty())
        for (const HalfSpaceSolid& s : proto.solids) append_mesh(solid, solid_surface_mesh(s));
      base = static_cast<uint32_t>(world.positions.size());
      for (size_t i = 0; i < solid.positions.size(); ++i) {
        world.positions.push_back(to_world(solid.positions[i]));
        if (normals) world.normals.push_back(to_world_normal(solid.normals[i]));
      }
      for (const glm::uvec3& t : solid.triangles) world.triangles.push_back(t + glm::uvec3(base));
    }
  }
  return world;
}

int run_export(const ExportOptions& opt) {
  if (opt.obj.empty()) throw Error("no output: give --obj OUT.obj");
  check_outputs({{"--obj", opt.obj}}, {opt.scene});
  SceneOptions scene_options;
  if (!opt.res.empty()) scene_options.resolution = parse_resolution(opt.res);
  const SceneFile file = opt.scene.empty() ? default_scene(scene_options) : load_scene_file(opt.scene, scene_options);
  check_outputs({{"--obj", opt.obj}}, file.inputs);
  const int width = file.render.width, height = file.render.height;
  const Scene& scene = file.scene;
  const TriangleMesh world = flatten_scene(scene);
  write_obj(opt.obj, world);

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
    fmt::print(stderr, "export: {} instances → {} triangles, {} vertices in {} (leaf outlines not kept: full quads)\n",
               scene.instances.size(), world.triangles.size(), world.positions.size(), opt.obj);
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
  cmd->add_flag("-q,--quiet", opt->quiet, "No summary on stderr");
  return [opt] { return run_export(*opt); };
}

}  // namespace sylva
