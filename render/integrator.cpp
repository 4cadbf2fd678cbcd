#include "render/integrator.h"

#include "core/error.h"
#include "core/simd.h"
#include "render/materials/leaf_medium.h"
#include "render/materials/material.h"

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
      haze_(scene.haze),
      lobes_(scene.materials) {
  for (const Prototype& p : scene.prototypes)
    for (const HalfSpaceSolid& solid : p.solids) has_media_ = has_media_ || solid.leaf_area_density > 0.0f;
}

const HalfSpaceSolid* Integrator::turbid_solid(const RayHit& hit) const {
  if (!hit.solid) return nullptr;
  const HalfSpaceSolid& solid = scene_.prototypes[scene_.instances[hit.instance].prototype].solids[hit.primitive];
  return solid.leaf_area_density > 0.0f ? &solid : nullptr;
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
    const HalfSpaceSolid* medium = turbid_solid(hit);
    if (medium == nullptr) return 0.0f;
    // Unit, as offset_ray_origin expects: the normal matrix scales it by 1/scale for scaled crowns.
    const Vec3 n = glm::normalize(normal_from_object(scene_.instances[hit.instance]) * hit.normal);
    const bool entering = glm::dot(d, n) < 0.0f;
    // Leaving a crown: the segment since the last crossing (or the start) was inside it.
    if (!entering) optical_depth += static_cast<double>(kSphericalG * medium->leaf_area_density) * hit.t;
    ray = Ray{offset_ray_origin(ray.origin + hit.t * d, entering ? -n : n), d};
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
  si.leaf = hit.leaf;
  if (hit.solid) {
    // A half-space solid (Fournier–Grindal): the point on the world ray, its texture looked up in
    // the crown's own coordinates (§4) to pick the palette material.
    si.p = ray.origin + hit.t * ray.direction;
    const Vec3 p_obj = Vec3(glm::inverse(inst.world_from_object) * Vec4(si.p, 1.0f));
    const std::vector<uint32_t>& palette = proto.solid_palettes[hit.primitive];
    const HalfSpaceSolid& solid = proto.solids[hit.primitive];
    si.material = palette[solid_palette_index(solid.colouring, p_obj, static_cast<uint32_t>(palette.size()))];
    si.ng = glm::normalize(normal_from_object(inst) * hit.normal);
    si.ns = si.ng;
    return si;
  }
  if (hit.curve) {
    // A grass blade: a thin two-sided leaf (reflectance and transmittance) at the hit point.
    si.p = ray.origin + hit.t * ray.direction;
    si.material = proto.curve_material;
    const Vec3 n = normal_from_object(inst) * hit.normal;
    const float ln = glm::length(n);
    si.ng = ln > 0 ? n / ln : -ray.direction;
    si.ns = si.ng;
    return si;
  }
  if (hit.disc) {
    // An exact leaf disc: the point on the world ray, the disc's normal as its upper side.
    si.p = ray.origin + hit.t * ray.direction;
    si.ng = glm::normalize(normal_from_object(inst) * proto.discs.normal[hit.primitive]);
    si.ns = si.ng;
    si.material = proto.disc_material;
    si.leaf = true;
    return si;
  }
  // Leaf quads and mesh triangles, the hits nearly every path meets: GLM's arithmetic in SSE
  // registers (core/simd.h: the same operations in the same order, so the same bits).
  using namespace simd;
  // normal_from_object(inst): the cofactors of the linear part, signed by its determinant.
  const Columns3 m = linear_part(inst.world_from_object);
  Columns3 nfo{cross(m.c1, m.c2), cross(m.c2, m.c0), cross(m.c0, m.c1)};
  if (dot(m.c0, nfo.c0) < 0) {
    const __m128 sign = splat(-0.0f);
    nfo = {_mm_xor_ps(nfo.c0, sign), _mm_xor_ps(nfo.c1, sign), _mm_xor_ps(nfo.c2, sign)};
  }
  __m128 p_obj, ng_obj, ns_obj = _mm_setzero_ps();
  bool shading_normals = false;  // ns_obj differs from ng_obj (a mesh with vertex normals)
  if (hit.leaf) {
    const Vec3* c = &proto.leaves.corners[4 * size_t(hit.primitive)];
    // Embree's quad parametrisation: triangle (c0,c1,c3) weighted (1−u−v, u, v) for u+v <= 1,
    // (c2,c3,c1) weighted (u+v−1, 1−u, 1−v) beyond. Which half a ray meets is random: the corners
    // and weights are selected, not branched on (the same arithmetic either way).
    const bool far = hit.u + hit.v > 1.0f;
    const __m128 a = load(far ? c[2] : c[0]);
    const __m128 b = load(far ? c[3] : c[1]);
    const __m128 d = load(far ? c[1] : c[3]);
    const float wa = select(far, hit.u + hit.v - 1.0f, 1.0f - hit.u - hit.v);
    const float wb = select(far, 1.0f - hit.u, hit.u), wd = select(far, 1.0f - hit.v, hit.v);
    p_obj = _mm_add_ps(_mm_add_ps(_mm_mul_ps(splat(wa), a), _mm_mul_ps(splat(wb), b)), _mm_mul_ps(splat(wd), d));
    ng_obj = cross(_mm_sub_ps(b, a), _mm_sub_ps(d, a));
    si.material = proto.leaf_material;
    si.uv = Vec2(hit.u, hit.v);  // Embree's quad coordinates are the leaf's (geometry/mesh.h)
    if (!proto.leaves.stem.empty()) si.stem = proto.leaves.stem[hit.primitive];
  } else {
    const TriangleMesh& mesh = proto.triangles;
    const glm::uvec3 t = mesh.triangles[hit.primitive];
    const __m128 b0 = splat(1.0f - hit.u - hit.v), b1 = splat(hit.u), b2 = splat(hit.v);
    const __m128 p0 = load(mesh.positions[t.x]), p1 = load(mesh.positions[t.y]), p2 = load(mesh.positions[t.z]);
    p_obj = _mm_add_ps(_mm_add_ps(_mm_mul_ps(b0, p0), _mm_mul_ps(b1, p1)), _mm_mul_ps(b2, p2));
    ng_obj = cross(_mm_sub_ps(p1, p0), _mm_sub_ps(p2, p0));
    shading_normals = !mesh.normals.empty();
    if (shading_normals)
      ns_obj = _mm_add_ps(_mm_add_ps(_mm_mul_ps(b0, load(mesh.normals[t.x])), _mm_mul_ps(b1, load(mesh.normals[t.y]))),
                          _mm_mul_ps(b2, load(mesh.normals[t.z])));
    si.material = proto.triangle_material;
    si.uv = Vec2(hit.u, hit.v);
  }
  si.p = store(transform_point(inst.world_from_object, p_obj));
  const __m128 ng = transform(nfo, ng_obj);
  const float lg = std::sqrt(dot(ng, ng));  // glm::length
  si.ng = lg > 0 ? store(_mm_div_ps(ng, splat(lg))) : -ray.direction;
  if (!shading_normals) {
    si.ns = si.ng;  // what the lines below give for ns_obj = ng_obj, without computing it twice
    return si;
  }
  const __m128 ns = transform(nfo, ns_obj);
  const float ls = std::sqrt(dot(ns, ns));
  si.ns = ls > 0 ? store(_mm_div_ps(ns, splat(ls))) : si.ng;
  if (glm::dot(si.ns, si.ng) < 0) si.ns = -si.ns;
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
  // path.shadow for resolve_shadow(). The locals are the path's own (references into `path`).
  Ray& ray = path.ray;
  const SampledWavelengths& wl = path.wl;
  Pcg32& rng = *path.rng;
  FirstHit* first = path.first;
  SampledSpectrum& L = path.L;
  SampledSpectrum& beta = path.beta;
  float& prev_pdf = path.prev_pdf;
  float& sigma_t = path.sigma_t;
  const int depth = path.depth;
  ShadowQuery& shadow = path.shadow;
  shadow.kind = ShadowQuery::Kind::kNone;
  // `continue` of the loop this was: the next bounce (a crown crossing does not count as one).
  const auto next_bounce = [&path](int increment = 1) { path.depth += increment; };
  const auto end_path = [&path] { path.alive = false; };
  // Russian roulette from rr_start_depth (survivors weighted 1/(1 − q)), then the next bounce.
  const auto roulette_then_next_bounce = [&] {
    if (depth + 1 >= settings_.rr_start_depth) {
      const float q = std::max(0.05f, 1.0f - max_component(beta));
      if (rng.uniform() < q) return end_path();
      beta /= 1.0f - q;
    }
    if (is_black(beta)) return end_path();
    next_bounce();
  };

  const float t_surface = found ? hit.t : std::numeric_limits<float>::infinity();
  // Free-flight sampling: a collision with a leaf before the next surface scatters the path.
  const float s_crown = sigma_t > 0.0f ? -std::log(1.0f - rng.uniform()) / sigma_t : t_surface;
  if (haze_.enabled()) {
    // The haze's collision competes with the crown's and the surface (independent media: the
    // nearer event happens; docs/radiometry.md, "Haze").
    const float s = haze_.sample_scattering(ray.origin, ray.direction, std::min(s_crown, t_surface), wl, rng, beta,
                                            path.haze_ratio);
    if (s < std::numeric_limits<float>::infinity()) {
      // The AOVs describe the first surface on the camera ray whether or not the haze scatters
      // the path before it.
      if (first && depth == 0 && found && !turbid_solid(hit)) {
        HitContext si = interaction(ray, hit);
        si.front = glm::dot(-ray.direction, si.ng) > 0;
        si.wl = &wl;
        record_first_hit(si, lobes_.bsdf(si), ray, hit.t, first);
      }
      if (depth + 1 > settings_.max_depth) return end_path();
      const Vec3 p = ray.origin + s * ray.direction;
      const float g = haze_.desc().g;
      if (const LightSample ls = sample_light(wl, rng); ls.pdf > 0 && !is_black(ls.radiance)) {
        {
          const float phase = henyey_greenstein(glm::dot(ray.direction, ls.wi), g);
          const float w = power_heuristic(ls.pdf, phase);
          shadow = ShadowQuery{ShadowQuery::Kind::kSky, kNoInstance, p, ls.wi, beta, SampledSpectrum(1.0f), ls.radiance,
                               phase * w / ls.pdf};
        }
      }
      const Vec3 wi = sample_henyey_greenstein(ray.direction, g, uniform2(rng));
      prev_pdf = henyey_greenstein(glm::dot(ray.direction, wi), g);
      ray = Ray{p, wi};
      path.from = kNoInstance;
      return roulette_then_next_bounce();
    }
  }
  if (sigma_t > 0.0f) {
    const float s = s_crown;
    if (s < t_surface) {
      if (depth + 1 > settings_.max_depth) return end_path();
      const Vec3 p = ray.origin + s * ray.direction;
      HitContext in_crown;  // a leaf of the crown's material, seen from its front
      in_crown.p = p;
      in_crown.material = path.medium_material;
      in_crown.wl = &wl;
      const Bsdf leaf = lobes_.bsdf(in_crown);
      const LeafPhase phase = make_leaf_phase(leaf.reflectance(), leaf.albedo() - leaf.reflectance());
      if (const LightSample ls = sample_light(wl, rng); ls.pdf > 0 && !is_black(ls.radiance)) {
        {
          const SampledSpectrum f = eval_leaf_phase(phase, ray.direction, ls.wi);
          if (!is_black(f)) {
            const float w = power_heuristic(ls.pdf, leaf_phase_pdf(phase, ray.direction, ls.wi));
            shadow = ShadowQuery{haze_.enabled() ? ShadowQuery::Kind::kSkyLeaf : ShadowQuery::Kind::kCrownLeaf,
                                 kNoInstance,
                                 p,
                                 ls.wi,
                                 beta,
                                 f,
                                 ls.radiance,
                                 w,
                                 ls.pdf};
          }
        }
      }
      const Vec2 u_normal = uniform2(rng), u_direction = uniform2(rng);
      const float u_lobe = rng.uniform();
      LeafPhaseSample ps;
      if (!sample_leaf_phase(phase, ray.direction, u_normal, u_direction, u_lobe, &ps)) return end_path();
      beta *= ps.weight;
      prev_pdf = ps.pdf;
      ray = Ray{p, ps.direction};
      path.from = kNoInstance;
      return roulette_then_next_bounce();
    }
  }
  if (found) {
    if (const HalfSpaceSolid* medium = turbid_solid(hit)) {
      const Vec3 n = glm::normalize(normal_from_object(scene_.instances[hit.instance]) * hit.normal);
      const bool entering = glm::dot(ray.direction, n) < 0.0f;
      if (entering) {
        const Prototype& proto = scene_.prototypes[scene_.instances[hit.instance].prototype];
        sigma_t = kSphericalG * medium->leaf_area_density;
        path.medium_material = proto.solid_palettes[hit.primitive].front();
      } else {
        sigma_t = 0.0f;
      }
      ray = Ray{offset_ray_origin(ray.origin + hit.t * ray.direction, entering ? -n : n), ray.direction};
      path.from = hit.instance;
      if (++path.crossings > 1024) return end_path();
      return next_bounce(0);
    }
  }
  if (!found) {
    const SampledSpectrum le = environment_.eval(ray.direction, wl);
    if (depth == 0 || faults_.mis_weight_one) {
      L += beta * le;
    } else {
      L += beta * le * power_heuristic(prev_pdf, environment_.pdf(ray.direction));
    }
    return end_path();
  }
  const SurfaceVertex v = surface_vertex(ray, hit, wl);
  const HitContext& si = v.ctx;
  const Vec3& ng = v.ng;
  const Frame& frame = v.frame;
  const Bsdf& bsdf = v.bsdf;
  // Emission: emitters are not sampled as lights, so a camera or BSDF-sampled ray that meets one
  // takes its whole radiance (the power heuristic's weight when the light-sampling pdf is 0).
  if (lobes_.emits(si.material)) L += beta * lobes_.emitted(si);
  if (first && depth == 0) record_first_hit(si, bsdf, ray, hit.t, first);
  if (depth + 1 > settings_.max_depth) return end_path();
  const Vec3& wo_local = v.wo_local;

  // Next-event estimation towards the sun + sky mixture.
  if (const LightSample ls = sample_light(wl, rng); ls.pdf > 0 && !is_black(ls.radiance)) {
    {
      const Vec3 wi_local = frame.to_local(ls.wi);
      const float cos_g = glm::dot(ls.wi, ng);
      const bool transmits = cos_g < 0;
      // The geometric and shading sides must agree, or light would leak through the surface.
      if ((wi_local.z > 0) == !transmits && cos_g != 0) {
        const SampledSpectrum f = bsdf.eval(wo_local, wi_local);
        if (!is_black(f)) {
          const float w = faults_.mis_weight_one ? 1.0f : power_heuristic(ls.pdf, bsdf.pdf(wo_local, wi_local));
          shadow = ShadowQuery{ShadowQuery::Kind::kSurface,
                               si.instance,
                               offset_ray_origin(si.p, transmits ? -ng : ng),
                               ls.wi,
                               beta * f * std::abs(wi_local.z),
                               SampledSpectrum(1.0f),
                               ls.radiance,
                               w,
                               ls.pdf};
        }
      }
    }
  }

  // Continue the path by sampling the BSDF.
  const Vec2 u_bsdf = uniform2(rng);
  const float u_lobe = rng.uniform();
  if (!scatter(v, u_bsdf, u_lobe, beta, prev_pdf, ray)) return end_path();
  path.from = si.instance;

  return roulette_then_next_bounce();
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
