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
      lobes_(scene.materials) {}

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

LightSample Integrator::sample_light(const SampledWavelengths& wl, Pcg32& rng) const {
  const Vec2 u_light = uniform2(rng);
  const float u_select = rng.uniform();
  if (environment_.empty()) return LightSample{Vec3(0.0f), SampledSpectrum(0.0f), 0.0f};
  return environment_.sample(u_light, u_select, wl);
}

void Integrator::record_first_hit(const HitContext& si, const Bsdf& bsdf, float t, FirstHit* first) const {
  first->hit = true;
  first->t = t;
  first->normal = si.ng;
  first->instance = si.instance + 1;
  first->object_id = si.object_id;
  first->albedo = bsdf.albedo();
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
  PathState path(ray, wl, rng, first);
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
  path.shadow.kind = ShadowQuery::Kind::kNone;
  const Ray& ray = path.ray;
  const float t_surface = found ? hit.t : std::numeric_limits<float>::infinity();
  const float s_crown = path.sigma_t > 0.0f ? -std::log(1.0f - path.rng->uniform()) / path.sigma_t : t_surface;
  if (haze_.enabled()) {
    // The haze's collision competes with the crown's and the surface (independent media: the
    // nearer event happens; docs/radiometry.md, "Haze").
    const float s = haze_.sample_scattering(ray.origin, ray.direction, std::min(s_crown, t_surface), path.wl, *path.rng,
                                            path.beta, path.haze_ratio);
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
      path.L += path.beta * le * power_heuristic(path.prev_pdf, environment_.pdf(ray.direction));
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
    if (path.rng->uniform() < q) {
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
  Pcg32& rng = *path.rng;
  // The AOVs describe the first surface on the camera ray whether or not the haze scatters the path
  // before it.
  if (path.first && path.depth == 0 && found && !turbid_crown(scene_, hit)) {
    HitContext si = interaction(ray, hit);
    si.front = glm::dot(-ray.direction, si.ng) > 0;
    si.wl = &wl;
    record_first_hit(si, lobes_.bsdf(si), hit.t, path.first);
  }
  if (path.depth + 1 > settings_.max_depth) {
    path.alive = false;
    return;
  }
  const Vec3 p = ray.origin + s * ray.direction;
  const float g = haze_.desc().g;
  if (const LightSample ls = sample_light(wl, rng); ls.pdf > 0 && !is_black(ls.radiance)) {
    const float phase = henyey_greenstein(glm::dot(ray.direction, ls.wi), g);
    const float w = power_heuristic(ls.pdf, phase);
    path.shadow =
        ShadowQuery{ShadowQuery::Kind::kSky, kNoInstance, p, ls.wi, path.beta, SampledSpectrum(1.0f), ls.radiance,
                    phase * w / ls.pdf};
  }
  const Vec3 wi = sample_henyey_greenstein(ray.direction, g, uniform2(rng));
  path.prev_pdf = henyey_greenstein(glm::dot(ray.direction, wi), g);
  ray = Ray{p, wi};
  path.from = kNoInstance;
  roulette_then_next_bounce(path);
}

void Integrator::scatter_in_crown(PathState& path, float s) const {
  Ray& ray = path.ray;
  const SampledWavelengths& wl = path.wl;
  Pcg32& rng = *path.rng;
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
  if (const LightSample ls = sample_light(wl, rng); ls.pdf > 0 && !is_black(ls.radiance)) {
    const SampledSpectrum f = eval_leaf_phase(phase, ray.direction, ls.wi);
    if (!is_black(f)) {
      const float w = power_heuristic(ls.pdf, leaf_phase_pdf(phase, ray.direction, ls.wi));
      path.shadow = ShadowQuery{haze_.enabled() ? ShadowQuery::Kind::kSkyLeaf : ShadowQuery::Kind::kCrownLeaf,
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
  const Vec2 u_normal = uniform2(rng), u_direction = uniform2(rng);
  const float u_lobe = rng.uniform();
  LeafPhaseSample ps;
  if (!sample_leaf_phase(phase, ray.direction, u_normal, u_direction, u_lobe, &ps)) {
    path.alive = false;
    return;
  }
  path.beta *= ps.weight;
  path.prev_pdf = ps.pdf;
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
  Pcg32& rng = *path.rng;
  const SurfaceVertex v = surface_vertex(ray, hit, wl);
  const HitContext& si = v.ctx;
  const Vec3& ng = v.ng;
  const Bsdf& bsdf = v.bsdf;
  // Emission: emitters are not sampled as lights, so a camera or BSDF-sampled ray that meets one
  // takes its whole radiance (the power heuristic's weight when the light-sampling pdf is 0).
  if (lobes_.emits(si.material)) path.L += path.beta * lobes_.emitted(si);
  if (path.first && path.depth == 0) record_first_hit(si, bsdf, hit.t, path.first);
  if (path.depth + 1 > settings_.max_depth) {
    path.alive = false;
    return;
  }
  const Vec3& wo_local = v.wo_local;

  // Next-event estimation towards the sun + sky mixture.
  if (const LightSample ls = sample_light(wl, rng); ls.pdf > 0 && !is_black(ls.radiance)) {
    const Vec3 wi_local = v.frame.to_local(ls.wi);
    const float cos_g = glm::dot(ls.wi, ng);
    const bool transmits = cos_g < 0;
    // The geometric and shading sides must agree, or light would leak through the surface.
    if ((wi_local.z > 0) == !transmits && cos_g != 0) {
      const SampledSpectrum f = bsdf.eval(wo_local, wi_local);
      if (!is_black(f)) {
        const float w = faults_.mis_weight_one ? 1.0f : power_heuristic(ls.pdf, bsdf.pdf(wo_local, wi_local));
        path.shadow = ShadowQuery{ShadowQuery::Kind::kSurface,
                                  si.instance,
                                  offset_ray_origin(si.p, transmits ? -ng : ng),
                                  ls.wi,
                                  path.beta * f * std::abs(wi_local.z),
                                  SampledSpectrum(1.0f),
                                  ls.radiance,
                                  w,
                                  ls.pdf};
      }
    }
  }

  // Continue the path by sampling the BSDF.
  const Vec2 u_bsdf = uniform2(rng);
  const float u_lobe = rng.uniform();
  if (!scatter(v, u_bsdf, u_lobe, path.beta, path.prev_pdf, ray)) {
    path.alive = false;
    return;
  }
  path.from = si.instance;
  roulette_then_next_bounce(path);
}

void Integrator::resolve_shadow(PathState& path, uint64_t& rays) const {
  // The expressions radiance() had in line, term by term in the same order (same bits).
  const ShadowQuery& q = path.shadow;
  const ShadowQuery::Kind kind = q.kind;
  if (kind == ShadowQuery::Kind::kNone) return;
  path.shadow.kind = ShadowQuery::Kind::kNone;  // resolved; the rest of the query is read below
  ++rays;
  if (embree_.occluded(q.origin, q.direction, std::numeric_limits<float>::infinity(), q.from)) return;
  switch (kind) {
    case ShadowQuery::Kind::kNone:
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
