// TREE-MAKER template files (scenes/species/treemaker_file.h): the paper's dogwood template as
// printed, Figure 6's rules (spacing, rule levels, probabilities, order), every kind of mistake
// with its line, damaged files never crash, and geometry goldens of the shipped templates.

#include "core/error.h"
#include "core/rng.h"
#include "geometry/trees/tree_mesher.h"
#include "geometry/trees/tree_stats.h"
#include "scenes/species/treemaker_file.h"

#include "tests/support/mutate.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <tuple>
#include <vector>

namespace sylva {
namespace {

const std::filesystem::path kSpeciesDir = std::filesystem::path(SYLVA_SOURCE_DIR) / "data" / "species";

std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

TEST(TreeMakerFile, ReadsThePapersDogwood) {
  const TreeMakerTemplate t = load_treemaker_template(kSpeciesDir / "dogwood.tmpl");
  EXPECT_EQ(t.iterations, 13);
  EXPECT_FLOAT_EQ(t.gravity, 0.08f);
  EXPECT_FLOAT_EQ(t.light.lambert, 0.4f);
  EXPECT_FLOAT_EQ(t.light.angle, 0.2f);
  ASSERT_EQ(t.colors.size(), 3u);
  EXPECT_EQ(t.colors[1].name, "brown");
  EXPECT_FLOAT_EQ(t.colors[1].rgb.y, 0.9f);
  ASSERT_EQ(t.branches.size(), 5u);
  const int levels[] = {1, 2, 3, 7, 9};
  for (size_t i = 0; i < 5; ++i) EXPECT_EQ(t.branches[i].level, levels[i]);
  EXPECT_FLOAT_EQ(t.branches[0].number.lo, 2.0f);
  EXPECT_FLOAT_EQ(t.branches[0].number.hi, 3.0f);
  ASSERT_EQ(t.branches[2].choices.size(), 3u);
  EXPECT_FLOAT_EQ(t.branches[2].choices[2].p, 0.10f);
  EXPECT_FLOAT_EQ(t.branches[2].choices[2].factor.lo, 0.1f);
  EXPECT_FLOAT_EQ(t.branches[2].choices[2].factor.hi, 0.2f);
  EXPECT_FLOAT_EQ(t.branches[1].choices[1].dir_deg.lo, 160.0f);
  ASSERT_EQ(t.particles.size(), 1u);
  const TreeMakerParticle& p = t.particles[0];
  EXPECT_FLOAT_EQ(p.mag.lo, 15.0f);
  EXPECT_FLOAT_EQ(p.mag.hi, 25.0f);
  EXPECT_EQ(p.dir, Vec3(0, 0, 1));
  EXPECT_FLOAT_EQ(p.max_dev_deg, 10.0f);
  EXPECT_FLOAT_EQ(p.acc, -0.8f);
  EXPECT_FLOAT_EQ(p.growth, 0.4f);
  EXPECT_EQ(p.color, 1);
  EXPECT_FLOAT_EQ(p.brightness.hi, 0.5f);
  ASSERT_EQ(t.leaves.size(), 2u);
  EXPECT_FLOAT_EQ(t.leaves[0].p, 0.6f);
  EXPECT_EQ(t.leaves[0].coord, TreeMakerCoord::Leaf);
  EXPECT_FLOAT_EQ(t.leaves[0].out_deg, 30.0f);
  EXPECT_FLOAT_EQ(t.leaves[0].up_deg, 10.0f);
  ASSERT_EQ(t.leaves[0].elements.size(), 2u);
  EXPECT_EQ(t.leaves[0].elements[0].points[1], Vec3(0, -9, 3));
  ASSERT_EQ(t.leaves[1].elements.size(), 5u);
  EXPECT_EQ(t.leaves[1].elements[0].color, 2);  // white petals
  EXPECT_EQ(t.leaves[1].elements[4].color, 0);  // green centre
  EXPECT_FLOAT_EQ(t.leaves[1].elements[4].brightness.lo, 0.5f);
  // §IV: the rule of the nearest level at or below.
  EXPECT_EQ(t.rule_for_level(1)->level, 1);
  EXPECT_EQ(t.rule_for_level(5)->level, 3);
  EXPECT_EQ(t.rule_for_level(8)->level, 7);
  EXPECT_EQ(t.rule_for_level(13)->level, 9);
}

TEST(TreeMakerFile, AnySpacingGivesTheSameTemplate) {
  const std::string spaced =
      "iterations { i= 4 }\ncolor { g = 0 , 1 , 0 }\ncolor{b=1,1,0.5}\n"
      "branch { level = 2 number = 1 to 2\n ( p = 1 angle = 10 to 20\n dir = 0 to 9 factor = 0.5 to 0.6 ) }\n"
      "particle { mag = 3 to 4 dir = 0 , 0 , 1 : 5 color = b }\n"
      "leaf { p = 1 coord = limb color = g tri = 0,0,0 1,0,0 0,1,0 ln = 0 , 0 , 0 0 , 0 , 1 }\n";
  const std::string tight =
      "iterations{i=4}color{g=0,1,0}color{b=1,1,0.5}branch{level=2 number=1 to 2(p=1 angle=10 to 20 dir=0 to 9 "
      "factor=0.5 to 0.6)}particle{mag=3 to 4 dir=0,0,1:5 color=b}leaf{p=1 coord=limb color=g tri=0,0,0 1,0,0 "
      "0,1,0 ln=0,0,0 0,0,1}";
  const TreeMakerTemplate a = parse_treemaker_template(spaced, "a.tmpl");
  const TreeMakerTemplate b = parse_treemaker_template(tight, "b.tmpl");
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_EQ(a.branches[0].choices[0].factor.hi, b.branches[0].choices[0].factor.hi);
  EXPECT_EQ(a.particles[0].max_dev_deg, 5.0f);
  EXPECT_EQ(b.particles[0].max_dev_deg, 5.0f);
  EXPECT_EQ(a.leaves[0].elements.size(), 2u);
  EXPECT_TRUE(a.leaves[0].elements[1].is_line());
  EXPECT_EQ(a.leaves[0].elements[1].points[1], b.leaves[0].elements[1].points[1]);
  EXPECT_EQ(a.rule_for_level(1), nullptr);  // no rule at or below level 1
  // Same template, same tree.
  const TreeModel ta = make_treemaker_tree(a, 3), tb = make_treemaker_tree(b, 3);
  EXPECT_EQ(ta.sections.positions, tb.sections.positions);
}

// A valid template with one line to break; line numbers are 1-based.
const char* kGood =
    "iterations { i= 3 }\n"                                             // 1
    "gravity { g= 0.1 }\n"                                              // 2
    "color { green= 0,1,0 }\n"                                          // 3
    "color { brown= 1,0.9,0.2 }\n"                                      // 4
    "branch { level= 1 number= 1 to 2\n"                                // 5
    "  (p=0.5 angle= 40 to 60 dir= 0 to 20 factor= 0.5 to 0.7)\n"       // 6
    "  (p=0.5 angle= 40 to 60 dir= 160 to 180 factor= 0.5 to 0.7) }\n"  // 7
    "particle { pos=0,0,0 mag= 10 to 12 dir= 0,0,1:5 acc= -0.5\n"       // 8
    "  growth= 0.3 age= 0 color= brown brightness= 0.2 to 0.5 }\n"      // 9
    "leaf { p= 1 coord= leaf out= 30 up= 10\n"                          // 10
    "  color= green brightness= 0.4 to 0.8\n"                           // 11
    "  tri= 0,0,0 0,-9,3 -3,-3,4 }\n";                                  // 12

std::string replace_line(int line, const std::string& with) {
  std::istringstream in(kGood);
  std::string out, l;
  for (int n = 1; std::getline(in, l); ++n) out += (n == line ? with : l) + "\n";
  return out;
}

TEST(TreeMakerFile, TheTestTemplateIsValid) { EXPECT_NO_THROW(parse_treemaker_template(kGood, "good.tmpl")); }

TEST(TreeMakerFile, RejectsEachKindOfMistakeAtItsLine) {
  struct Case {
    std::string text;
    int line;
    const char* message;
  };
  const std::vector<Case> cases = {
      {replace_line(7, "  (p=0.4 angle= 40 to 60 dir= 160 to 180 factor= 0.5 to 0.7) }"), 5, "add up to 0.9, not 1"},
      {std::string(kGood) + "branch { level= 2 number= 1 (p=1 angle=1 dir=1 factor=1) }\n", 13,
       "must come before the particles"},
      {replace_line(2, "gravitation { g= 0.1 }"), 2, "unknown section 'gravitation'"},
      {replace_line(2, "gravity { G= 0.1 }"), 2, "unknown keyword 'G' in gravity"},
      {replace_line(6, "  (p=0.5 angel= 40 to 60 dir= 0 to 20 factor= 0.5 to 0.7)"), 6, "unknown keyword 'angel'"},
      {replace_line(6, "  (p=0.5 angle= dir= 0 to 20 factor= 0.5 to 0.7)"), 6, "expected a number for 'angle='"},
      {replace_line(6, "  (p=0.5 angle= 40 to dir= 0 to 20 factor= 0.5 to 0.7)"), 6, "end of the 'angle=' range"},
      {replace_line(7, "  (p=0.5 angle= 40 to 60 dir= 160 to 180) }"), 7, "the triplet is missing 'factor='"},
      {replace_line(5, "branch { level= 1"), 7, "branch is missing 'number='"},
      {replace_line(9, "  growth= 0.3 age= 0 brightness= 0.2 to 0.5 }"), 9, "particle is missing 'color='"},
      {replace_line(9, "  growth= 0.3 age= 0 color= bron brightness= 0.2 to 0.5 }"), 9, "unknown color 'bron'"},
      {replace_line(10, "leaf { p= 0.7 coord= leaf out= 30 up= 10"), 10, "the leaf probabilities add up to 0.7"},
      {replace_line(10, "leaf { p= 1 coord= branch out= 30 up= 10"), 10, "'coord=' must be limb or leaf"},
      {replace_line(12, "  tri= 0,0,0 0,-9,3 }"), 12, "expected a number for 'tri='"},
      {replace_line(11, "  color= green brightness= 0.4 to 1.8"), 11, "'brightness=' must lie in [0, 1]"},
      {replace_line(11, "  color= green brightness= 0.8 to 0.4"), 11, "range goes from 0.8 down to 0.4"},
      {replace_line(1, "iterations { i= 2.5 }"), 1, "'i=' must be a whole number"},
      {replace_line(1, "iterations { i 3 }"), 1, "expected '=' after 'i'"},
      {replace_line(4, "color { green= 1,0.9,0.2 }"), 4, "color 'green' is already defined"},
      {replace_line(3, "color { green= 0,1,0 } @"), 3, "unexpected character '@'"},
      {replace_line(8, "particle { pos=0,0,0 mag= 10 to 12 dir= 0,0,0:5 acc= -0.5"), 8,
       "'dir=' must not be the zero vector"},
      {replace_line(2, "gravity { g= 0.1 g= 0.2 }"), 2, "'g=' is repeated"},
      {replace_line(2, "gravity { g= 0.1 } gravity { g= 0.1 }"), 2, "the gravity section is repeated"},
      {replace_line(12, "  tri= 0,0,0 0,-9,3 -3,-3,4"), 13, "expected a keyword or '}' in leaf"},
      {replace_line(11, "  brightness= 0.4 to 0.8"), 12, "'tri=' needs a color= before it"},
      {replace_line(5, "branch { level= 1 number= 1 to 2 p=1"), 5, "unknown keyword 'p' in branch"},
  };
  for (const Case& c : cases) {
    try {
      parse_treemaker_template(c.text, "bad.tmpl");
      ADD_FAILURE() << "accepted a template expecting '" << c.message << "':\n" << c.text;
    } catch (const ParseError& e) {
      EXPECT_EQ(e.line(), c.line) << e.what();
      EXPECT_NE(std::string(e.what()).find(c.message), std::string::npos) << e.what();
      EXPECT_EQ(std::string(e.what()).rfind("bad.tmpl:", 0), 0u) << e.what();
    }
  }
}

TEST(TreeMakerFile, MissingSectionsAreNamed) {
  for (const auto& [drop_from, drop_to, message] :
       {std::tuple{1, 1, "missing the iterations"}, std::tuple{5, 7, "at least one branch rule"},
        std::tuple{8, 9, "at least one particle"}, std::tuple{10, 12, "at least one leaf definition"}}) {
    std::istringstream in(kGood);
    std::string text, l;
    for (int n = 1; std::getline(in, l); ++n)
      if (n < drop_from || n > drop_to) text += l + "\n";
    try {
      parse_treemaker_template(text, "bad.tmpl");
      ADD_FAILURE() << message;
    } catch (const ParseError& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  }
}

// Damaged templates either parse or throw a ParseError naming the file; none crashes or hangs,
// and whatever parses also grows (or stops at the growth budget with a clear error).
TEST(TreeMakerFile, DamagedTemplatesNeverCrash) {
  const std::string base = read_text(kSpeciesDir / "dogwood.tmpl");
  ASSERT_GT(base.size(), 500u);
  Pcg32 rng(11);
  const char junk[] = "{}()=,:#\n 0123456789.e-+tolimbeafxyz\t";
  int rejected = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const std::string text = mutate_text(base, trial, rng, std::string_view(junk, sizeof(junk) - 1));
    try {
      const TreeMakerTemplate t = parse_treemaker_template(text, "fuzz.tmpl");
      try {
        make_treemaker_tree(t, 1);
      } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("tree too large"), std::string::npos) << e.what();
      }
    } catch (const ParseError& e) {
      ++rejected;
      EXPECT_EQ(std::string(e.what()).rfind("fuzz.tmpl:", 0), 0u) << e.what();
    }
  }
  EXPECT_GT(rejected, 100);
}

// What makes the dogwood a flowering dogwood (§V): a short trunk branching low into a broad,
// layered crown a few metres tall, about 60 % leaves and 40 % white flowers at the branch ends.
TEST(TreeMakerFile, DogwoodGrowsIntoAFloweringTree) {
  const TreeMakerTemplate t = load_treemaker_template(kSpeciesDir / "dogwood.tmpl");
  int ends = 0, flowers = 0;
  for (uint64_t seed = 1; seed <= 5; ++seed) {
    const TreeModel m = make_treemaker_tree(t, seed);
    const TreeMesh mesh = make_tree_mesh(m);
    const Bounds3 b = bounds_of(mesh);
    const float height = b.hi.z - b.lo.z;
    const float width = std::max(b.hi.x - b.lo.x, b.hi.y - b.lo.y);
    std::printf("dogwood seed %d: %zu stems, %zu leaf quads, height %.2f m, crown %.2f m\n", static_cast<int>(seed),
                m.stems.size(), m.leaves.size(), height, width);
    EXPECT_GT(height, 3.0f);
    EXPECT_LT(height, 10.0f);
    EXPECT_GT(width, 0.6f * height);  // broader than tall-ish, as dogwoods are
    EXPECT_GT(m.stems.size(), 200u);
    std::vector<int> stem_has_flower(m.stems.size(), 0);
    for (size_t i = 0; i < m.leaves.size(); ++i)
      if (m.leaves.material_of(i) == 1) stem_has_flower[static_cast<size_t>(m.leaves.stem[i])] = 1;
    for (const int f : stem_has_flower) flowers += f;
    ends += static_cast<int>(m.stems.size());
  }
  EXPECT_NEAR(flowers, 0.4 * ends, 4.0 * std::sqrt(0.24 * ends));
  const TreeMakerMaterials mats = treemaker_materials(t);
  ASSERT_EQ(mats.element_rgb.size(), 2u);
  EXPECT_EQ(mats.element_color_names[1], "white");
}

}  // namespace
}  // namespace sylva
