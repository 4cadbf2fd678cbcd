// Issue 16: the §4.6 pruning probe forms a stem's clones too; without the stem budget that guards
// normal generation, a willow whose clones split again (1SegSplits = 5, or SegSplits = 10000, both
// in range) with PruneRatio = 1 never finished. Now it fails as fast as the unpruned tree does.

#include "core/error.h"
#include "geometry/trees/weber_penn/weber_penn.h"
#include "tests/geometry/trees/wp_test_species.h"

#include <gtest/gtest.h>

#include <chrono>
#include <string>

namespace sylva {
namespace {

// The error generation ends with, "" if the tree was made; and how long that took.
std::string generate(const WeberPennParams& p, double& seconds) {
  const auto start = std::chrono::steady_clock::now();
  std::string message;
  try {
    make_weber_penn_tree(p, 1);
  } catch (const Error& e) {
    message = e.what();
  }
  seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return message;
}

TEST(WeberPennPruning, SplittingClonesStopAtTheStemBudget) {
  for (const auto& [level, splits] : {std::pair{1, 5.0f}, std::pair{0, 10000.0f}, std::pair{2, 10000.0f}}) {
    WeberPennParams p = test::weeping_willow();
    ASSERT_EQ(p.prune_ratio, 1.0f);
    p.level[static_cast<size_t>(level)].seg_splits = splits;
    double seconds = 0;
    const std::string message = generate(p, seconds);
    EXPECT_NE(message.find("tree too large"), std::string::npos)
        << level << "SegSplits = " << splits << ": " << message;
    EXPECT_LT(seconds, 60.0) << level << "SegSplits = " << splits;
    std::printf("[pruning budget] %dSegSplits = %g: %.2f s\n", level, static_cast<double>(splits), seconds);
  }
}

TEST(WeberPennPruning, TheBudgetLeavesTheShippedWillowAlone) {
  // The guard only ends probes the real pass could not finish: the appendix willow, pruned, is made.
  double seconds = 0;
  EXPECT_EQ(generate(test::weeping_willow(), seconds), "");
}

}  // namespace
}  // namespace sylva
