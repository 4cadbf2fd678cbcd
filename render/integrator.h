#pragma once
// Spectral unidirectional path tracer: hero-wavelength sampling (kLambdaCount wavelengths per
// path), next-event estimation of the sun+sky mixture with multiple importance sampling (power
// heuristic, Veach 1997 §9.2), Russian roulette after three bounces, a maximum depth. Media: the
// turbid crowns (render/materials/leaf_medium.h) and the optional haze (render/media/haze.h), each
// sampled by free flight; a haze collision scatters by the Henyey–Greenstein phase function.
// Emission: an emitting material's radiance (render/materials/emissive.h) counts where a camera
// ray meets it, and the emissive triangles are lights too (render/lights/emitters.h): each surface
// vertex samples a point on them for next-event estimation (one more shadow ray, a finite one), and
// a BSDF-sampled ray that meets one counts its radiance with the power-heuristic weight of the BSDF
// sample against that light sample (Veach 1997 §9.2). Medium vertices (haze, turbid crowns) sample
// only the sun and sky, so emission met after one counts with weight 1, as does emission that is not
// sampled (emitters.h). A scene without emitters draws no random number for them.
#include "core/band.h"
#include "core/rng.h"
#include "core/sampler.h"
#include "render/embree_scene.h"
#include "render/lights/emitters.h"
#include "render/materials/hit_context.h"
#include "render/materials/material.h"
#include "render/media/haze.h"
#include "render/scene.h"
#include "render/testing/faults.h"

#include <span>
#include <vector>

namespace sylva {

// Path length: Russian roulette ends paths (unbiased); max_depth is only a safety cap far beyond
// where roulette has ended practically every path (docs/radiometry.md, "Path length"). A lower cap
// truncates light that needs more bounces and biases bright canopies low.
struct IntegratorSettings {
  int max_depth = 1024;    // scattering events per path: a safety cap
  int rr_start_depth = 3;  // Russian roulette from this bounce on
  // Record the denoiser's first-hit features (FirstHit::shading_normal, feature_class, sun): one
  // more occlusion ray per camera path that meets a surface. Changes no path's radiance or random
  // numbers.
  bool first_hit_features = false;
  // Which estimators of emitted light run: the light samples and BSDF-sampled hits weighted by MIS
  // (kMis, the default), or for tests and debugging one alone: kBsdf (emitters are not sampled as
  // lights; hits count with weight 1), kLight (emission a BSDF-sampled ray meets after a surface
  // vertex is not counted; light samples count with weight 1). Each is unbiased; no command line
  // sets it.
  enum class EmitterSampling : uint8_t { kMis, kBsdf, kLight };
  EmitterSampling emitter_sampling = EmitterSampling::kMis;
  // Sun and sky samples (shadow rays) at a camera path's first surface vertex, 1 to
  // kMaxLightSamples; later vertices take one. They are combined with the vertex's BSDF sample by
  // the power heuristic with sample counts (Veach 1997 §9.2.4). Under a canopy most of a leaf's
  // noise is whether its one sky sample sees the sky through the leaves (bench/README.md, "Where
  // the canopy's noise comes from"); more samples there cost shadow rays, not paths.
  int light_samples = 1;
};
inline constexpr int kMaxLightSamples = 8;

// A path's vertex on a surface, as every walk sees it (camera paths, the plot sensor's flux walk):
// the hit's context with its face and wavelengths set, the directions and normal turned to the
// side wo leaves from, and the BSDF there (Integrator::surface_vertex).
struct SurfaceVertex {
  HitContext ctx;
  Vec3 wo{0.0f};        // world, unit, towards the previous vertex
  Vec3 ng{0.0f};        // geometric normal on wo's side
  Frame frame;          // local shading frame: z = shading normal on wo's side
  Vec3 wo_local{0.0f};  // wo in `frame`
  Bsdf bsdf;
};

// The denoiser's classes of a first hit (FirstHit::feature_class; docs/denoise.md).
enum class FeatureClass : uint8_t {
  kSky,     // no surface
  kLeaf,    // a leaf quad or disc of anything but terrain and grass
  kBark,    // any other surface: wood, meshes, targets
  kGround,  // terrain and grass (Instance::class_id kClassTerrain, kClassGrass)
};

// First-hit data for the AOVs and, with IntegratorSettings::first_hit_features, the denoiser's
// features.
struct FirstHit {
  bool hit = false;
  float t = 0;
  Vec3 normal{0.0f};
  uint32_t instance = 0;  // 0 = background, else instance index + 1
  uint32_t object_id = 0;
  SampledSpectrum albedo{0.0f};
  // Features (first_hit_features): the world shading normal turned to the camera ray's side, the
  // class, and whether the sun's centre is visible from the hit (1) or blocked by a surface (0; 0
  // without a sun). Turbid-crown collisions are not surfaces and record nothing.
  Vec3 shading_normal{0.0f};
  FeatureClass feature_class = FeatureClass::kSky;
  float sun = 0;
};

// A next-event shadow ray waiting for its visibility test, and what its light adds when the ray
// is unoccluded (Integrator::resolve_shadow): the factors a · b · c, the transmittance along the
// ray and the scalars x, y, combined per kind as radiance() always combined them.
struct ShadowQuery {
  enum class Kind : uint8_t {
    kNone,
    kSky,        // from a haze collision: a = β, c = L_e, x = phase · w / pdf
    kSkyLeaf,    // from a crown collision in haze: a = β, b = f, c = L_e, x = w, y = pdf
    kCrownLeaf,  // from a crown collision: a = β, b = f, c = L_e, x = w, y = pdf
    kSurface,    // from a surface: a = β · f · |cos θ|, c = L_e, x = w, y = pdf
    kEmitter,    // from a surface to an emitter's point: as kSurface, the ray ends at t_max, and
                 // starts in a turbid crown of extinction sigma_t (0: none)
  };
  Kind kind = Kind::kNone;
  uint32_t from = kNoInstance;  // the instance whose surface the ray leaves (EmbreeScene::occluded)
  Vec3 origin{0.0f}, direction{0.0f};
  SampledSpectrum a{0.0f}, b{0.0f}, c{0.0f};
  float x = 0, y = 0;
  float t_max = std::numeric_limits<float>::infinity();
  float sigma_t = 0;
};

// One path in flight: what radiance() keeps from bounce to bounce. A caller may hold several and
// trace their rays together (Renderer: a pixel's samples), each path giving the same bits as
// radiance() would.
struct PathState {
  PathState() = default;
  PathState(const Ray& camera_ray, const SampledWavelengths& wavelengths, PathSampler& random, FirstHit* first_hit)
      : ray(camera_ray), wl(wavelengths), sampler(&random), first(first_hit) {}
  // The same as assigning PathState(camera_ray, ...), written in place: a temporary's copy would
  // reload its fields right after storing them at other offsets, which the processor cannot
  // forward (a stall per path; bench/README.md, "Four at a time").
  void start(const Ray& camera_ray, const SampledWavelengths& wavelengths, PathSampler& random, FirstHit* first_hit) {
    ray = camera_ray;
    from = kNoInstance;
    wl = wavelengths;
    sampler = &random;
    first = first_hit;
    L = SampledSpectrum(0.0f);
    beta = SampledSpectrum(1.0f);
    haze_ratio = SampledSpectrum(1.0f);
    prev_pdf = 0.0f;
    sigma_t = 0.0f;
    medium_material = 0;
    crossings = 0;
    depth = 0;
    alive = true;
    emitters_sampled = false;
    prev_p = Vec3(0.0f);
    prev_light_samples = 1.0f;
    shadows = 0;
    emitter_shadow.kind = ShadowQuery::Kind::kNone;
  }

  Ray ray;                      // the next ray to trace
  uint32_t from = kNoInstance;  // the instance whose surface `ray` leaves (EmbreeScene::intersect)
  SampledWavelengths wl;
  PathSampler* sampler = nullptr;  // the path's random numbers (events from 1 on: advance())
  FirstHit* first = nullptr;       // optional
  SampledSpectrum L{0.0f}, beta{1.0f};
  // With haze: the path's free-flight density per carried wavelength over the hero's (Haze::sample_scattering).
  SampledSpectrum haze_ratio{1.0f};
  float prev_pdf = 0.0f;  // solid-angle pdf of the BSDF sample that produced `ray`; 0 = camera ray
  // The turbid crown the path is in (docs/fournier_grindal.md): σ_t = G·LAD, 0 outside; crossing a
  // crown's boundary is not a scattering event and does not count towards the depth.
  float sigma_t = 0.0f;
  uint32_t medium_material = 0;
  int crossings = 0;
  int depth = 0;
  bool alive = true;
  // Whether the vertex `ray` leaves is a surface that sampled the emitters (so emission it meets is
  // weighted by MIS), and that vertex's position (for the light sample's density there).
  bool emitters_sampled = false;
  Vec3 prev_p{0.0f};
  float prev_light_samples = 1.0f;  // light samples the vertex `ray` leaves took (MIS's count)
  int shadows = 0;                  // this bounce's next-event shadow rays: shadow[0, shadows)
  ShadowQuery shadow[kMaxLightSamples];
  ShadowQuery emitter_shadow;  // this bounce's shadow ray to an emitter (render/lights/emitters.h), if any
};
// start() sets every field but the shadow queries' payload (read only once counted or its kind is
// set): a field added to PathState must be added there too.
// (5 spectra and 3 per shadow query: 16 bytes per block of each beyond the first.)
static_assert(sizeof(PathState) ==
                  184 + 16 * 5 * (kLambdaBlocks - 1) + (kMaxLightSamples + 1) * (96 + 16 * 3 * (kLambdaBlocks - 1)),
              "PathState::start() must set every field");

class Integrator {
 public:
  Integrator(const Scene& scene, const EmbreeScene& embree, const Environment& environment,
             IntegratorSettings settings);
  // Test seam: the same integrator with deliberate faults (render/testing/faults.h).
  Integrator(const Scene& scene, const EmbreeScene& embree, const Environment& environment, IntegratorSettings settings,
             const TransportFaults& faults);

  // Radiance along `ray` for the carried wavelengths. `first` (optional) receives first-hit data;
  // `rays` is incremented by the number of rays traced (closest-hit and shadow).
  SampledSpectrum radiance(Ray ray, const SampledWavelengths& wl, Pcg32& rng, FirstHit* first, uint64_t& rays) const;
  SampledSpectrum radiance(Ray ray, const SampledWavelengths& wl, PathSampler& sampler, FirstHit* first,
                           uint64_t& rays) const;

  // Traces paths.size() ≤ kMaxPaths paths to their ends in lock-step, bounce by bounce: the
  // closest-hit rays of all, then their shading, then their shadow rays, so each stage's code stays
  // in the instruction cache (Renderer: a pixel's samples; bench/README.md). Each path's L, random
  // numbers and rays are those it gives alone; radiance() is one path through the same stages.
  static constexpr int kMaxPaths = 16;
  void trace_paths(std::span<PathState> paths, uint64_t& rays) const;

  // The hit's context (world space), from the prototype's mesh data: everything but the face and
  // the wavelengths, which the caller sets before a material is evaluated.
  HitContext interaction(const Ray& ray, const RayHit& hit) const;

  // The transport step every walk shares, written once: the surface vertex where `ray` meets
  // `hit` (its context, face, frame and BSDF from the scene's materials), ...
  SurfaceVertex surface_vertex(const Ray& ray, const RayHit& hit, const SampledWavelengths& wl) const;
  // ... and the path's continuation by sampling the BSDF with (u, u_lobe): multiplies `beta` by
  // the sample's weight f·|cos|/pdf, sets `pdf` and the next ray (offset to the side it leaves
  // to). False, with nothing changed, when the path ends there: no direction was sampled, or the
  // shading and geometric normals disagree on the side it would leave to.
  bool scatter(const SurfaceVertex& v, Vec2 u, float u_lobe, SampledSpectrum& beta, float& pdf, Ray& next) const;

  // Beer's law along o + t d (d unit) through the turbid crowns it crosses, exp(−Σ σ_t·length),
  // σ_t = G·LAD; assumes no opaque surface on the way (check occluded() first) and crowns that do
  // not overlap. 1 in scenes without turbid crowns.
  float medium_transmittance(const Vec3& o, const Vec3& d, uint64_t& rays) const;
  // The same along the segment o + t d, t in [0, t_max), which starts in a turbid crown of extinction
  // sigma_t (0: outside every crown) and may end inside one (a shadow ray to an emitter).
  float segment_transmittance(const Vec3& o, const Vec3& d, float t_max, float sigma_t, uint64_t& rays) const;

  // Next-event estimation's light sample, the one place the transport samples lights: draws its two
  // random numbers always (so a path's draws do not depend on the scene's lights), then samples the
  // sun + sky mixture; pdf 0 when the scene has no light. Callers use a sample with pdf > 0 and
  // non-black radiance.
  LightSample sample_light(const SampledWavelengths& wl, PathSampler& sampler) const;
  LightSample sample_light(const SampledWavelengths& wl, Pcg32& rng) const;
  // The j-th of n light samples at one vertex: point j of the vertex's n in its stratified sequence
  // (PathSampler::get2d(dim, j, n)).
  LightSample sample_light(const SampledWavelengths& wl, PathSampler& sampler, uint32_t j, uint32_t n) const;

  // The crowns' transmittance times the haze's (per wavelength) along an unoccluded ray to the sky.
  SampledSpectrum sky_transmittance(const Vec3& o, const Vec3& d, const SampledWavelengths& wl, uint64_t& rays) const;

 private:
  const Scene& scene_;
  const EmbreeScene& embree_;
  const Environment& environment_;
  IntegratorSettings settings_;
  TransportFaults faults_;
  bool has_media_ = false;  // some prototype has a turbid crown
  Haze haze_;               // the scene's haze; disabled: no extra work, no random numbers
  MaterialLobes lobes_;     // the scene's materials as evaluated at hits (BSDFs, emission)
  EmitterLights emitters_;  // the emitters sampled as lights; empty: no random numbers for them

  // trace_paths' stages: advance() shades path.ray's hit, leaving the bounce's shadow rays in
  // path.shadow and the next ray in path.ray; resolve_shadow() traces the shadow rays and adds their light.
  void advance(PathState& path, bool found, const RayHit& hit) const;
  void resolve_shadow(PathState& path, uint64_t& rays) const;
  void resolve_sky_shadow(PathState& path, const ShadowQuery& q, uint64_t& rays) const;
  // advance()'s events: a collision in the haze at distance s, a collision with the leaves of the
  // turbid crown the path is in, the crossing of a crown's boundary, a surface. Each leaves the
  // shadow ray and the next ray; the scattering ones end with roulette_then_next_bounce (Russian
  // roulette from rr_start_depth, then depth + 1).
  void scatter_in_haze(PathState& path, bool found, const RayHit& hit, float s) const;
  void scatter_in_crown(PathState& path, float s) const;
  void cross_crown_boundary(PathState& path, const RayHit& hit, const HalfSpaceSolid& crown) const;
  void scatter_at_surface(PathState& path, const RayHit& hit) const;
  // A surface vertex's light sample j of n on the sun and sky (a shadow query in path.shadow).
  void sample_sky_at_surface(PathState& path, const SurfaceVertex& v, uint32_t j, uint32_t n) const;
  void roulette_then_next_bounce(PathState& path) const;
  // A surface vertex's light sample on the emitters (path.emitter_shadow), and the MIS weight of
  // emission that a ray leaving the previous vertex meets at `hit` (si its context).
  void sample_emitter(PathState& path, const SurfaceVertex& v) const;
  float emission_weight(const PathState& path, const RayHit& hit, const HitContext& si) const;
  void resolve_emitter_shadow(PathState& path, uint64_t& rays) const;
  void record_first_hit(const HitContext& si, const Bsdf& bsdf, const Ray& ray, float t, FirstHit* first) const;
  // The first-hit features of FirstHit (first_hit_features).
  void record_first_hit_features(const HitContext& si, const Ray& ray, FirstHit* first) const;
};

// Moves `p` off the surface along `n` (the side the new ray leaves to) by a few ulps scaled with
// |p|: Wächter & Binder, "A Fast and Robust Method for Avoiding Self-Intersection", Ray Tracing
// Gems ch. 6.
Vec3 offset_ray_origin(const Vec3& p, const Vec3& n);

}  // namespace sylva
