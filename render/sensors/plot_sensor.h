#pragma once
// The plot sensor (docs/radiometry.md, "Plot sensor"): what a distant sensor records over a
// rectangular plot, and where the light that falls on the plot goes.
//
// BRF: for each view direction v, the mean over the plot's top surface of the radiance leaving it
// towards v — rays start at points drawn uniformly on the plot's top plane (a horizontal rectangle
// above all geometry) and travel along −v, as from a sensor infinitely far away — band-weighted like
// a rendered pixel and, for Quantity::reflectance, multiplied by π / E_c (the BRF under the scene's
// sun and sky). Each value comes with its Monte Carlo standard error.
//
// Flux budget: light paths from the sun and sky through points drawn uniformly on the plot's top
// plane, followed as an analogue random walk (each surface keeps the absorbed part 1 − ρ − τ of the
// path's weight; Russian roulette as the integrator) until they leave upwards. Tallied per band
// channel as fractions of the incident energy: absorbed by leaves (fAPAR in a visible band), by
// bark and other surfaces, by the ground; reaching the ground unscattered and in total; reflected to
// the sky. On a cyclic plot absorbed + reflected = 1 up to Monte Carlo error.
//
// Deterministic: sample i of view k uses a PCG32 stream hashed from (seed, k, i), and blocks of
// samples are summed in a fixed order, so the results are bit-identical at any thread count.

#include "core/band.h"
#include "render/embree_scene.h"
#include "render/integrator.h"
#include "render/renderer.h"
#include "render/scene.h"

#include <array>
#include <string>
#include <vector>

namespace sylva {

// A view direction: zenith angle and compass azimuth (degrees clockwise from north) of the direction
// from the plot towards the sensor (the sun's convention). `label_deg` is what the output calls it:
// the zenith, or in a principal plane the signed zenith (negative on the sun's side).
struct PlotView {
  float zenith_deg = 0;
  float azimuth_deg = 0;
  float label_deg = 0;
};

// The principal plane: signed view zeniths from `from` to `to` (inclusive) every `step` degrees;
// negative zeniths look from the sun's side (azimuth = the sun's), positive ones from the opposite.
std::vector<PlotView> principal_plane_views(float from_deg, float to_deg, float step_deg, float sun_azimuth_deg);

struct PlotSettings {
  std::vector<PlotView> views;
  int samples = 16384;                     // rays per view direction
  int flux_samples = 65536;                // light paths for the flux budget
  std::vector<uint32_t> ground_materials;  // materials the flux budget counts as ground
};

struct MeasureSettings {
  PlotSettings plot;
  std::vector<Band> bands;
  IntegratorSettings integrator;
  Quantity quantity = Quantity::reflectance;
  uint64_t seed = 1;
  int threads = 0;  // 0 = all hardware threads
};

// Per view, per band channel: the mean and its standard error.
struct BrfTable {
  std::vector<std::string> channels;
  std::vector<PlotView> views;
  std::vector<std::vector<double>> mean, se;  // [view][channel]
  int samples = 0;
  double top_m = 0;  // height of the plot's top plane
};

// Flux fractions per band channel: [channel], each with its standard error (ratio estimator).
struct FluxTable {
  static constexpr int kTerms = 7;
  static constexpr const char* kNames[kTerms] = {"absorbed_leaves",        "absorbed_bark", "absorbed_ground",
                                                 "ground_direct",          "ground_total",  "reflected",
                                                 "absorbed_plus_reflected"};
  std::vector<std::string> channels;
  std::vector<std::array<double, kTerms>> mean, se;  // [channel][term]
  int samples = 0;
};

// Throws sylva::Error if the scene has no plot or the settings are unusable.
BrfTable measure_brf(const Scene& scene, const EmbreeScene& embree, const MeasureSettings& settings);
// Throws sylva::Error also for scenes with turbid crowns (the walk follows surfaces only).
FluxTable measure_flux(const Scene& scene, const EmbreeScene& embree, const MeasureSettings& settings);

}  // namespace sylva
