#pragma once
// A BSDF at a hit: one or more lobes, each with eval, pdf and sample, for the carried
// wavelengths. Directions are in the local shading frame (HitContext::shading_frame): z = shading
// normal on the side of `wo`, which points away from the surface towards the previous vertex.
//
// Lobes form a closed set (`Lobe`, a std::variant: a glossy lobe is a new alternative with the
// same four operations); the Bsdf picks one to sample with probability proportional to its mean
// albedo over the carried wavelengths. Per-ray dispatch is static (docs/style.md, rule 5).

#include "core/math.h"
#include "core/sampling.h"
#include "core/spectrum.h"

#include <array>
#include <variant>

namespace sylva {

// One lobe's sample: wi (local frame), its density and the weight f·|cos θi|/pdf.
struct LobeSample {
  Vec3 wi{0.0f};
  SampledSpectrum weight{0.0f};
  float pdf = 0;
};

// Lambertian reflection (wi on wo's side of the surface) or transmission (the other side):
// f = albedo/π on its hemisphere, cosine-weighted sampling there.
struct LambertLobe {
  SampledSpectrum albedo;  // hemispherical reflectance ρ or transmittance τ per wavelength
  bool transmission = false;

  bool on_its_side(const Vec3& wo, const Vec3& wi) const { return ((wo.z > 0) == (wi.z > 0)) != transmission; }
  SampledSpectrum eval(const Vec3& wo, const Vec3& wi) const {
    return on_its_side(wo, wi) ? albedo * kInvPi : SampledSpectrum(0.0f);
  }
  float pdf(const Vec3& wo, const Vec3& wi) const {
    return on_its_side(wo, wi) ? cosine_hemisphere_pdf(std::abs(wi.z)) : 0.0f;
  }
  bool sample(const Vec3& wo, Vec2 u, LobeSample* out) const {
    Vec3 wi = sample_cosine_hemisphere(u);
    if (wi.z <= 0) return false;
    const float side = select(wo.z >= 0, 1.0f, -1.0f);
    wi.z *= select(transmission, -side, side);
    out->wi = wi;
    out->pdf = cosine_hemisphere_pdf(std::abs(wi.z));
    out->weight = albedo;  // f·cos/pdf = (ρ/π)·cos / (cos/π)
    return true;
  }
};

using Lobe = std::variant<LambertLobe>;

// What Bsdf::sample returns.
struct BsdfSample {
  Vec3 wi;                // local frame
  SampledSpectrum value;  // f · |cos θi| / pdf
  float pdf = 0;
  bool transmitted = false;
};

class Bsdf {
 public:
  static constexpr int kMaxLobes = 3;

  // Lobes are added, then finish() sets the selection probabilities; a Bsdf without lobes is black.
  void add(const Lobe& lobe) {
    transmits_[count_] = std::visit([](const auto& l) { return l.transmission; }, lobe);
    for (int i = 0; i < count_; ++i) disjoint_ = disjoint_ && transmits_[i] != transmits_[count_];
    lobes_[count_++] = lobe;
  }
  // Each lobe is selected with probability ∝ its mean albedo (the first when all are black); the
  // last takes 1 − the others' sum, so the probabilities add to one exactly.
  void finish() {
    float mean[kMaxLobes], sum = 0;
    for (int i = 0; i < count_; ++i) sum += (mean[i] = average(albedo_of(i)));
    float rest = 1.0f;
    for (int i = 0; i + 1 < count_; ++i) {
      p_[i] = sum > 0 ? mean[i] / sum : (i == 0 ? 1.0f : 0.0f);
      rest -= p_[i];
    }
    if (count_ > 0) p_[count_ - 1] = count_ == 1 ? 1.0f : rest;
  }

  // f(wo, wi) (no cosine): the sum of the lobes.
  SampledSpectrum eval(const Vec3& wo, const Vec3& wi) const {
    SampledSpectrum f(0.0f);
    for (int i = 0; i < count_; ++i) f += std::visit([&](const auto& l) { return l.eval(wo, wi); }, lobes_[i]);
    return f;
  }
  // The density of sample()'s directions: Σ p_i · pdf_i.
  float pdf(const Vec3& wo, const Vec3& wi) const {
    float pdf = 0;
    for (int i = 0; i < count_; ++i) pdf += p_[i] * std::visit([&](const auto& l) { return l.pdf(wo, wi); }, lobes_[i]);
    return pdf;
  }
  // Picks lobe i with u_lobe, samples it with u. Where no other lobe reaches wi's hemisphere (the
  // lobes lie on distinct sides) the value is the lobe's weight / p_i; otherwise the one-sample
  // mixture f·|cos|/Σ p pdf (Veach 1997 §9.2.4). Returns false when no direction was sampled.
  bool sample(const Vec3& wo, Vec2 u, float u_lobe, BsdfSample* out) const {
    if (count_ == 0) return false;
    int i = 0;
    for (float cdf = p_[0]; i + 1 < count_ && u_lobe >= cdf; cdf += p_[i]) ++i;
    const float p = p_[i];
    if (p <= 0) return false;
    LobeSample ls;
    if (!std::visit([&](const auto& l) { return l.sample(wo, u, &ls); }, lobes_[i])) return false;
    out->wi = ls.wi;
    out->transmitted = transmits_[i];
    if (disjoint_) {
      out->pdf = p * ls.pdf;
      out->value = ls.weight / p;
    } else {
      out->pdf = pdf(wo, ls.wi);
      out->value = out->pdf > 0 ? eval(wo, ls.wi) * (std::abs(ls.wi.z) / out->pdf) : SampledSpectrum(0.0f);
    }
    return out->pdf > 0;
  }

  // Hemispherical reflectance + transmittance (the albedo AOV).
  SampledSpectrum albedo() const {
    SampledSpectrum a(0.0f);
    for (int i = 0; i < count_; ++i) a += albedo_of(i);
    return a;
  }
  // The reflection lobes' part of albedo().
  SampledSpectrum reflectance() const {
    SampledSpectrum a(0.0f);
    for (int i = 0; i < count_; ++i)
      if (!transmits_[i]) a += albedo_of(i);
    return a;
  }
  int lobe_count() const { return count_; }
  const Lobe& lobe(int i) const { return lobes_[i]; }

 private:
  SampledSpectrum albedo_of(int i) const {
    return std::visit([](const auto& l) { return l.albedo; }, lobes_[i]);
  }

  std::array<Lobe, kMaxLobes> lobes_;
  std::array<float, kMaxLobes> p_{};  // selection probabilities
  std::array<bool, kMaxLobes> transmits_{};
  int count_ = 0;
  bool disjoint_ = true;  // no two lobes share a hemisphere
};

}  // namespace sylva
