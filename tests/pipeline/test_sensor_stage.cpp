// The sensor stage of the render call (pipeline/sensor_stage.h): [sensor] leaves the render's
// pixels as they were and writes the sensed image, its sidecar and preview beside them, recording
// the parameters and seeds; bad [sensor] input is `file:line: what was expected`.

#include "core/error.h"
#include "core/image.h"
#include "pipeline/render_call.h"
#include "pipeline/sensor_stage.h"
#include "tests/support/box_scene.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace sylva {
namespace {

RenderCallOptions sensor_options(const std::string& sensor_toml, const std::filesystem::path& exr,
                                 const std::filesystem::path& png = {}) {
  RenderCallOptions o;
  o.request.source = SceneSource::from_text(std::string(test::kBoxSceneToml) + sensor_toml, "sensor scene");
  o.request.threads = 2;
  o.exr = exr;
  o.png = png;
  return o;
}

std::string sensor_file_text(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class SensorStage : public test::TempDirTest {};

TEST_F(SensorStage, KeepsThePreSensorRenderAndWritesTheSensedImageBesideIt) {
  RenderObserver quiet;
  const RenderResult plain = render_scene(sensor_options("", dir_ / "plain.exr"), quiet);
  const RenderResult sensed =
      render_scene(sensor_options("\n[sensor]\npreset = \"machine_vision_12bit\"\noversample = 2\nnoise_seed = 5\n",
                                  dir_ / "s.exr", dir_ / "s.png"),
                   quiet);
  EXPECT_TRUE(plain.sensor.pixels.empty());
  ASSERT_EQ(plain.image.pixels.size(), sensed.image.pixels.size());
  EXPECT_EQ(plain.image.pixels, sensed.image.pixels) << "the pre-sensor radiance changed";
  for (const char* name : {"s.exr", "s.png", "s.sensor.exr", "s.sensor.json", "s.sensor.png"})
    EXPECT_TRUE(std::filesystem::exists(dir_ / name)) << name;
  const Image file = read_exr(dir_ / "s.sensor.exr");
  EXPECT_EQ(file.width, 12);
  EXPECT_EQ(file.height, 8);
  for (const char* c : {"R", "G", "B", "nir.Y", "optical.R", "optical.nir.Y"}) EXPECT_GE(file.find_channel(c), 0) << c;
  EXPECT_EQ(file.attribute("sylva:sensor:preset"), "machine_vision_12bit");
  EXPECT_EQ(file.attribute("sylva:sensor:noise_seed"), "5");
  EXPECT_NE(file.attribute("sylva:sensor:calibration:G").find("radiance = "), std::string::npos);
  EXPECT_EQ(sensed.sensor.pixels, file.pixels);
  const std::string json = sensor_file_text(dir_ / "s.sensor.json");
  EXPECT_NE(json.find("\"noise_seed\": 5"), std::string::npos) << json;
  EXPECT_NE(json.find("\"radiance_per_dn\""), std::string::npos) << json;
  // The calibration gives the optical radiance back from the numbers, on average over the image.
  const int g = file.find_channel("G"), og = file.find_channel("optical.G");
  double dn = 0, optical = 0;
  for (int y = 0; y < file.height; ++y)
    for (int x = 0; x < file.width; ++x) dn += file.at(x, y, g), optical += file.at(x, y, og);
  const double n = file.width * file.height;
  const std::string cal = file.attribute("sylva:sensor:calibration:G");
  double per_dn = 0, offset = 0;
  ASSERT_EQ(std::sscanf(cal.c_str(), "radiance = %lf * (DN - %lf)", &per_dn, &offset), 2) << cal;
  EXPECT_NEAR(per_dn * (dn / n - offset) / (optical / n), 1.0, 0.02);
}

TEST_F(SensorStage, SameSeedsSameFilesAndTheSeedFollowsTheRender) {
  RenderObserver quiet;
  const std::string sensor = "\n[sensor]\npreset = \"phone_8bit\"\n";
  render_scene(sensor_options(sensor, dir_ / "a.exr"), quiet);
  render_scene(sensor_options(sensor, dir_ / "b.exr"), quiet);
  EXPECT_EQ(sensor_file_text(dir_ / "a.sensor.exr"), sensor_file_text(dir_ / "b.sensor.exr"));
  RenderCallOptions other = sensor_options(sensor, dir_ / "c.exr");
  other.request.seed = 77;
  render_scene(other, quiet);
  EXPECT_NE(read_exr(dir_ / "a.sensor.exr").attribute("sylva:sensor:noise_seed"),
            read_exr(dir_ / "c.sensor.exr").attribute("sylva:sensor:noise_seed"));
}

TEST_F(SensorStage, BadInputIsFileLineWhatWasExpected) {
  RenderObserver quiet;
  const auto message = [&](const std::string& sensor) -> std::string {
    try {
      render_scene(sensor_options(sensor, dir_ / "x.exr"), quiet);
    } catch (const Error& e) {
      return e.what();
    }
    return "no error";
  };
  // The line after "[sensor]", which follows the box scene and a blank line.
  const std::string where =
      "sensor scene:" +
      std::to_string(std::count(test::kBoxSceneToml, test::kBoxSceneToml + std::strlen(test::kBoxSceneToml), '\n') +
                     3) +
      ": ";
  const std::string key = message("\n[sensor]\nf_numbre = 2\n");
  EXPECT_NE(key.find(where + "unknown key 'f_numbre' in [sensor] (expected one of: preset, f_number"),
            std::string::npos)
      << key;
  EXPECT_NE(key.find("oversample"), std::string::npos) << key;
  const std::string preset = message("\n[sensor]\npreset = \"hubble\"\n");
  EXPECT_NE(preset.find(where + "unknown sensor preset 'hubble' (expected one of: machine_vision_12bit"),
            std::string::npos)
      << preset;
  const std::string range = message("\n[sensor]\nadc_bits = 40\n");
  EXPECT_NE(range.find(where + "'adc_bits' must lie in [1, 24], not 40"), std::string::npos) << range;
  EXPECT_NE(message("\n[sensor]\noversample = 2\nfocal_length_mm = 16\n").find("not both"), std::string::npos);
  RenderCallOptions reflectance = sensor_options("\n[sensor]\n", dir_ / "r.exr");
  reflectance.request.quantity = "reflectance";
  EXPECT_THROW(render_scene(reflectance, quiet), Error);
}

// A split render's chunks carry no sensor (a chunk is part of the samples or tiles); the merge
// applies it with the render's seed, so the sensed image equals a single render's bit for bit.
// A chunk of a scene the sensor cannot take fails before rendering, not at the merge.
TEST_F(SensorStage, ChunksMergeToTheSingleRendersSensedImage) {
  const std::filesystem::path scene = dir_ / "box.toml";
  std::ofstream(scene) << test::kBoxSceneToml;
  RenderCallOptions o;
  o.request.source = SceneSource::from_file(scene.string());
  o.request.threads = 2;
  o.request.overrides = {"sensor.preset=phone_8bit", "sensor.oversample=2"};
  RenderObserver quiet;
  std::vector<std::filesystem::path> parts;
  for (const char* chunk : {"0/2", "1/2"}) {
    RenderCallOptions c = o;
    c.chunk = chunk;
    c.exr = dir_ / (std::string("part") + chunk[0] + ".partial");
    const RenderResult part = render_scene(c, quiet);
    ASSERT_EQ(part.status, RenderStatus::finished);
    EXPECT_TRUE(part.sensor.pixels.empty());
    parts.push_back(c.exr);
  }
  EXPECT_FALSE(std::filesystem::exists(dir_ / "part0.sensor.exr"));
  RenderCallOptions m;
  m.exr = dir_ / "merged.exr";
  m.png = dir_ / "merged.png";
  const MergeResult merged = merge_parts(parts, false, m, quiet);
  RenderCallOptions single = o;
  single.exr = dir_ / "single.exr";
  const RenderResult whole = render_scene(single, quiet);
  ASSERT_FALSE(whole.sensor.pixels.empty());
  EXPECT_EQ(merged.render.image.pixels, whole.image.pixels);
  EXPECT_EQ(merged.render.sensor.pixels, whole.sensor.pixels) << "the merge sensed another image";
  const Image merged_file = read_exr(dir_ / "merged.sensor.exr");
  const Image single_file = read_exr(dir_ / "single.sensor.exr");
  EXPECT_EQ(merged_file.pixels, single_file.pixels);
  EXPECT_EQ(merged_file.channels, single_file.channels);
  for (const char* key : {"sylva:sensor:preset", "sylva:sensor:seed", "sylva:sensor:noise_seed"})
    EXPECT_EQ(merged_file.attribute(key), single_file.attribute(key)) << key;
  EXPECT_EQ(sensor_file_text(dir_ / "merged.sensor.json"), sensor_file_text(dir_ / "single.sensor.json"));
  EXPECT_TRUE(std::filesystem::exists(dir_ / "merged.sensor.png"));

  RenderCallOptions reflectance = o;
  reflectance.chunk = "0/2";
  reflectance.exr = dir_ / "r0.partial";
  reflectance.request.quantity = "reflectance";
  EXPECT_THROW(render_scene(reflectance, quiet), Error);
  EXPECT_FALSE(std::filesystem::exists(reflectance.exr));
}

}  // namespace
}  // namespace sylva
