// The render call (pipeline/render_call.h): a scene in, its outputs out, with progress,
// cancellation, resumption, chunks and their merge all through one function.

#include "core/error.h"
#include "core/image.h"
#include "pipeline/render_call.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace sylva {
namespace {

const std::string kScene = R"([render]
width = 24
height = 16
spp = 4
bands = ["rgb", "nir"]
max_depth = 4

[camera]
position = [0.0, -6.0, 4.0]
target = [0.0, 0.0, 0.0]

[sun]
azimuth = 210
elevation = 35

[materials.grey]
reflectance = 0.4

[[meshes]]
shape = "plane"
size = [40, 40]
material = "grey"

[[meshes]]
shape = "box"
size = [1.0, 1.0, 1.2]
material = "grey"
)";

// Records what the call tells it; cancels once rendering starts when asked to.
class RecordingObserver : public RenderObserver {
 public:
  explicit RecordingObserver(bool cancel_on_render = false) : cancel_on_render_(cancel_on_render) {}
  void on_phase(RenderPhase phase) override {
    phases.push_back(phase);
    if (phase == RenderPhase::rendering && cancel_on_render_) cancel();
  }
  void on_message(const std::string& text) override { messages.push_back(text); }
  void on_progress(const ProgressReport& report) override { reports.push_back(report); }

  std::vector<RenderPhase> phases;
  std::vector<std::string> messages;
  std::vector<ProgressReport> reports;

 private:
  bool cancel_on_render_;
};

RenderCallOptions text_options(const std::vector<std::string>& overrides = {}) {
  RenderCallOptions o;
  o.request.source = SceneSource::from_text(kScene, "test scene");
  o.request.overrides = overrides;
  o.request.threads = 2;
  return o;
}

void expect_same_pixels(const Image& a, const Image& b) {
  ASSERT_EQ(a.width, b.width);
  ASSERT_EQ(a.height, b.height);
  ASSERT_EQ(a.channels, b.channels);
  size_t differ = 0;
  for (size_t i = 0; i < a.pixels.size(); ++i) differ += a.pixels[i] != b.pixels[i];
  EXPECT_EQ(differ, 0u) << "of " << a.pixels.size() << " values";
}

class RenderCall : public test::TempDirTest {
 protected:
  std::filesystem::path scene_file() {
    const std::filesystem::path p = dir_ / "scene.toml";
    std::ofstream(p) << kScene;
    return p;
  }
};

TEST_F(RenderCall, TextSceneRendersInMemoryWithProgressAndPhases) {
  RecordingObserver observer;
  const RenderResult r = render_scene(text_options({"render.width=20"}), observer);
  EXPECT_EQ(r.status, RenderStatus::finished);
  EXPECT_EQ(r.image.width, 20);  // the override reached the scene
  EXPECT_EQ(r.image.height, 16);
  EXPECT_GE(r.image.find_channel("R"), 0);
  EXPECT_GE(r.image.find_channel("nir.Y"), 0);
  EXPECT_EQ(r.image.attribute("sylva:spp"), "4");
  EXPECT_EQ(r.stats.samples, 20u * 16u * 4u);
  EXPECT_TRUE(r.outputs.exr.empty());
  EXPECT_TRUE(std::filesystem::is_empty(dir_));
  const std::vector<RenderPhase> expected{RenderPhase::loading, RenderPhase::rendering, RenderPhase::writing};
  EXPECT_EQ(observer.phases, expected);
  ASSERT_FALSE(observer.reports.empty());
  EXPECT_EQ(observer.reports.back().done, observer.reports.back().total);
  EXPECT_EQ(observer.reports.back().total, 20u * 16u * 4u);
}

TEST_F(RenderCall, WritesEveryOutputAndReturnsTheSameImage) {
  RecordingObserver observer;
  RenderCallOptions o = text_options();
  o.exr = dir_ / "out.exr";
  o.png = dir_ / "out.png";
  const RenderResult r = render_scene(o, observer);
  ASSERT_EQ(r.status, RenderStatus::finished);
  EXPECT_TRUE(std::filesystem::exists(dir_ / "out.png"));
  EXPECT_TRUE(std::filesystem::exists(r.outputs.sidecar));
  EXPECT_FALSE(std::filesystem::exists(r.outputs.checkpoint));  // removed once the outputs are written
  const Image written = read_exr(dir_ / "out.exr");
  ASSERT_EQ(written.channel_count(), r.image.channel_count());
  ASSERT_EQ(written.width, r.image.width);
  ASSERT_EQ(written.height, r.image.height);
  for (int c = 0; c < r.image.channel_count(); ++c) {  // the EXR orders its channels by name
    const int w = written.find_channel(r.image.channels[static_cast<size_t>(c)]);
    ASSERT_GE(w, 0) << r.image.channels[static_cast<size_t>(c)];
    const bool half = r.image.types[static_cast<size_t>(c)] == PixelType::Half;
    for (int y = 0; y < r.image.height; ++y)
      for (int x = 0; x < r.image.width; ++x) {
        const float v = r.image.at(x, y, c);
        ASSERT_NEAR(written.at(x, y, w), v, half ? 1e-3f * std::abs(v) : 0.0f)
            << r.image.channels[static_cast<size_t>(c)];
      }
  }
  EXPECT_EQ(written.attribute("sylva:scene_hash"), r.image.attribute("sylva:scene_hash"));
}

TEST_F(RenderCall, CancelledThenResumedEqualsUninterrupted) {
  RenderCallOptions o = text_options();
  o.exr = dir_ / "out.exr";
  RecordingObserver cancelling(true);
  const RenderResult cut = render_scene(o, cancelling);
  ASSERT_EQ(cut.status, RenderStatus::interrupted);
  EXPECT_TRUE(std::filesystem::exists(cut.outputs.checkpoint));
  EXPECT_FALSE(std::filesystem::exists(o.exr));  // nothing but the checkpoint
  o.resume = true;
  RecordingObserver resuming;
  const RenderResult resumed = render_scene(o, resuming);
  ASSERT_EQ(resumed.status, RenderStatus::finished);
  EXPECT_EQ(resumed.resumed_samples, cut.film_samples);
  EXPECT_FALSE(std::filesystem::exists(cut.outputs.checkpoint));
  RecordingObserver plain;
  const RenderResult whole = render_scene(text_options(), plain);
  expect_same_pixels(resumed.image, whole.image);
}

TEST_F(RenderCall, ChunksMergeToTheSingleRender) {
  RenderCallOptions o = text_options({"sun.elevation=50"});
  o.request.source = SceneSource::from_file(scene_file().string());
  std::vector<std::filesystem::path> parts;
  for (const char* chunk : {"0/3", "1/3", "2/3"}) {
    RenderCallOptions c = o;
    c.chunk = chunk;
    c.exr = dir_ / (std::string("part") + chunk[0] + ".partial");
    RecordingObserver observer;
    ASSERT_EQ(render_scene(c, observer).status, RenderStatus::finished);
    parts.push_back(c.exr);
  }
  RenderCallOptions m;
  m.exr = dir_ / "merged.exr";
  RecordingObserver observer;
  const MergeResult merged = merge_parts(parts, false, m, observer);
  EXPECT_TRUE(merged.missing.empty());
  RecordingObserver single;
  const RenderResult whole = render_scene(o, single);
  expect_same_pixels(merged.render.image, whole.image);
  // The overrides travel in the parts' header: without them the scene would be another one.
  EXPECT_EQ(merged.render.image.attribute("sylva:scene_hash"), whole.image.attribute("sylva:scene_hash"));
}

TEST_F(RenderCall, BadRequestsFailBeforeAnyWork) {
  RecordingObserver observer;
  RenderCallOptions o = text_options();
  o.png = dir_ / "only.png";
  EXPECT_THROW(render_scene(o, observer), Error);  // a preview without its EXR
  RenderCallOptions chunk = text_options();
  chunk.chunk = "0/2";
  chunk.exr = dir_ / "part.partial";
  EXPECT_THROW(render_scene(chunk, observer), Error);  // a chunk of text cannot be merged again
  RenderCallOptions same = text_options();
  same.request.source = SceneSource::from_file(scene_file().string());
  same.exr = dir_ / "scene.toml";
  EXPECT_THROW(render_scene(same, observer), Error);  // an output never replaces an input
  RenderCallOptions bad = text_options({"sun.elevaton=3"});
  try {
    render_scene(bad, observer);
    ADD_FAILURE() << "a misspelt override was accepted";
  } catch (const ParseError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("--set sun.elevaton=3: unknown key 'elevaton'", 0), 0u) << e.what();
  }
  EXPECT_EQ(std::vector<std::filesystem::path>(std::filesystem::directory_iterator(dir_), {}),
            std::vector<std::filesystem::path>{dir_ / "scene.toml"});
  EXPECT_TRUE(observer.reports.empty());  // nothing was rendered
}

}  // namespace
}  // namespace sylva
