#include "render/integrator.h"

#include "core/error.h"
#include "core/simd.h"
#include "render/materials/leaf_medium.h"
#include "render/materials/material.h"
#include "render/primitives/curves.h"
#include "render/primitives/discs.h"
#include "render/primitives/leaf_quads.h"
#include "render/primitives/media.h"
#include "render/primitives/solids.h"
#include "render/primitives/triangles.h"

#include <fmt/core.h>

namespace sylva {

namespace {

float power_heuristic(float a, float b) {
  const float a2 = a * a, b2 = b * b;
  return a2 + b2 > 0 ? a2 / (a2 + b2) : 0.0f;
}

}  // namespace

Vec3 offset_ray_origin(const Vec3& p, const Vec3& n) {
  constexpr float kOrigin = 1.0f / 32.0f;
  constexpr float kFloatScale = 1.0f / 65536.0f;
  constexpr float kIntScale = 256.0f;
  // The three coordinates side by side, each with the scalar method's operations (same bits): p's
  // bits moved by 256·n ulps away from the surface, or, near the origin where ulps are tiny, p
  // moved by n/65 536.
  const __m128 pv = simd::load(p), nv = simd::load(n);
  const __m128i of = _mm_cvttps_epi32(_mm_mul_ps(simd::splat(kIntScale), nv));
  const __m128i negative = _mm_castps_si128(_mm_cmplt_ps(pv, _mm_setzero_ps()));   // all ones where p < 0
  const __m128i signed_of = _mm_sub_epi32(_mm_xor_si128(of, negative), negative);  // −of there
  const __m128 moved = _mm_castsi128_ps(_mm_add_epi32(_mm_castps_si128(pv), signed_of));
  const __m128 abs_p = _mm_andnot_ps(simd::splat(-0.0f), pv);
  const __m128 near = _mm_cmplt_ps(abs_p, simd::splat(kOrigin));
  const __m128 nudged = _mm_add_ps(pv, _mm_mul_ps(simd::splat(kFloatScale), nv));
  return simd::store(simd::select(near, nudged, moved));
}

Integrator::Integrator(const Scene& scene, const EmbreeScene& embree, const Environment& environment,
                       IntegratorSettings settings)
    : Integrator(scene, embree, environment, settings, TransportFaults{}) {}

Integrator::Integrator(const Scene& scene, const EmbreeScene& embree, const Environment& environment,
                       IntegratorSettings settings, const TransportFaults& faults)
    : scene_(scene),
      embree_(embree),
      environment_(environment),
      settings_(settings),
      faults_(faults),
      has_media_(has_turbid_crowns(scene)),
      haze_(scene.haze),
      lobes_(scene.materials) {
  if (settings_.emitter_sampling != IntegratorSettings::EmitterSampling::kBsdf) emitters_ = EmitterLights(scene);
}

float Integrator::medium_transmittance(const Vec3& o, const Vec3& d, uint64_t& rays) const {
  if (!has_media_) return 1.0f;
  constexpr int kMaxCrossings = 256;
  double optical_depth = 0.0;
  Ray ray{o, d};
  uint32_t from = kNoInstance;
  for (int i = 0; i < kMaxCrossings; ++i) {
    RayHit hit;
    ++rays;
    if (!embree_.intersect(ray, &hit, from)) break;
    const HalfSpaceSolid* crown = turbid_crown(scene_, hit);
    if (crown == nullptr) return 0.0f;
    const CrownCrossing c = cross_crown(scene_, hit, *crown, d);
    // Leaving a crown: the segment since the last crossing (or the start) was inside it.
    if (!c.entering) optical_depth += static_cast<double>(c.sigma_t) * hit.t;
    ray = Ray{offset_ray_origin(ray.origin + hit.t * d, c.entering ? -c.normal : c.normal), d};
    from = hit.instance;
  }
  return static_cast<float>(std::exp(-optical_depth));
}

float Integrator::segment_transmittance(const Vec3& o, const Vec3& d, float t_max, float sigma_t,
                                        uint64_t& rays) const {
  constexpr int kMaxCrossings = 256;
  // The distance left is measured to the segment's end each time: a crossing's origin moves off the
  // boundary, forwards, by as much as the end was moved off the emitter (offset_ray_origin).
  const Vec3 end = o + t_max * d;
  double optical_depth = 0.0;
  float sigma = sigma_t, remaining = t_max;
  Ray ray{o, d};
  uint32_t from = kNoInstance;
  for (int i = 0; i < kMaxCrossings && remaining > 0; ++i) {
    RayHit hit;
    ++rays;
    ray.t_max = remaining;
    if (!embree_.intersect(ray, &hit, from)) break;
    const HalfSpaceSolid* crown = turbid_crown(scene_, hit);
    if (crown == nullptr) return 0.0f;
    const CrownCrossing c = cross_crown(scene_, hit, *crown, d);
    optical_depth += static_cast<double>(sigma) * hit.t;
    sigma = c.entering ? c.sigma_t : 0.0f;
    ray = Ray{offset_ray_origin(ray.origin + hit.t * d, c.entering ? -c.normal : c.normal), d};
    remaining = glm::dot(end - ray.origin, d);
    from = hit.instance;
  }
  optical_depth += static_cast<double>(sigma) * std::max(remaining, 0.0f);
  return static_cast<float>(std::exp(-optical_depth));
}

LightSample Integrator::sample_light(const SampledWavelengths& wl, Pcg32& rng) const {
  PathSampler sampler(rng);
  return sample_light(wl, sampler);
}

LightSample Integrator::sample_light(const SampledWavelengths& wl, PathSampler& sampler) const {
  return sample_light(wl, sampler, 0, 1);  // draw 0 of 1 is the plain draw (PathSampler::get2d)
}

LightSample Integrator::sample_light(const SampledWavelengths& wl, PathSampler& sampler, uint32_t j, uint32_t n) const {
  const Vec2 u_light = sampler.get2d(SampleDim::kLight, j, n);
  const float u_select = sampler.get1d(SampleDim::kLightSelect, j, n);
  if (environment_.empty()) return LightSample{Vec3(0.0f), SampledSpectrum(0.0f), 0.0f};
  return environment_.sample(u_light, u_select, wl);
}

void Integrator::record_first_hit(const HitContext& si, const Bsdf& bsdf, const Ray& ray, float t,
                                  FirstHit* first) const {
  first->hit = true;
  first->t = t;
  first->normal = si.ng;
  first->instance = si.instance + 1;
  first->object_id = si.object_id;
  first->albedo = bsdf.albedo();
  if (settings_.first_hit_features) record_first_hit_features(si, ray, first);
}

void Integrator::record_first_hit_features(const HitContext& si, const Ray& ray, FirstHit* first) const {
  first->shading_normal = glm::dot(si.ns, ray.direction) > 0 ? -si.ns : si.ns;
  const uint32_t class_id = scene_.instances[si.instance].class_id;
  if (class_id == kClassTerrain || class_id == kClassGrass)
    first->feature_class = FeatureClass::kGround;
  else
    first->feature_class = si.leaf ? FeatureClass::kLeaf : FeatureClass::kBark;
  // The sun's centre, seen from the side of the surface it lies on: a fixed direction, so no
  // random number is drawn and the path's own are untouched.
  first->sun = 0.0f;
  if (environment_.sun_selection_probability() > 0) {
    const Vec3& sun = environment_.sun_axis();
    const Vec3 n = glm::dot(sun, si.ng) > 0 ? si.ng : -si.ng;
    const bool blocked =
        embree_.occluded(offset_ray_origin(si.p, n), sun, std::numeric_limits<float>::infinity(), si.instance);
    first->sun = blocked ? 0.0f : 1.0f;
  }
}

SampledSpectrum Integrator::sky_transmittance(const Vec3& o, const Vec3& d, const SampledWavelengths& wl,
                                              uint64_t& rays) const {
  SampledSpectrum t(medium_transmittance(o, d, rays));
  if (haze_.enabled()) t *= haze_.transmittance(o, d, std::numeric_limits<float>::infinity(), wl);
  return t;
}

HitContext Integrator::interaction(const Ray& ray, const RayHit& hit) const {
  const Instance& inst = scene_.instances[hit.instance];
  const Prototype& proto = scene_.prototypes[inst.prototype];
  HitContext si;
  si.instance = hit.instance;
  si.object_id = inst.object_id;
  si.prototype = inst.prototype;
  si.primitive = hit.primitive;
  // Each kind decodes its own hits (render/primitives/); meshes and leaf quads in object space,
  // moved to the world by the code they share.
  switch (hit.kind) {
    case PrimitiveKind::kTriangles:
      finish_surface_hit(ray, inst, decode_triangle_hit(proto, hit, si), si);
      break;
    case PrimitiveKind::kLeafQuads:
      finish_surface_hit(ray, inst, decode_leaf_quad_hit(proto, hit, si), si);
      break;
    case PrimitiveKind::kSolids:
      decode_solid_hit(ray, hit, inst, proto, si);
      break;
    case PrimitiveKind::kCurves:
      decode_curve_hit(ray, hit, inst, proto, si);
      break;
    case PrimitiveKind::kDiscs:
      decode_disc_hit(ray, hit, inst, proto, si);
      break;
  }
  return si;
}

SurfaceVertex Integrator::surface_vertex(const Ray& ray, const RayHit& hit, const SampledWavelengths& wl) const {
  SurfaceVertex v;
  v.ctx = interaction(ray, hit);
  v.wo = -ray.direction;
  v.ctx.front = glm::dot(v.wo, v.ctx.ng) > 0;
  v.ctx.wl = &wl;
  v.ng = v.ctx.front ? v.ctx.ng : -v.ctx.ng;
  v.frame = v.ctx.shading_frame();
  v.wo_local = v.frame.to_local(v.wo);
  v.bsdf = lobes_.bsdf(v.ctx);
  return v;
}

bool Integrator::scatter(const SurfaceVertex& v, Vec2 u, float u_lobe, SampledSpectrum& beta, float& pdf,
                         Ray& next) const {
  BsdfSample bs;
  if (!v.bsdf.sample(v.wo_local, u, u_lobe, &bs)) return false;
  const Vec3 wi = v.frame.to_world(bs.wi);
  const float cos_g = glm::dot(wi, v.ng);
  if (cos_g == 0 || (cos_g < 0) != bs.transmitted) return false;  // shading/geometry disagreement
  beta *= bs.value;
  pdf = bs.pdf;
  next = Ray{offset_ray_origin(v.ctx.p, bs.transmitted ? -v.ng : v.ng), wi};
  return true;
}

SampledSpectrum Integrator::radiance(Ray ray, const SampledWavelengths& wl, Pcg32& rng, FirstHit* first,
                                     uint64_t& rays) const {
  PathSampler sampler(rng);
  return radiance(ray, wl, sampler, first, rays);
}

SampledSpectrum Integrator::radiance(Ray ray, const SampledWavelengths& wl, PathSampler& sampler, FirstHit* first,
                                     uint64_t& rays) const {
  PathState path(ray, wl, sampler, first);
  trace_paths({&path, 1}, rays);
  return path.L;
}

void Integrator::trace_paths(std::span<PathState> paths, uint64_t& rays) const {
  if (paths.size() > static_cast<size_t>(kMaxPaths))
    throw Error(fmt::format("trace_paths: {} paths, at most {} at a time", paths.size(), kMaxPaths));
  RayHit hits[kMaxPaths];
  bool found[kMaxPaths];
  // The paths still alive, in order. Which ones end at a bounce is random, so the list is kept
  // without a branch per path (bench/README.md, "Branches on random numbers").
  PathState* live[kMaxPaths];
  size_t n = 0;
  for (PathState& path : paths) {
    live[n] = &path;
    n += path.alive;
  }
  while (n > 0) {
    for (size_t k = 0; k < n; ++k) found[k] = embree_.intersect(live[k]->ray, &hits[k], live[k]->from);
    rays += n;
    for (size_t k = 0; k < n; ++k) advance(*live[k], found[k], hits[k]);
    // A path that ended at this bounce may still have its last shadow ray to resolve.
    size_t still = 0;
    for (size_t k = 0; k < n; ++k) {
      resolve_shadow(*live[k], rays);
      live[still] = live[k];
      still += live[k]->alive;
    }
    n = still;
  }
}

void Integrator::advance(PathState& path, bool found, const RayHit& hit) const {
  // One bounce of the path: the body of radiance()'s loop, with the next-event shadow ray left in
  // path.shadow for resolve_shadow(). The nearest of three events ends the ray: a collision in the
  // haze, a collision with a turbid crown's leaves (free-flight sampling), or the surface hit.
  path.shadows = 0;
  const Ray& ray = path.ray;
  const float t_surface = found ? hit.t : std::numeric_limits<float>::infinity();
  PathSampler& sampler = *path.sampler;
  // Each event's random numbers are its own dimensions (core/sampler.h): depth + crossings grows
  // by one at every event a path lives through.
  sampler.start_event(1 + static_cast<uint32_t>(path.depth + path.crossings));
  const float s_crown =
      path.sigma_t > 0.0f ? -std::log(1.0f - sampler.get1d(SampleDim::kFreeFlight)) / path.sigma_t : t_surface;
  if (haze_.enabled()) {
    // The haze's collision competes with the crown's and the surface (independent media: the
    // nearer event happens; docs/radiometry.md, "Haze").
    const float s = haze_.sample_scattering(ray.origin, ray.direction, std::min(s_crown, t_surface), path.wl,
                                            sampler.get1d(SampleDim::kHaze), path.beta, path.haze_ratio);
    if (s < std::numeric_limits<float>::infinity()) return scatter_in_haze(path, found, hit, s);
  }
  if (path.sigma_t > 0.0f && s_crown < t_surface) return scatter_in_crown(path, s_crown);
  if (found) {
    if (const HalfSpaceSolid* crown = turbid_crown(scene_, hit)) return cross_crown_boundary(path, hit, *crown);
  }
  if (!found) {
    const SampledSpectrum le = environment_.eval(ray.direction, path.wl);
    if (path.depth == 0 || faults_.mis_weight_one) {
      path.L += path.beta * le;
    } else {
      path.L +=
          path.beta * le * power_heuristic(path.prev_pdf, path.prev_light_samples * environment_.pdf(ray.direction));
    }
    path.alive = false;
    return;
  }
  scatter_at_surface(path, hit);
}

void Integrator::roulette_then_next_bounce(PathState& path) const {
  // Russian roulette from rr_start_depth (survivors weighted 1/(1 − q)), then the next bounce.
  if (path.depth + 1 >= settings_.rr_start_depth) {
    const float q = std::max(0.05f, 1.0f - max_component(path.beta));
    if (path.sampler->get1d(SampleDim::kRoulette) < q) {
      path.alive = false;
      return;
    }
    path.beta /= 1.0f - q;
  }
  if (is_black(path.beta)) {
    path.alive = false;
    return;
  }
  path.depth += 1;
}

void Integrator::scatter_in_haze(PathState& path, bool found, const RayHit& hit, float s) const {
  Ray& ray = path.ray;
  const SampledWavelengths& wl = path.wl;
  PathSampler& sampler = *path.sampler;
  // The AOVs describe the first surface on the camera ray whether or not the haze scatters the path
  // before it.
  if (path.first && path.depth == 0 && found && !turbid_crown(scene_, hit)) {
    HitContext si = interaction(ray, hit);
    si.front = glm::dot(-ray.direction, si.ng) > 0;
    si.wl = &wl;
    record_first_hit(si, lobes_.bsdf(si), ray, hit.t, path.first);
  }
  if (path.depth + 1 > settings_.max_depth) {
    path.alive = false;
    return;
  }
  const Vec3 p = ray.origin + s * ray.direction;
  const float g = haze_.desc().g;
  if (const LightSample ls = sample_light(wl, sampler); ls.pdf > 0 && !is_black(ls.radiance)) {
    const float phase = henyey_greenstein(glm::dot(ray.direction, ls.wi), g);
    const float w = power_heuristic(ls.pdf, phase);
    path.shadow[path.shadows++] =
        ShadowQuery{ShadowQuery::Kind::kSky, kNoInstance, p, ls.wi, path.beta, SampledSpectrum(1.0f), ls.radiance,
                    phase * w / ls.pdf};
  }
  const Vec3 wi = sample_henyey_greenstein(ray.direction, g, sampler.get2d(SampleDim::kScatter));
  path.prev_pdf = henyey_greenstein(glm::dot(ray.direction, wi), g);
  path.prev_light_samples = 1.0f;
  path.emitters_sampled = false;
  ray = Ray{p, wi};
  path.from = kNoInstance;
  roulette_then_next_bounce(path);
}

void Integrator::scatter_in_crown(PathState& path, float s) const {
  Ray& ray = path.ray;
  const SampledWavelengths& wl = path.wl;
  PathSampler& sampler = *path.sampler;
  if (path.depth + 1 > settings_.max_depth) {
    path.alive = false;
    return;
  }
  const Vec3 p = ray.origin + s * ray.direction;
  HitContext in_crown;  // a leaf of the crown's material, seen from its front
  in_crown.p = p;
  in_crown.material = path.medium_material;
  in_crown.wl = &wl;
  const Bsdf leaf = lobes_.bsdf(in_crown);
  const LeafPhase phase = make_leaf_phase(leaf.reflectance(), leaf.albedo() - leaf.reflectance());
  if (const LightSample ls = sample_light(wl, sampler); ls.pdf > 0 && !is_black(ls.radiance)) {
    const SampledSpectrum f = eval_leaf_phase(phase, ray.direction, ls.wi);
    if (!is_black(f)) {
      const float w = power_heuristic(ls.pdf, leaf_phase_pdf(phase, ray.direction, ls.wi));
      path.shadow[path.shadows++] =
          ShadowQuery{haze_.enabled() ? ShadowQuery::Kind::kSkyLeaf : ShadowQuery::Kind::kCrownLeaf,
                      kNoInstance,
                      p,
                      ls.wi,
                      path.beta,
                      f,
                      ls.radiance,
                      w,
                      ls.pdf};
    }
  }
  const Vec2 u_normal = sampler.get2d(SampleDim::kScatterNormal);
  const Vec2 u_direction = sampler.get2d(SampleDim::kScatter);
  const float u_lobe = sampler.get1d(SampleDim::kLobe);
  LeafPhaseSample ps;
  if (!sample_leaf_phase(phase, ray.direction, u_normal, u_direction, u_lobe, &ps)) {
    path.alive = false;
    return;
  }
  path.beta *= ps.weight;
  path.prev_pdf = ps.pdf;
  path.prev_light_samples = 1.0f;
  path.emitters_sampled = false;
  ray = Ray{p, ps.direction};
  path.from = kNoInstance;
  roulette_then_next_bounce(path);
}

void Integrator::cross_crown_boundary(PathState& path, const RayHit& hit, const HalfSpaceSolid& crown) const {
  // Crossing a crown's boundary is not a scattering event and does not count towards the depth.
  Ray& ray = path.ray;
  const CrownCrossing c = cross_crown(scene_, hit, crown, ray.direction);
  path.sigma_t = c.entering ? c.sigma_t : 0.0f;
  if (c.entering) path.medium_material = c.material;
  ray = Ray{offset_ray_origin(ray.origin + hit.t * ray.direction, c.entering ? -c.normal : c.normal), ray.direction};
  path.from = hit.instance;
  if (++path.crossings > 1024) path.alive = false;
}

void Integrator::scatter_at_surface(PathState& path, const RayHit& hit) const {
  Ray& ray = path.ray;
  const SampledWavelengths& wl = path.wl;
  PathSampler& sampler = *path.sampler;
  const SurfaceVertex v = surface_vertex(ray, hit, wl);
  const HitContext& si = v.ctx;
  // Emission, weighted against the previous vertex's light sample on the emitters (integrator.h).
  if (lobes_.emits(si.material)) path.L += path.beta * lobes_.emitted(si) * emission_weight(path, hit, si);
  if (path.first && path.depth == 0) record_first_hit(si, v.bsdf, ray, hit.t, path.first);
  if (path.depth + 1 > settings_.max_depth) {
    path.alive = false;
    return;
  }

  // Next-event estimation towards the sun + sky mixture: light_samples of it at the first vertex.
  const uint32_t n_light = path.depth == 0 ? static_cast<uint32_t>(settings_.light_samples) : 1u;
  for (uint32_t j = 0; j < n_light; ++j) sample_sky_at_surface(path, v, j, n_light);

  // Next-event estimation towards the emitters, in scenes that have some.
  if (!emitters_.empty()) sample_emitter(path, v);

  // Continue the path by sampling the BSDF.
  const Vec2 u_bsdf = sampler.get2d(SampleDim::kScatter);
  const float u_lobe = sampler.get1d(SampleDim::kLobe);
  if (!scatter(v, u_bsdf, u_lobe, path.beta, path.prev_pdf, ray)) {
    path.alive = false;
    return;
  }
  path.from = si.instance;
  path.prev_light_samples = static_cast<float>(n_light);
  path.emitters_sampled = !emitters_.empty();
  path.prev_p = si.p;
  roulette_then_next_bounce(path);
}

void Integrator::sample_sky_at_surface(PathState& path, const SurfaceVertex& v, uint32_t j, uint32_t n) const {
  // With n samples each counts 1/n of the estimate, weighted against the BSDF sample by the power
  // heuristic on n·p_light (Veach 1997 §9.2.4): x = w, y = n·p_light.
  const LightSample ls = sample_light(*v.ctx.wl, *path.sampler, j, n);
  if (!(ls.pdf > 0) || is_black(ls.radiance)) return;
  const Vec3 wi_local = v.frame.to_local(ls.wi);
  const float cos_g = glm::dot(ls.wi, v.ng);
  const bool transmits = cos_g < 0;
  // The geometric and shading sides must agree, or light would leak through the surface.
  if ((wi_local.z > 0) != !transmits || cos_g == 0) return;
  const SampledSpectrum f = v.bsdf.eval(v.wo_local, wi_local);
  if (is_black(f)) return;
  const float pdf = static_cast<float>(n) * ls.pdf;
  const float w = faults_.mis_weight_one ? 1.0f : power_heuristic(pdf, v.bsdf.pdf(v.wo_local, wi_local));
  path.shadow[path.shadows++] = ShadowQuery{ShadowQuery::Kind::kSurface,
                                            v.ctx.instance,
                                            offset_ray_origin(v.ctx.p, transmits ? -v.ng : v.ng),
                                            ls.wi,
                                            path.beta * f * std::abs(wi_local.z),
                                            SampledSpectrum(1.0f),
                                            ls.radiance,
                                            w,
                                            pdf};
}

void Integrator::sample_emitter(PathState& path, const SurfaceVertex& v) const {
  // A point on an emitter (by power, then uniform on its triangle), as a direction: the density per
  // area times d²/|cos θ_light| (Veach 1997 §9.2; pbrt-v4 §12.3 "Area lights").
  const float u_select = path.sampler->get1d(SampleDim::kEmitterSelect);
  const Vec2 u = path.sampler->get2d(SampleDim::kEmitter);
  EmitterPoint e = emitters_.sample(u_select, u);
  const Vec3 to = e.ctx.p - v.ctx.p;
  const float dist2 = glm::dot(to, to);
  if (!(e.pdf_area > 0) || !(dist2 > 0)) return;
  const Vec3 wi = to / std::sqrt(dist2);
  const float cos_light = -glm::dot(e.ctx.ng, wi);  // > 0: the vertex faces the emitter's front
  if (cos_light == 0) return;
  e.ctx.front = cos_light > 0;
  e.ctx.wl = &path.wl;
  const SampledSpectrum le = lobes_.emitted(e.ctx);
  if (is_black(le)) return;
  const Vec3 wi_local = v.frame.to_local(wi);
  const float cos_g = glm::dot(wi, v.ng);
  const bool transmits = cos_g < 0;
  if ((wi_local.z > 0) != !transmits || cos_g == 0) return;  // shading/geometry disagreement
  const SampledSpectrum f = v.bsdf.eval(v.wo_local, wi_local);
  if (is_black(f)) return;
  const float pdf = e.pdf_area * dist2 / std::abs(cos_light);
  const bool light_only = settings_.emitter_sampling == IntegratorSettings::EmitterSampling::kLight;
  const float w = light_only ? 1.0f : power_heuristic(pdf, v.bsdf.pdf(v.wo_local, wi_local));
  // The shadow ray runs between the two points, each moved off its surface towards the other.
  const Vec3 origin = offset_ray_origin(v.ctx.p, transmits ? -v.ng : v.ng);
  const Vec3 d = offset_ray_origin(e.ctx.p, e.ctx.front ? e.ctx.ng : -e.ctx.ng) - origin;
  const float length = glm::length(d);
  if (!(length > 0)) return;
  ShadowQuery& q = path.emitter_shadow;
  q = ShadowQuery{ShadowQuery::Kind::kEmitter,
                  v.ctx.instance,
                  origin,
                  d / length,
                  path.beta * f * std::abs(wi_local.z),
                  SampledSpectrum(1.0f),
                  le,
                  w,
                  pdf};
  q.t_max = length;
  q.sigma_t = path.sigma_t;
}

float Integrator::emission_weight(const PathState& path, const RayHit& hit, const HitContext& si) const {
  // A camera ray, or a ray from a medium vertex or in a scene without sampled emitters: weight 1.
  if (path.depth == 0 || !path.emitters_sampled) return 1.0f;
  const float pdf_area = emitters_.pdf_area(hit);
  if (!(pdf_area > 0)) return 1.0f;  // not a sampled emitter
  if (settings_.emitter_sampling == IntegratorSettings::EmitterSampling::kLight) return 0.0f;
  const float cos_light = std::abs(glm::dot(si.ng, path.ray.direction));
  if (!(cos_light > 0)) return 1.0f;
  const Vec3 d = si.p - path.prev_p;
  return power_heuristic(path.prev_pdf, pdf_area * glm::dot(d, d) / cos_light);
}

void Integrator::resolve_emitter_shadow(PathState& path, uint64_t& rays) const {
  const ShadowQuery& q = path.emitter_shadow;
  path.emitter_shadow.kind = ShadowQuery::Kind::kNone;
  ++rays;
  if (embree_.occluded(q.origin, q.direction, q.t_max, q.from)) return;
  const float transmittance =
      has_media_ ? segment_transmittance(q.origin, q.direction, q.t_max, q.sigma_t, rays) : 1.0f;
  SampledSpectrum contribution = q.a * q.c * (q.x * transmittance / q.y);
  if (haze_.enabled()) contribution *= haze_.transmittance(q.origin, q.direction, q.t_max, path.wl);
  path.L += contribution;
}

void Integrator::resolve_shadow(PathState& path, uint64_t& rays) const {
  if (path.emitter_shadow.kind != ShadowQuery::Kind::kNone) resolve_emitter_shadow(path, rays);
  const int n = path.shadows;
  path.shadows = 0;  // resolved; the queries are read below
  for (int i = 0; i < n; ++i) resolve_sky_shadow(path, path.shadow[i], rays);
}

void Integrator::resolve_sky_shadow(PathState& path, const ShadowQuery& q, uint64_t& rays) const {
  // The expressions radiance() had in line, term by term in the same order (same bits).
  ++rays;
  if (embree_.occluded(q.origin, q.direction, std::numeric_limits<float>::infinity(), q.from)) return;
  switch (q.kind) {
    case ShadowQuery::Kind::kNone:
    case ShadowQuery::Kind::kEmitter:  // resolve_emitter_shadow
      break;
    case ShadowQuery::Kind::kSky:  // a haze collision: a = β, c = L_e, x = phase · w / pdf
      path.L += q.a * q.c * sky_transmittance(q.origin, q.direction, path.wl, rays) * q.x;
      break;
    case ShadowQuery::Kind::kSkyLeaf:  // a crown collision in haze: a = β, b = f, x = w, y = pdf
      path.L += q.a * q.b * q.c * sky_transmittance(q.origin, q.direction, path.wl, rays) * (q.x / q.y);
      break;
    case ShadowQuery::Kind::kCrownLeaf:  // a crown collision: a = β, b = f, x = w, y = pdf
      path.L += q.a * q.b * q.c * (medium_transmittance(q.origin, q.direction, rays) * q.x / q.y);
      break;
    case ShadowQuery::Kind::kSurface: {  // a surface: a = β · f · |cos θ|, x = w, y = pdf
      const float transmittance = has_media_ ? medium_transmittance(q.origin, q.direction, rays) : 1.0f;
      SampledSpectrum contribution = q.a * q.c * (q.x * transmittance / q.y);
      if (haze_.enabled())
        contribution *= haze_.transmittance(q.origin, q.direction, std::numeric_limits<float>::infinity(), path.wl);
      path.L += contribution;
      break;
    }
  }
}

}  // namespace sylva
