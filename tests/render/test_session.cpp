// Render sessions: interrupt -> checkpoint -> resume is bit-identical to one render, periodic
// checkpoints change nothing, exceptions inside a round propagate (the watcher thread is joined),
// and SIGINT sets the interrupt flag instead of ending the process.

#include "core/error.h"
#include "render/session.h"
#include "tests/render/render_test_scenes.h"

#include <gtest/gtest.h>

#include <fmt/core.h>

#include <chrono>
#include <csignal>
#include <fstream>
#include <memory>
#include <thread>

namespace sylva {
namespace {

using test::film_bytes;
using test::small_forest_scene;
using test::test_settings;

std::filesystem::path checkpoint_path(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("sylva_session_" + name + "_" + std::to_string(::getpid()));
}

// One scene, Embree scene and uninterrupted reference render for the whole suite.
class Session : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scene_ = std::make_unique<Scene>(small_forest_scene());
    embree_ = std::make_unique<EmbreeScene>(*scene_);
    // Long enough (about a second here) that an interrupt after 50 ms lands mid-render.
    settings_ = test_settings(64, 40, 128, 8);
    settings_.threads = 2;
    Renderer renderer(*scene_, *embree_, settings_);
    reference_ = std::make_unique<Film>(renderer.make_film());
    renderer.render(*reference_);
  }
  static void TearDownTestSuite() {
    reference_.reset();
    embree_.reset();
    scene_.reset();
  }

  static inline std::unique_ptr<Scene> scene_;
  static inline std::unique_ptr<EmbreeScene> embree_;
  static inline RenderSettings settings_;
  static inline std::unique_ptr<Film> reference_;
};

TEST_F(Session, InterruptCheckpointResumeIsBitIdentical) {
  const auto checkpoint = checkpoint_path("resume");
  std::atomic<bool> interrupt{false};
  SessionOptions options;
  options.checkpoint = checkpoint;
  options.key = checkpoint_key("scene-hash", settings_);
  options.checkpoint_minutes = 0;
  options.interrupt = &interrupt;
  SessionResult first;
  {
    RenderSession session(*scene_, *embree_, settings_, options);
    EXPECT_EQ(session.resumed_samples(), 0u);
    std::thread stopper([&] {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      interrupt = true;
    });
    first = session.run();
    stopper.join();
    EXPECT_THROW(session.run(), Error);  // a session runs once
  }
  ASSERT_TRUE(first.interrupted) << "the render finished within 50 ms; make it longer";
  EXPECT_EQ(first.checkpoints, 1);
  EXPECT_LT(first.film.total_samples(), reference_->total_samples());
  ASSERT_TRUE(std::filesystem::exists(checkpoint));
  std::printf("[session] interrupted with %llu of %llu samples\n",
              static_cast<unsigned long long>(first.film.total_samples()),
              static_cast<unsigned long long>(reference_->total_samples()));

  // Another render's key is refused.
  SessionOptions wrong = options;
  wrong.resume = true;
  wrong.key = checkpoint_key("another-scene", settings_);
  EXPECT_THROW(RenderSession(*scene_, *embree_, settings_, wrong), Error);

  SessionOptions resume = options;
  resume.resume = true;
  resume.interrupt = nullptr;
  RenderSession second(*scene_, *embree_, settings_, resume);
  EXPECT_EQ(second.resumed_samples(), first.film.total_samples());
  const SessionResult done = second.run();
  EXPECT_FALSE(done.interrupted);
  EXPECT_EQ(done.stats.samples + first.film.total_samples(), reference_->total_samples());
  EXPECT_EQ(film_bytes(done.film), film_bytes(*reference_));
  second.remove_checkpoint();
  EXPECT_FALSE(std::filesystem::exists(checkpoint));
}

TEST_F(Session, PeriodicCheckpointsLeaveTheImageUnchanged) {
  const auto checkpoint = checkpoint_path("periodic");
  SessionOptions options;
  options.checkpoint = checkpoint;
  options.key = "periodic";
  options.checkpoint_minutes = 0.05 / 60.0;  // every 50 ms (the watcher's polling period)
  RenderSession session(*scene_, *embree_, settings_, options);
  const SessionResult result = session.run();
  EXPECT_FALSE(result.interrupted);
  EXPECT_GE(result.checkpoints, 1) << "the render finished within one checkpoint period; make it longer";
  std::printf("[session] %d periodic checkpoints\n", result.checkpoints);
  EXPECT_EQ(result.stats.samples, reference_->total_samples());
  EXPECT_EQ(film_bytes(result.film), film_bytes(*reference_));
  // The last checkpoint holds a film that resumes to the same bits.
  SessionOptions resume = options;
  resume.resume = true;
  resume.checkpoint_minutes = 0;
  RenderSession again(*scene_, *embree_, settings_, resume);
  EXPECT_LT(again.resumed_samples(), reference_->total_samples());
  EXPECT_EQ(film_bytes(again.run().film), film_bytes(*reference_));
  again.remove_checkpoint();
}

TEST(SessionErrors, ACheckpointOfAnotherSizeIsRefusedBeforeRendering) {
  // A checkpoint under the right key but of another resolution (issue 16: a changed width field
  // ended in std::terminate, thrown inside the round while the watcher thread ran). Refused when
  // the session is made, with both sizes named; StopWatcher's own test covers the join.
  const Scene scene = small_forest_scene();
  const EmbreeScene embree(scene);
  const auto checkpoint = checkpoint_path("throw");
  Renderer(scene, embree, test_settings(8, 8, 4, 4)).make_film().save(checkpoint, "same key");
  SessionOptions options;
  options.checkpoint = checkpoint;
  options.key = "same key";
  options.resume = true;
  options.checkpoint_minutes = 1.0;
  try {
    RenderSession session(scene, embree, test_settings(9, 8, 4, 4), options);
    FAIL() << "a checkpoint of another size was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("(8x8, "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("is not this render's (9x8, "), std::string::npos) << e.what();
  }
  std::filesystem::remove(checkpoint);
}

TEST_F(Session, ResumingWithFewerSamplesThanTheCheckpointHoldsIsRefused) {
  // An image of fewer samples cannot be made from a film that holds more (issue 16: it was accepted
  // and gave an image that was not the lower-spp render).
  const auto checkpoint = checkpoint_path("fewer");
  reference_->save(checkpoint, "fewer");
  SessionOptions options;
  options.checkpoint = checkpoint;
  options.key = "fewer";
  options.resume = true;
  RenderSettings fewer = settings_;
  fewer.spp = settings_.spp / 2;
  try {
    RenderSession session(*scene_, *embree_, fewer, options);
    FAIL() << "resumed with a lower spp";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(
                  fmt::format("holds up to {} samples per pixel, more than --spp {}", settings_.spp, fewer.spp)),
              std::string::npos)
        << e.what();
  }
  // The same spp, or more, resumes.
  EXPECT_NO_THROW(RenderSession(*scene_, *embree_, settings_, options));
  std::filesystem::remove(checkpoint);
}

TEST_F(Session, CorruptCheckpointsAreRefused) {
  // Issue 16: sums overwritten or counts set to 0xFFFFFFFF resumed into a wrong image.
  const auto checkpoint = checkpoint_path("corrupt");
  const std::string bytes = film_bytes(*reference_);
  const auto refused = [&](const std::string& corrupted) {
    std::ofstream(checkpoint, std::ios::binary | std::ios::trunc) << corrupted;
    try {
      Film::load(checkpoint, "bytes");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(refused(bytes), "accepted");
  // A count (right after the header) set to 0xFFFFFFFF, a sum overwritten, the checksum changed.
  const size_t header = 8 + 8 + 5 + 7 * 4 + 4;
  std::string count = bytes;
  count.replace(header, 4, "\xff\xff\xff\xff");
  EXPECT_NE(refused(count).find("corrupt checkpoint"), std::string::npos) << refused(count);
  std::string sum = bytes;
  sum[sum.size() / 2] = static_cast<char>(sum[sum.size() / 2] ^ 0x40);
  EXPECT_NE(refused(sum).find("checksum mismatch"), std::string::npos) << refused(sum);
  std::string tail = bytes;
  tail.back() = static_cast<char>(tail.back() ^ 1);
  EXPECT_NE(refused(tail).find("checksum mismatch"), std::string::npos);
  EXPECT_NE(refused(bytes.substr(0, bytes.size() - 9)).find("truncated"), std::string::npos);
  EXPECT_NE(refused(bytes + "x").find("data after the checksum"), std::string::npos);
  std::filesystem::remove(checkpoint);
}

TEST_F(Session, AFailingPeriodicCheckpointWarnsAndRenderingGoesOn) {
  // Issue 16: a periodic checkpoint that could not be written (full disk) aborted the render.
  SessionOptions options;
  options.checkpoint = checkpoint_path("nowhere") / "missing-dir" / "c.checkpoint";
  options.key = "warn";
  options.checkpoint_minutes = 0.05 / 60.0;
  std::vector<std::string> warnings;
  options.warn = [&](const std::string& w) { warnings.push_back(w); };
  RenderSession session(*scene_, *embree_, settings_, options);
  const SessionResult result = session.run();
  EXPECT_FALSE(result.interrupted);
  EXPECT_EQ(result.checkpoints, 0);
  ASSERT_FALSE(warnings.empty()) << "the render finished within one checkpoint period; make it longer";
  EXPECT_NE(warnings[0].find("warning: checkpoint not written"), std::string::npos) << warnings[0];
  EXPECT_EQ(film_bytes(result.film), film_bytes(*reference_));
  // The final checkpoint of an interrupted render is the only copy: its failure is an error.
  std::atomic<bool> interrupt{true};
  options.interrupt = &interrupt;
  RenderSession interrupted(*scene_, *embree_, settings_, options);
  EXPECT_THROW(interrupted.run(), Error);
}

TEST(CheckpointPath, BesideTheOutputAndShortEnoughForAnyName) {
  EXPECT_EQ(checkpoint_path_for("/a/out.exr"), std::filesystem::path("/a/out.exr.checkpoint"));
  const std::string long_a(250, 'a'), long_b = std::string(249, 'a') + "b";
  const auto a = checkpoint_path_for("/d/" + long_a), b = checkpoint_path_for("/d/" + long_b);
  EXPECT_EQ(a.filename().string().size(), 255u);
  EXPECT_EQ(a.parent_path(), std::filesystem::path("/d"));
  EXPECT_EQ(a.extension(), ".checkpoint");
  EXPECT_NE(a, b) << "names that differ only past the cut get different checkpoints";
  EXPECT_EQ(a, checkpoint_path_for("/d/" + long_a));
}

TEST(StopWatcher, StopsOnInterruptOrPeriodAndJoinsOnExceptions) {
  std::atomic<bool> stop{false}, interrupt{false};
  EXPECT_THROW(
      {
        const StopWatcher watcher(stop, &interrupt, 0.0);
        throw Error("thrown while watching");
      },
      Error);
  EXPECT_FALSE(stop);
  {
    const StopWatcher watcher(stop, &interrupt, 0.0);
    interrupt = true;
    for (int i = 0; i < 200 && !stop; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    EXPECT_TRUE(stop);
  }
  stop = false;
  {
    const auto start = std::chrono::steady_clock::now();
    const StopWatcher watcher(stop, nullptr, 0.1 / 60.0);
    while (!stop && std::chrono::steady_clock::now() - start < std::chrono::seconds(5))
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    EXPECT_TRUE(stop);
    EXPECT_GE(std::chrono::steady_clock::now() - start, std::chrono::milliseconds(100));
  }
  // Without interrupt or period the watcher never stops the render, and leaves promptly.
  stop = false;
  const auto start = std::chrono::steady_clock::now();
  { const StopWatcher watcher(stop, nullptr, 0.0); }
  EXPECT_FALSE(stop);
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::milliseconds(40));
}

TEST(InterruptHandlers, SigintSetsTheFlagInsteadOfEndingTheProcess) {
  {
    const InterruptHandlers handlers;
    EXPECT_FALSE(InterruptHandlers::flag());
    std::raise(SIGINT);
    EXPECT_TRUE(InterruptHandlers::flag());
  }
  const InterruptHandlers again;
  EXPECT_FALSE(InterruptHandlers::flag()) << "a new installation clears the flag";
}

TEST(CheckpointKey, NamesEverythingThatChangesTheSamples) {
  const RenderSettings base = test_settings(64, 40, 16, 8);
  const std::string key = checkpoint_key("abc", base);
  EXPECT_NE(key.find("abc"), std::string::npos);
  EXPECT_NE(key.find("rgb nir"), std::string::npos);
  RenderSettings s = base;
  s.seed = 2;
  EXPECT_NE(checkpoint_key("abc", s), key);
  s = base;
  s.width = 65;
  EXPECT_NE(checkpoint_key("abc", s), key);
  s = base;
  s.integrator.max_depth = 9;
  EXPECT_NE(checkpoint_key("abc", s), key);
  s = base;
  s.bands = {resolve_band("nir")};
  EXPECT_NE(checkpoint_key("abc", s), key);
  EXPECT_NE(checkpoint_key("abd", base), key);
  // The sample count is not part of it: a finished render can be resumed to more samples.
  s = base;
  s.spp = 64;
  EXPECT_EQ(checkpoint_key("abc", s), key);
}

}  // namespace
}  // namespace sylva
