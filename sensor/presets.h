#pragma once
// Named cameras for [sensor] preset = "NAME" (docs/sensors.md, "Presets"). Each names the source
// of its figures; what the source does not give is marked as an assumption there.

#include "sensor/sensor_params.h"

#include <string>
#include <vector>

namespace sylva {

struct SensorPreset {
  std::string name;
  std::string source;
  SensorParams params;  // params.preset and params.source set
};

// Every preset, in a fixed order.
const std::vector<SensorPreset>& sensor_presets();
// The preset called `name`, or nullptr.
const SensorPreset* find_sensor_preset(const std::string& name);

}  // namespace sylva
