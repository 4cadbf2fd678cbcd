// Progress (core/progress.h): the lines printed when stderr is not a terminal, at their cadence
// and with the right ETA, on a clock the test drives; nothing when disabled.

#include "core/progress.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace sylva {
namespace {

// A Progress on a fake clock that writes into `lines`.
struct FakeOutput {
  double t = 0;
  std::vector<std::string> lines;
  ProgressOutput output(ProgressStyle style) {
    ProgressOutput out;
    out.style = style;
    out.clock_s = [this] { return t; };
    out.write = [this](std::string_view text) { lines.emplace_back(text); };
    return out;
  }
};

// Adds `per_step` every 0.25 s until `until_s`.
void run(Progress& p, FakeOutput& fake, uint64_t per_step, double until_s) {
  while (fake.t < until_s) {
    fake.t += 0.25;
    p.add(per_step);
  }
}

TEST(Progress, LinesEveryTenPercentAndTenSecondsWithTheEta) {
  FakeOutput fake;
  Progress p("render", 10000, fake.output(ProgressStyle::lines));
  run(p, fake, 25, 100.0);  // 100 samples/s: 100 s in all
  p.finish();
  ASSERT_EQ(fake.lines.size(), 10u);
  EXPECT_EQ(fake.lines[0], "render: 10.0% 1000/10000 samples, 00:10 elapsed, 100 samples/s, 01:30 left\n");
  EXPECT_EQ(fake.lines[2], "render: 30.0% 3000/10000 samples, 00:30 elapsed, 100 samples/s, 01:10 left\n");
  EXPECT_EQ(fake.lines[8], "render: 90.0% 9000/10000 samples, 01:30 elapsed, 100 samples/s, 00:10 left\n");
  EXPECT_EQ(fake.lines[9], "render: 100.0% 10000/10000 samples, 01:40 elapsed, 100 samples/s, done\n");
}

TEST(Progress, FastWorkIsLoggedEveryTenSecondsNotEveryTenPercent) {
  FakeOutput fake;
  Progress p("render", 10000, fake.output(ProgressStyle::lines));
  run(p, fake, 100, 25.0);  // 40 % every 10 s
  p.finish();
  ASSERT_EQ(fake.lines.size(), 3u);
  EXPECT_EQ(fake.lines[0], "render: 40.0% 4000/10000 samples, 00:10 elapsed, 400 samples/s, 00:15 left\n");
  EXPECT_EQ(fake.lines[1], "render: 80.0% 8000/10000 samples, 00:20 elapsed, 400 samples/s, 00:05 left\n");
  EXPECT_EQ(fake.lines[2], "render: 100.0% 10000/10000 samples, 00:25 elapsed, 400 samples/s, done\n");
}

TEST(Progress, SlowWorkIsLoggedAtLeastEveryFiveMinutes) {
  FakeOutput fake;
  Progress p("render", 1000000, fake.output(ProgressStyle::lines));
  run(p, fake, 25, 700.0);  // 100 samples/s: 10 % takes 1000 s
  ASSERT_EQ(fake.lines.size(), 3u);
  EXPECT_EQ(fake.lines[0], "render: 0.1% 1000/1000000 samples, 00:10 elapsed, 100 samples/s, 2:46:30 left\n");
  EXPECT_EQ(fake.lines[1], "render: 3.1% 31000/1000000 samples, 05:10 elapsed, 100 samples/s, 2:41:30 left\n");
  EXPECT_EQ(fake.lines[2], "render: 6.1% 61000/1000000 samples, 10:10 elapsed, 100 samples/s, 2:36:30 left\n");
  // Stopped before the end (an interrupt): the last line says what was done and what is left.
  p.finish();
  ASSERT_EQ(fake.lines.size(), 4u);
  EXPECT_EQ(fake.lines[3], "render: 7.0% 70000/1000000 samples, 11:40 elapsed, 100 samples/s, 2:35:00 left\n");
}

TEST(Progress, ShortWorkPrintsNoLine) {
  FakeOutput fake;
  Progress p("render", 1000, fake.output(ProgressStyle::lines));
  run(p, fake, 25, 9.75);
  p.finish();
  EXPECT_TRUE(fake.lines.empty());
}

TEST(Progress, DisabledPrintsNothingButTheSinkHearsOfIt) {
  FakeOutput fake;
  std::vector<ProgressReport> reports;
  {
    Progress p("render", 10000, fake.output(ProgressStyle::none), "samples",
               [&](const ProgressReport& r) { reports.push_back(r); });
    run(p, fake, 25, 100.0);
  }  // finished by the destructor
  EXPECT_TRUE(fake.lines.empty());
  ASSERT_FALSE(reports.empty());
  EXPECT_EQ(reports.back().done, 10000u);
  EXPECT_DOUBLE_EQ(reports.back().elapsed_s, 100.0);
  EXPECT_DOUBLE_EQ(reports[reports.size() / 2].remaining_s,
                   (10000.0 - static_cast<double>(reports[reports.size() / 2].done)) / 100.0);
}

TEST(Progress, TheBarIsRedrawnInPlace) {
  FakeOutput fake;
  Progress p("grow", 4, fake.output(ProgressStyle::bar), "years");
  run(p, fake, 1, 1.0);
  p.finish();
  ASSERT_FALSE(fake.lines.empty());
  for (const std::string& s : fake.lines) EXPECT_EQ(s.front(), '\r') << s;
  EXPECT_EQ(fake.lines.back().back(), '\n');
  EXPECT_NE(fake.lines.back().find("100.0%"), std::string::npos) << fake.lines.back();
}

TEST(Progress, StderrStyleFollowsTheTerminal) {
  EXPECT_EQ(stderr_progress(false).style, ProgressStyle::none);
  EXPECT_EQ(stderr_progress(true).style, Progress::terminal_stderr() ? ProgressStyle::bar : ProgressStyle::lines);
}

TEST(Progress, CadenceRule) {
  const ProgressCadence c;
  EXPECT_FALSE(progress_line_due(c, true, 9.9, 0.5));
  EXPECT_TRUE(progress_line_due(c, true, 10.0, 0.0));
  EXPECT_FALSE(progress_line_due(c, false, 9.9, 0.5));
  EXPECT_FALSE(progress_line_due(c, false, 60.0, 0.09));
  EXPECT_TRUE(progress_line_due(c, false, 10.0, 0.1));
  EXPECT_TRUE(progress_line_due(c, false, 300.0, 0.0));
}

}  // namespace
}  // namespace sylva
