#pragma once
// Test seam: deliberate light-transport faults for the golden suite's power tests
// (tests/compare/test_golden.cpp), which prove that a real regression is caught by the statistical
// comparison. Production code never builds one: the faults are not part of RenderSettings or
// IntegratorSettings, and reach the renderer only through the constructor overloads that take a
// `TransportFaults` (EmbreeScene, Integrator, Renderer). The default value injects nothing.

namespace sylva {

struct TransportFaults {
  bool no_shadow_alpha = false;  // shadow rays ignore the leaf outlines (EmbreeScene occlusion filter)
  bool mis_weight_one = false;   // NEE and BSDF sampling both weighted 1, so direct light double counts
  // The sky's radiance × sky_horizon_gain between the horizon and sky_horizon_elevation_deg
  // (Environment::inject_horizon_fault): a fault local in direction, e.g. 1.03 for +3 %.
  float sky_horizon_gain = 1.0f;
  float sky_horizon_elevation_deg = 15.0f;
};

}  // namespace sylva
