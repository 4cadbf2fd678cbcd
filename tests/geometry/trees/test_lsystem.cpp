// L-systems: parallel rewriting against closed-form symbol counts (the thesis's two examples,
// seed 002 Ch. 4), stochastic productions against their probabilities (χ²), parametric
// productions, the length budget, and the turtle's geometry on hand-checked words.

#include "core/error.h"
#include "geometry/trees/lsystem/lsystem.h"
#include "geometry/trees/tree_mesher.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace sylva {
namespace {

LsProduction plain(char pred, std::string_view successor, float probability = 1) {
  LsProduction p;
  p.predecessor = pred;
  for (const char c : successor) p.successor.push_back(LsModuleTemplate{c, {}});
  p.probability = probability;
  return p;
}

size_t count(const LsWord& w, char c) { return static_cast<size_t>(std::count(w.symbols.begin(), w.symbols.end(), c)); }

size_t segments(const TreeModel& m) {
  size_t n = 0;
  for (size_t s = 0; s < m.stems.size(); ++s) n += m.stems.section_count[s] - 1;
  return n;
}

// Thesis Figure 3 (ABOP Fig. 1.24a): ω = F, F → F[+F]F[−F]F, δ = 25.7°, 5 iterations.
TEST(LSystem, ThesisExampleOneMatchesClosedFormCounts) {
  LSystem ls;
  ls.axiom = make_ls_word("F");
  ls.productions = {plain('F', "F[+F]F[-F]F")};
  ls.turtle.angle_deg = 25.7f;
  ls.iterations = 5;
  // Each F becomes 5 F, 2 '[', 2 ']', one '+' and one '-'; other symbols are copied.
  uint64_t f = 1, open = 0, turns = 0;
  for (int i = 0; i < ls.iterations; ++i) {
    open += 2 * f;
    turns += 2 * f;
    f *= 5;
  }
  const LsWord w = expand_lsystem(ls, 1);
  EXPECT_EQ(f, 3125u);
  EXPECT_EQ(w.size(), f + 2 * open + turns);
  EXPECT_EQ(count(w, 'F'), f);
  EXPECT_EQ(count(w, '['), open);
  EXPECT_EQ(count(w, '+'), turns / 2);
  EXPECT_EQ(ls_word_string(expand_lsystem(LSystem{ls.axiom, ls.productions, 1, 0, ls.turtle}, 1)), "F[+F]F[-F]F");

  const TreeModel m = make_lsystem_tree(ls, 1);
  EXPECT_EQ(segments(m), f);            // one segment per F
  EXPECT_EQ(m.stems.size(), 1 + open);  // the main axis and one stem per bracket
  EXPECT_EQ(m.leaves.size(), 0u);
  // The main axis holds the F's outside every bracket: 3 per rewrite, 3^5.
  EXPECT_EQ(m.stems.section_count[0], 1u + 243u);
}

// Thesis Figure 4 (ABOP Fig. 1.24f with Y, X): ω = Y, Y → YFX[+Y][−Y], X → X[−FFF][+FFF]FX.
TEST(LSystem, ThesisExampleTwoMatchesClosedFormCounts) {
  LSystem ls;
  ls.axiom = make_ls_word("Y");
  ls.productions = {plain('Y', "YFX[+Y][-Y]"), plain('X', "X[-FFF][+FFF]FX")};
  ls.turtle.angle_deg = 25.7f;
  ls.iterations = 6;
  uint64_t y = 1, x = 0, f = 0, brackets = 0, signs = 0;
  for (int i = 0; i < ls.iterations; ++i) {
    const uint64_t y2 = 3 * y, x2 = y + 2 * x, f2 = f + y + 7 * x;
    brackets += 4 * y + 4 * x;
    signs += 2 * y + 2 * x;
    y = y2, x = x2, f = f2;
  }
  const LsWord w = expand_lsystem(ls, 1);
  EXPECT_EQ(w.size(), y + x + f + brackets + signs);
  EXPECT_EQ(count(w, 'Y'), y);
  EXPECT_EQ(count(w, 'X'), x);
  EXPECT_EQ(count(w, 'F'), f);
  EXPECT_EQ(y, 729u);
  EXPECT_EQ(segments(make_lsystem_tree(ls, 1)), f);
}

TEST(LSystem, StochasticProductionsHitTheirProbabilities) {
  LSystem ls;
  const int n = 30000;
  ls.axiom = make_ls_word(std::string(n, 'X'));
  const float p[3] = {0.2f, 0.3f, 0.5f};
  ls.productions = {plain('X', "A", p[0]), plain('X', "B", p[1]), plain('X', "C", p[2])};
  ls.iterations = 1;
  for (const uint64_t seed : {1u, 2u, 3u}) {
    const LsWord w = expand_lsystem(ls, seed);
    ASSERT_EQ(w.size(), static_cast<size_t>(n));
    double chi2 = 0;
    for (int k = 0; k < 3; ++k) {
      const double expected = n * p[k];
      chi2 += std::pow(static_cast<double>(count(w, static_cast<char>('A' + k))) - expected, 2) / expected;
    }
    EXPECT_LT(chi2, 13.8) << "seed " << seed;  // χ²(2 dof) at p = 0.001
  }
  // Unequal weights are renormalised over the productions that apply.
  ls.productions = {plain('X', "A", 0.1f), plain('X', "B", 0.3f)};
  const LsWord w = expand_lsystem(ls, 9);
  const double z = (static_cast<double>(count(w, 'A')) - n * 0.25) / std::sqrt(n * 0.25 * 0.75);
  EXPECT_LT(std::abs(z), 3.3);
}

TEST(LSystem, StochasticChoicesAreDeterministicPerSeed) {
  LSystem ls;
  ls.axiom = make_ls_word("F");
  ls.productions = {plain('F', "F[+F]F[-F]F", 0.33f), plain('F', "F[+F]F", 0.33f), plain('F', "F[-F]F", 0.34f)};
  ls.iterations = 5;
  EXPECT_EQ(ls_word_string(expand_lsystem(ls, 4)), ls_word_string(expand_lsystem(ls, 4)));
  EXPECT_NE(ls_word_string(expand_lsystem(ls, 4)), ls_word_string(expand_lsystem(ls, 5)));
  LSystem other = ls;
  other.seed = 1;  // the file's seed selects another family
  EXPECT_NE(ls_word_string(expand_lsystem(other, 4)), ls_word_string(expand_lsystem(ls, 4)));
}

TEST(LSystem, ParametricProductionsWithConditions) {
  // A(x) : x > 0.3 -> F(x) A(x * 0.5)
  LsProduction p;
  p.predecessor = 'A';
  p.param_count = 1;
  p.condition.code = {{LsOp::Param, 0, 0}, {LsOp::Const, 0, 0.3f}, {LsOp::Gt, 0, 0}};
  p.successor = {LsModuleTemplate{'F', {LsExpr::parameter(0)}},
                 LsModuleTemplate{'A', {LsExpr{{{LsOp::Param, 0, 0}, {LsOp::Const, 0, 0.5f}, {LsOp::Mul, 0, 0}}}}}};
  LSystem ls;
  ls.axiom.push('A', std::vector<float>{1.0f});
  ls.productions = {p};
  ls.iterations = 5;
  EXPECT_EQ(ls_word_string(expand_lsystem(ls, 0)), "F(1)F(0.5)A(0.25)");
  const TreeModel m = make_lsystem_tree(ls, 0);
  ASSERT_EQ(m.stems.size(), 1u);
  EXPECT_FLOAT_EQ(m.stems.length_m[0], 1.5f);
}

TEST(LSystem, RunawayGrowthIsAClearError) {
  LSystem ls;
  ls.axiom = make_ls_word("F");
  ls.productions = {plain('F', "FF")};
  ls.iterations = 40;
  try {
    expand_lsystem(ls, 0, 100000);
    FAIL() << "2^40 modules were generated";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("L-system too long: iteration 17"), std::string::npos) << e.what();
  }
  LsProduction div;
  div.predecessor = 'A';
  div.param_count = 1;
  div.successor = {LsModuleTemplate{'A', {LsExpr{{{LsOp::Param, 0, 0}, {LsOp::Const, 0, 0}, {LsOp::Div, 0, 0}}}}}};
  LSystem nan;
  nan.axiom.push('A', std::vector<float>{1.0f});
  nan.productions = {div};
  nan.iterations = 1;
  EXPECT_THROW(expand_lsystem(nan, 0), Error);
}

void expect_vec(const Vec3& a, const Vec3& b) {
  EXPECT_NEAR(a.x, b.x, 1e-6f);
  EXPECT_NEAR(a.y, b.y, 1e-6f);
  EXPECT_NEAR(a.z, b.z, 1e-6f);
}

Vec3 tip(const TreeModel& m, size_t stem) {
  return m.sections.positions[m.stems.first_section[stem] + m.stems.section_count[stem] - 1];
}

TEST(LSystemTurtle, TurnsPitchesAndRollsAsInAbop) {
  LsTurtle t;
  t.angle_deg = 90;
  // Heading +Z, left −X, up −Y.
  expect_vec(tip(interpret_lsystem(make_ls_word("F+F"), t), 0), {-1, 0, 1});
  expect_vec(tip(interpret_lsystem(make_ls_word("F-F"), t), 0), {1, 0, 1});
  expect_vec(tip(interpret_lsystem(make_ls_word("F&F"), t), 0), {0, 1, 1});
  expect_vec(tip(interpret_lsystem(make_ls_word("F^F"), t), 0), {0, -1, 1});
  expect_vec(tip(interpret_lsystem(make_ls_word("F/+F"), t), 0), {0, 1, 1});
  expect_vec(tip(interpret_lsystem(make_ls_word("F\\+F"), t), 0), {0, -1, 1});
  expect_vec(tip(interpret_lsystem(make_ls_word("F|F"), t), 0), {0, 0, 0});
  // Parameters override δ and the step.
  LsWord w;
  w.push('+', std::vector<float>{30.0f});
  w.push('F', std::vector<float>{2.0f});
  expect_vec(tip(interpret_lsystem(w, t), 0), {-1.0f, 0, std::sqrt(3.0f)});
  // $ makes the left vector horizontal.
  const TreeModel rolled = interpret_lsystem(make_ls_word("&/$F"), LsTurtle{.angle_deg = 35});
  EXPECT_NEAR(rolled.sections.frames[1].x.z, 0.0f, 1e-6f);
}

TEST(LSystemTurtle, BracketsMakeChildStemsAndWidthsAndUnitsScale) {
  LsTurtle t;
  t.angle_deg = 90;
  t.unit_m = 2;
  t.width = 0.5f;
  t.width_factor = 0.5f;
  const TreeModel m = interpret_lsystem(make_ls_word("F[+F]!F"), t);
  ASSERT_EQ(m.stems.size(), 2u);
  EXPECT_EQ(m.stems.section_count[0], 3u);
  EXPECT_EQ(m.stems.parent[1], 0);
  EXPECT_EQ(m.stems.level[1], 1);
  EXPECT_FLOAT_EQ(m.stems.offset_m[1], 2.0f);
  expect_vec(tip(m, 0), {0, 0, 4});
  expect_vec(tip(m, 1), {-2, 0, 2});
  EXPECT_FLOAT_EQ(m.sections.radius_m[0], 0.5f);  // diameter 0.5 units × 2 m / 2
  EXPECT_FLOAT_EQ(m.sections.radius_m[2], 0.25f);
  EXPECT_FLOAT_EQ(m.stems.length_m[0], 4.0f);
  EXPECT_FLOAT_EQ(m.sections.arc_m[2], 4.0f);
  // f breaks a stem; the next F starts another one.
  EXPECT_EQ(interpret_lsystem(make_ls_word("FfF"), t).stems.size(), 2u);
  // The mesher accepts the result: one closed tube per stem.
  const TreeMesh mesh = make_tree_mesh(m);
  EXPECT_GT(mesh.stems.triangles.size(), 0u);
}

TEST(LSystemTurtle, LeavesAndPolygons) {
  LsTurtle t;
  t.angle_deg = 90;
  t.leaf_length = 0.3f;
  t.leaf_width = 0.1f;
  const TreeModel m = interpret_lsystem(make_ls_word("F~"), t);
  ASSERT_EQ(m.leaves.size(), 1u);
  expect_vec(m.leaves.positions[0], {0, 0, 1});
  expect_vec(m.leaves.frames[0].z, {0, 0, 1});
  expect_vec(m.leaves.frames[0].y, {0, -1, 0});
  EXPECT_FLOAT_EQ(m.leaves.length_m[0], 0.3f);
  EXPECT_EQ(m.leaves.stem[0], 0);
  // A unit square in the XZ plane, from its first corner to the opposite one.
  const TreeModel sq = interpret_lsystem(make_ls_word("{f+f+f}"), t);
  ASSERT_EQ(sq.leaves.size(), 1u);
  EXPECT_NEAR(sq.leaves.length_m[0], std::sqrt(2.0f), 1e-6f);
  EXPECT_NEAR(sq.leaves.width_m[0], std::sqrt(2.0f), 1e-6f);
  EXPECT_NEAR(std::abs(sq.leaves.frames[0].y.y), 1.0f, 1e-6f);
  expect_vec(sq.leaves.positions[0], {0, 0, 0});
  EXPECT_EQ(sq.stems.size(), 0u);  // moves inside a polygon draw nothing
}

TEST(LSystemTurtle, TropismBendsTheHeading) {
  LsTurtle t;
  t.tropism = {1, 0, 0};
  t.tropism_e = 0.5f;
  const TreeModel m = interpret_lsystem(make_ls_word("FF"), t);
  expect_vec(tip(m, 0), {std::sin(0.5f), 0, 1 + std::cos(0.5f)});
}

TEST(LSystemTurtle, UnbalancedWordsAreErrorsNotCrashes) {
  EXPECT_THROW(interpret_lsystem(make_ls_word("F]F"), {}), Error);
  EXPECT_THROW(interpret_lsystem(make_ls_word("F[F"), {}), Error);
  EXPECT_THROW(interpret_lsystem(make_ls_word("F}"), {}), Error);
}

}  // namespace
}  // namespace sylva
