#pragma once
// What a training or evaluation pipeline needs to relate an image to the world: the camera's
// intrinsics and pose, the sun and the bands, as recorded in the EXR header (annotate_render) and
// the label sidecar (scenes/sidecar.h). docs/scene_format.md, "Camera and sun metadata".
//
// Conventions (those of OpenCV and COLMAP): camera space has x right, y down and z forward, in
// metres; raster coordinates put (0, 0) at the top-left corner of pixel (0, 0), so pixel (i, j)'s
// centre is (i + 0.5, j + 0.5). A perspective camera maps camera point p to raster
// (u, v) = (K p) / p.z; an orthographic one to (u, v) = (p.x, p.y) / metres_per_pixel + (cx, cy).

#include "core/image.h"
#include "core/math.h"
#include "render/scene.h"

#include <optional>
#include <string>

namespace sylva {

struct CameraMetadata {
  std::string projection;  // "perspective" or "orthographic"
  int width = 0, height = 0;
  // Perspective: K = [[fx, 0, cx], [0, fy, cy], [0, 0, 1]] in pixels (fx = fy: square pixels).
  // Orthographic: fx = fy = 1 / metres_per_pixel, cx, cy the image centre.
  double fx = 0, fy = 0, cx = 0, cy = 0;
  double metres_per_pixel = 0;  // orthographic only
  glm::dmat4 world_from_camera{1.0};
};

// The camera of `desc` rendering a width × height image.
CameraMetadata camera_metadata(const CameraDesc& desc, int width, int height);

// The raster position of a world point, or nullopt behind a perspective camera.
std::optional<glm::dvec2> project_to_raster(const CameraMetadata& camera, const glm::dvec3& world);

struct SunMetadata {
  bool enabled = true;
  double azimuth_deg = 0, elevation_deg = 0;  // compass bearing clockwise from north (+Y); above the horizon
  glm::dvec3 direction{0, 0, 1};              // unit, world, toward the sun
};

SunMetadata sun_metadata(const SunDesc& sun);

// Row-major numbers separated by spaces ("%.17g"), as the header attributes hold matrices.
std::string matrix_text(const glm::dmat3& m);
std::string matrix_text(const glm::dmat4& m);
glm::dmat3 intrinsic_matrix(const CameraMetadata& camera);

// The camera and sun in an image's header: sylva:camera_projection, sylva:camera_intrinsics (K,
// row-major) and for an orthographic camera sylva:camera_metres_per_pixel, sylva:world_from_camera
// (row-major 4 × 4), sylva:camera_convention, sylva:sun_direction (x y z), sylva:sun_azimuth_deg,
// sylva:sun_elevation_deg (the bands are sylva:bands, annotate_render).
void annotate_view(Image& image, const Scene& scene, int width, int height);

// The same as JSON members: `"camera": {...},\n  "sun": {...}` (two-space indent, no final comma).
std::string view_json(const Scene& scene, int width, int height);

}  // namespace sylva
