#pragma once
// Small math vocabulary on GLM. World space is right-handed, Z up (docs/design.md §4).
// Transforms are named b_from_a. Geometry and shading use float; accumulation uses double.

#include <glm/glm.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

namespace sylva {

using Vec2 = glm::vec2;
using Vec3 = glm::vec3;
using Vec4 = glm::vec4;
using DVec3 = glm::dvec3;
using Mat3 = glm::mat3;
using Mat4 = glm::mat4;

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kTwoPi = 2.0f * kPi;
inline constexpr float kInvPi = 1.0f / kPi;
inline constexpr float kInvTwoPi = 1.0f / kTwoPi;
inline constexpr float kInvFourPi = 1.0f / (4.0f * kPi);

inline constexpr float radians(float degrees) { return degrees * (kPi / 180.0f); }
inline constexpr float degrees(float radians) { return radians * (180.0f / kPi); }

template <typename T>
inline constexpr T sqr(T x) {
  return x * x;
}
inline float safe_sqrt(float x) { return std::sqrt(std::max(0.0f, x)); }
inline float safe_acos(float x) { return std::acos(std::clamp(x, -1.0f, 1.0f)); }
inline bool is_finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// c ? a : b without a branch, bit for bit: both are computed, and the mask picks one. For choices
// on random samples (a quadrant, one of two table bins, a sign), where a branch mispredicts about
// half the time (bench/README.md, "Branches on random numbers").
inline float select(bool c, float a, float b) {
  const uint32_t m = 0u - static_cast<uint32_t>(c);
  return std::bit_cast<float>((std::bit_cast<uint32_t>(a) & m) | (std::bit_cast<uint32_t>(b) & ~m));
}

// Orthonormal frame; `z` is the normal. Built with the branchless method of
// Duff et al. 2017, "Building an Orthonormal Basis, Revisited".
struct Frame {
  Vec3 x{1, 0, 0};
  Vec3 y{0, 1, 0};
  Vec3 z{0, 0, 1};

  static Frame from_z(const Vec3& n) {
    const float sign = std::copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z);
    const float b = n.x * n.y * a;
    return Frame{Vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x), Vec3(b, sign + n.y * n.y * a, -n.y), n};
  }
  Vec3 to_local(const Vec3& v) const { return {glm::dot(v, x), glm::dot(v, y), glm::dot(v, z)}; }
  Vec3 to_world(const Vec3& v) const { return x * v.x + y * v.y + z * v.z; }
};

// The azimuth of a direction about +Z, from +X towards +Y, in [0, 2π) (spherical_direction's φ),
// from atan2(y, x) in (−π, π].
inline float azimuth_from_atan2(float atan2_phi) { return select(atan2_phi < 0, atan2_phi + kTwoPi, atan2_phi); }
inline float spherical_phi(const Vec3& d) { return azimuth_from_atan2(std::atan2(d.y, d.x)); }

// Unit direction from spherical angles about +Z: azimuth measured from +X towards +Y, given by its
// sine and cosine or by the angle.
inline Vec3 spherical_direction(float sin_theta, float cos_theta, float sin_phi, float cos_phi) {
  return {std::clamp(sin_theta, -1.0f, 1.0f) * cos_phi, std::clamp(sin_theta, -1.0f, 1.0f) * sin_phi,
          std::clamp(cos_theta, -1.0f, 1.0f)};
}
inline Vec3 spherical_direction(float sin_theta, float cos_theta, float phi) {
  return spherical_direction(sin_theta, cos_theta, std::sin(phi), std::cos(phi));
}

}  // namespace sylva
