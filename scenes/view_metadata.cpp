#include "scenes/view_metadata.h"

#include <fmt/core.h>

#include <cmath>
#include <variant>

namespace sylva {

CameraMetadata camera_metadata(const CameraDesc& desc, int width, int height) {
  CameraMetadata m;
  m.width = width;
  m.height = height;
  // The frame of Camera (render/sensors/camera.cpp): right = forward × up, its up = right × forward.
  const glm::dvec3 position(desc.position), forward = glm::normalize(glm::dvec3(desc.target) - position);
  const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(desc.up)));
  const glm::dvec3 down = -glm::cross(right, forward);
  m.world_from_camera =
      glm::dmat4(glm::dvec4(right, 0), glm::dvec4(down, 0), glm::dvec4(forward, 0), glm::dvec4(position, 1));
  m.cx = 0.5 * width;
  m.cy = 0.5 * height;
  std::visit(
      [&](const auto& p) {
        using P = std::decay_t<decltype(p)>;
        m.projection = std::string(P::kType);
        if constexpr (std::is_same_v<P, PerspectiveProjection>) {
          // render/sensors/perspective.cpp: x_cam = (2u/W − 1)·tan(vfov/2)·W/H, y_up = (1 − 2v/H)·tan(vfov/2).
          m.fx = m.fy = 0.5 * height / std::tan(0.5 * glm::radians(static_cast<double>(p.vfov_deg)));
        } else {
          m.metres_per_pixel = static_cast<double>(p.width_m) / width;
          m.fx = m.fy = 1.0 / m.metres_per_pixel;
        }
      },
      desc.projection);
  return m;
}

std::optional<glm::dvec2> project_to_raster(const CameraMetadata& camera, const glm::dvec3& world) {
  const glm::dvec3 p = glm::dvec3(glm::inverse(camera.world_from_camera) * glm::dvec4(world, 1.0));
  if (camera.projection == "orthographic") return glm::dvec2(camera.fx * p.x + camera.cx, camera.fy * p.y + camera.cy);
  if (p.z <= 0) return std::nullopt;
  return glm::dvec2(camera.fx * p.x / p.z + camera.cx, camera.fy * p.y / p.z + camera.cy);
}

SunMetadata sun_metadata(const SunDesc& sun) {
  SunMetadata s;
  s.enabled = sun.enabled;
  s.azimuth_deg = sun.azimuth_deg;
  s.elevation_deg = sun.elevation_deg;
  const double az = glm::radians(s.azimuth_deg), el = glm::radians(s.elevation_deg);
  s.direction = glm::dvec3(std::sin(az) * std::cos(el), std::cos(az) * std::cos(el), std::sin(el));
  return s;
}

glm::dmat3 intrinsic_matrix(const CameraMetadata& camera) {
  glm::dmat3 k(1.0);  // column-major: k[column][row]
  k[0][0] = camera.fx;
  k[1][1] = camera.fy;
  k[2][0] = camera.cx;
  k[2][1] = camera.cy;
  return k;
}

std::string matrix_text(const glm::dmat3& m) {
  std::string out;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) out += fmt::format("{}{:.17g}", out.empty() ? "" : " ", m[c][r]);
  return out;
}

std::string matrix_text(const glm::dmat4& m) {
  std::string out;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) out += fmt::format("{}{:.17g}", out.empty() ? "" : " ", m[c][r]);
  return out;
}

namespace {

constexpr const char* kCameraConvention =
    "camera x right, y down, z forward (OpenCV), metres; raster (0,0) is the top-left corner of pixel (0,0); "
    "perspective: (u,v,1) ~ K p_camera; orthographic: (u,v) = (x,y) / metres_per_pixel + (cx,cy)";

std::string vector_text(const glm::dvec3& v) { return fmt::format("{:.17g} {:.17g} {:.17g}", v.x, v.y, v.z); }

std::string json_numbers(const std::string& text) {
  std::string out = "[";
  for (char c : text) out += c == ' ' ? std::string(", ") : std::string(1, c);
  return out + "]";
}

}  // namespace

void annotate_view(Image& image, const Scene& scene, int width, int height) {
  const CameraMetadata camera = camera_metadata(scene.camera, width, height);
  image.set_attribute("sylva:camera_projection", camera.projection);
  image.set_attribute("sylva:camera_intrinsics", matrix_text(intrinsic_matrix(camera)));
  if (camera.projection == "orthographic")
    image.set_attribute("sylva:camera_metres_per_pixel", fmt::format("{:.17g}", camera.metres_per_pixel));
  image.set_attribute("sylva:world_from_camera", matrix_text(camera.world_from_camera));
  image.set_attribute("sylva:camera_convention", kCameraConvention);
  const SunMetadata sun = sun_metadata(scene.sun);
  image.set_attribute("sylva:sun_enabled", sun.enabled ? "true" : "false");
  image.set_attribute("sylva:sun_direction", vector_text(sun.direction));
  image.set_attribute("sylva:sun_azimuth_deg", fmt::format("{:.17g}", sun.azimuth_deg));
  image.set_attribute("sylva:sun_elevation_deg", fmt::format("{:.17g}", sun.elevation_deg));
}

std::string view_json(const Scene& scene, int width, int height) {
  const CameraMetadata camera = camera_metadata(scene.camera, width, height);
  const SunMetadata sun = sun_metadata(scene.sun);
  std::string out = fmt::format("  \"camera\": {{\"projection\": \"{}\", \"width\": {}, \"height\": {}, ",
                                camera.projection, camera.width, camera.height);
  out += fmt::format("\"intrinsics\": {}, ", json_numbers(matrix_text(intrinsic_matrix(camera))));
  if (camera.projection == "orthographic")
    out += fmt::format("\"metres_per_pixel\": {:.17g}, ", camera.metres_per_pixel);
  out += fmt::format("\"world_from_camera\": {}, \"convention\": \"{}\"}},\n",
                     json_numbers(matrix_text(camera.world_from_camera)), kCameraConvention);
  out += fmt::format(
      "  \"sun\": {{\"enabled\": {}, \"azimuth_deg\": {:.17g}, \"elevation_deg\": {:.17g}, \"direction\": {}}}",
      sun.enabled ? "true" : "false", sun.azimuth_deg, sun.elevation_deg, json_numbers(vector_text(sun.direction)));
  return out;
}

}  // namespace sylva
