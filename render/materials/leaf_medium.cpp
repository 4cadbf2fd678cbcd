#include "render/materials/leaf_medium.h"

#include "core/sampling.h"

#include <cmath>

namespace sylva {

namespace {

// (sin β − β cos β) and (sin β + (π − β) cos β) for cos β = c.
void lobe_shapes(float c, float* reflect, float* transmit) {
  c = std::clamp(c, -1.0f, 1.0f);
  const float beta = std::acos(c), s = std::sqrt(std::max(0.0f, 1.0f - c * c));
  *reflect = std::max(0.0f, s - beta * c);
  *transmit = std::max(0.0f, s + (kPi - beta) * c);
}

}  // namespace

LeafPhase make_leaf_phase(const SampledSpectrum& reflect, const SampledSpectrum& transmit) {
  LeafPhase p;
  p.reflect = reflect;
  p.transmit = transmit;
  const float r = average(reflect), t = average(transmit);
  p.p_reflect = r + t > 0.0f ? std::clamp(r / (r + t), 0.05f, 0.95f) : 0.5f;
  return p;
}

SampledSpectrum eval_leaf_phase(const LeafPhase& phase, const Vec3& a, const Vec3& b) {
  float r, t;
  lobe_shapes(glm::dot(a, b), &r, &t);
  const float k = 2.0f / (3.0f * kPi * kPi);
  return phase.reflect * (k * r) + phase.transmit * (k * t);
}

float leaf_phase_pdf(const LeafPhase& phase, const Vec3& a, const Vec3& b) {
  float r, t;
  lobe_shapes(glm::dot(a, b), &r, &t);
  return 2.0f / (3.0f * kPi * kPi) * (phase.p_reflect * r + (1.0f - phase.p_reflect) * t);
}

bool sample_leaf_phase(const LeafPhase& phase, const Vec3& a, Vec2 u_normal, Vec2 u_direction, float u_lobe,
                       LeafPhaseSample* out) {
  // A leaf normal on a's side with density |n·a|/π (the other sign is the same two-sided leaf).
  const Vec3 n = Frame::from_z(a).to_world(sample_cosine_hemisphere(u_normal));
  const bool reflect = u_lobe < phase.p_reflect;
  const Vec3 side = reflect ? -n : n;
  out->direction = glm::normalize(Frame::from_z(side).to_world(sample_cosine_hemisphere(u_direction)));
  out->pdf = leaf_phase_pdf(phase, a, out->direction);
  if (!(out->pdf > 0.0f)) return false;
  out->weight = eval_leaf_phase(phase, a, out->direction) / out->pdf;
  return true;
}

}  // namespace sylva
