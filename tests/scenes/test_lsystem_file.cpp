// L-system (.lsys) and aspen grammar (.grammar) files: the shipped files parse and grow, the
// parametric ABOP tree expands as its productions say, and every kind of mistake is a ParseError
// naming the file and line. Mutated files never crash or hang.

#include "core/error.h"
#include "core/rng.h"
#include "geometry/trees/tree_mesher.h"
#include "scenes/species.h"
#include "scenes/species/lsystem_file.h"

#include "tests/support/mutate.h"

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

namespace sylva {
namespace {

std::string read_species(const std::string& name) {
  std::ifstream in(std::string(SYLVA_SOURCE_DIR "/data/species/") + name);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

TEST(LsystemFile, ShippedPlantsParseAndGrow) {
  for (const char* name : {"abop_bush.lsys", "abop_stochastic.lsys", "abop_monopodial.lsys"}) {
    const LSystemSpecies s = parse_lsystem(read_species(name), name);
    EXPECT_FALSE(s.name.empty());
    const TreeModel m = make_lsystem_tree(s.system, 1);
    EXPECT_GT(m.stems.size(), 10u) << name;
    const TreeMesh mesh = make_tree_mesh(m);
    EXPECT_GT(mesh.stems.triangles.size(), 100u) << name;
  }
  // The bush's polygons became leaves; Unicode ∧ read as ^.
  const LSystemSpecies bush = parse_lsystem(read_species("abop_bush.lsys"), "abop_bush.lsys");
  EXPECT_GT(make_lsystem_tree(bush.system, 1).leaves.size(), 100u);
  EXPECT_FLOAT_EQ(bush.system.turtle.angle_deg, 22.5f);
  EXPECT_EQ(bush.system.iterations, 7);
}

TEST(LsystemFile, ParametricProductionsDefinesAndConditions) {
  const std::string text =
      "define r = 0.5\n"
      "iterations = 4\n"
      "axiom = A(1, 2)   # comment\n"
      "A(l, w) : l >= 0.25 && w > -10 --> !(w)F(l)[+(45)A(l*r, w - 1)]A(l * r, max(w - 1, 0.5))\n"
      "A(l, w) : l < 0.25 -> ~(l*4)\n";
  const LSystemSpecies s = parse_lsystem(text, "t.lsys");
  ASSERT_EQ(s.system.productions.size(), 2u);
  EXPECT_EQ(ls_word_string(expand_lsystem(LSystem{s.system.axiom, s.system.productions, 1, 0, {}}, 0)),
            "!(2)F(1)[+(45)A(0.5,1)]A(0.5,1)");
  const LsWord w = expand_lsystem(s.system, 0);
  // Three levels of doubling then leaves: 2^3 leaves of scale 0.125 × 4 = 0.5.
  const TreeModel m = interpret_lsystem(w, s.system.turtle);
  EXPECT_EQ(m.leaves.size(), 8u);
  EXPECT_FLOAT_EQ(m.leaves.length_m[0], 0.5f * s.system.turtle.leaf_length);
}

TEST(LsystemFile, StochasticFileHitsItsProbabilities) {
  const LSystemSpecies s = parse_lsystem(read_species("abop_stochastic.lsys"), "abop_stochastic.lsys");
  ASSERT_EQ(s.system.productions.size(), 3u);
  // One rewrite of many F's: count which successor each produced by its bracket signature.
  LSystem one = s.system;
  one.iterations = 1;
  one.axiom = make_ls_word(std::string(20000, 'F'));
  const std::string w = ls_word_string(expand_lsystem(one, 3));
  size_t counts[3] = {0, 0, 0};
  for (size_t i = 0; i < w.size();) {
    if (w.compare(i, 11, "F[+F]F[-F]F") == 0)
      ++counts[0], i += 11;
    else if (w.compare(i, 6, "F[+F]F") == 0)
      ++counts[1], i += 6;
    else if (w.compare(i, 6, "F[-F]F") == 0)
      ++counts[2], i += 6;
    else
      FAIL() << "unexpected successor at " << i;
  }
  const double p[3] = {0.33, 0.33, 0.34};
  double chi2 = 0;
  for (int k = 0; k < 3; ++k) chi2 += std::pow(counts[k] - 20000 * p[k], 2) / (20000 * p[k]);
  EXPECT_LT(chi2, 13.8);  // χ²(2 dof), p = 0.001
}

TEST(LsystemFile, MistakesNameFileAndLine) {
  const std::pair<const char*, const char*> cases[] = {
      {"axiom = F\nF -> F[+F\n", "t.lsys:2: '[' without a matching ']'"},
      {"axiom = F\nangle = 25\nangle = 30\n", "t.lsys:3: 'angle' given twice (first on line 2)"},
      {"axiom = F\nangel = 25\n", "t.lsys:2: unknown setting 'angel'"},
      {"axiom = F\nF -> F : 1.5\n", "t.lsys:2: the probability must be in (0, 1]"},
      {"axiom = F\nA(x) -> F(y)\n", "t.lsys:2: unknown name 'y'"},
      {"axiom = F\nA(x, x) -> F\n", "t.lsys:2: parameter 'x' given twice"},
      {"axiom = F\nA(x) : x > -> F\n", "t.lsys:2: expected a value"},
      {"axiom = F\niterations = 2.5\n", "t.lsys:2: 'iterations' must be an integer"},
      {"axiom = F\niterations = 100\n", "t.lsys:2: 'iterations' must be in [0, 64]"},
      {"iterations = 3\n", "t.lsys:1: missing 'axiom = ...'"},
      {"axiom = F(1\n", "t.lsys:1: expected ',' or ')'"},
      {"axiom = F\nF -> F(((((((((((((((((((((((((((((((((((1)))))))))))))))))))))))))))))))))))\n",
       "t.lsys:2: expression nested deeper than 32 levels"},
      {"axiom = F\nthis is not a statement\n", "t.lsys:2: expected 'key = value'"},
      {"axiom = F\nF -> F\xC3\xA9\n", "t.lsys:2: byte 0xc3 is not a module symbol"},
      {"axiom = F\ntropism = 0, 0\n", "t.lsys:2: 'tropism' needs three values"},
      {"axiom = F\nmodel = \"weber-penn\"\n", "t.lsys:2: model must be \"lsystem\""},
  };
  for (const auto& [text, expected] : cases) {
    try {
      parse_lsystem(text, "t.lsys");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const ParseError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(expected, 0), 0u) << e.what() << "\nexpected: " << expected;
    }
  }
}

TEST(AspenGrammarFile, ShippedSpeciesParsesAndGrows) {
  const AspenGrammarSpecies s = parse_aspen_grammar(read_species("quaking_aspen.grammar"), "quaking_aspen.grammar");
  EXPECT_EQ(s.name, "Quaking Aspen (grammar)");
  EXPECT_FLOAT_EQ(s.params.divergence_deg, 138.0f);
  EXPECT_EQ(s.params.generations, 4);
  const TreeModel m = make_aspen_grammar_tree(s.params, 1);
  EXPECT_GT(m.stems.size(), 200u);
  EXPECT_GT(m.leaves.size(), 1000u);
}

TEST(AspenGrammarFile, MistakesNameFileAndLine) {
  const std::pair<const char*, const char*> cases[] = {
      {"height = 100\nheight = 200\n", "a.grammar:2: 'height' given twice (first on line 1)"},
      {"hieght = 100\n", "a.grammar:1: unknown key 'hieght' in the grammar file"},
      {"\ngenerations = 2.5\n", "a.grammar:2: 'generations' must be an integer"},
      {"height = -3\n", "a.grammar:1: 'height' must lie in"},
      {"height = tall\n", "a.grammar:1: 'height' must be a number"},
      {"branch_probability = 0.9\ndead_probability = 0.3\n", "a.grammar:2: branch_probability + dead_probability"},
      {"model = \"weber-penn\"\n", "a.grammar:1: model must be \"aspen-grammar\""},
      {"leaf_shape = \"fern\"\n", "a.grammar:1: unknown leaf_shape"},
      {"height\n", "a.grammar:1: expected 'key = value'"},
  };
  for (const auto& [text, expected] : cases) {
    try {
      parse_aspen_grammar(text, "a.grammar");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const ParseError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(expected, 0), 0u) << e.what() << "\nexpected: " << expected;
    }
  }
}

TEST(LsystemSpecies, RegisteredByExtensionAndModelKey) {
  const Species aspen = load_species(SYLVA_SOURCE_DIR "/data/species/quaking_aspen.grammar");
  ASSERT_TRUE(std::holds_alternative<AspenGrammarParams>(aspen.model));
  const Species bush = load_species(SYLVA_SOURCE_DIR "/data/species/abop_bush.lsys");
  ASSERT_TRUE(std::holds_alternative<LSystem>(bush.model));
  EXPECT_GT(make_species_mesh(bush, 1).leaves.size(), 100u);
  // The grammar mesh uses the thesis's 8-point circles on every stem.
  TreeMeshOptions eight;
  eight.radial_segments = {8, 8, 8, 8};
  const TreeMesh mesh = make_species_mesh(aspen, 1);
  EXPECT_EQ(mesh.stems.positions, make_tree_mesh(make_species_model(aspen, 1), eight).stems.positions);
  EXPECT_NE(mesh.stems.positions.size(), make_tree_mesh(make_species_model(aspen, 1)).stems.positions.size());
  // A TOML species may name the aspen grammar too; an L-system needs its .lsys file.
  const Species toml = parse_species("model = \"aspen-grammar\"\nheight = 200\ngenerations = 2\n", "a.toml");
  EXPECT_FLOAT_EQ(std::get<AspenGrammarParams>(toml.model).height, 200.0f);
  try {
    parse_species("model = \"lsystem\"\n", "l.toml");
    FAIL() << "an L-system without productions was accepted";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("l.toml:1: an L-system is written as a .lsys file"), std::string::npos)
        << e.what();
  }
}

// Damaged files either parse or throw a ParseError naming the file; a parsed one grows or fails
// with a clear sylva::Error (the length budget), never a crash or a hang.
template <typename Parse, typename Grow>
void fuzz(const std::string& name, const std::string& file, Parse parse, Grow grow) {
  const std::string base = read_species(name);
  ASSERT_GT(base.size(), 100u) << name;
  Pcg32 rng(11);
  const char junk[] = "[]{}()=:,*^/+-.#\n 0123456789e-+ABFfxyz\t!~&|\"";
  int rejected = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const std::string text = mutate_text(base, trial, rng, std::string_view(junk, sizeof(junk) - 1));
    try {
      const auto parsed = parse(text, file);
      try {
        grow(parsed);
      } catch (const ParseError&) {
        ADD_FAILURE() << "a parsed file failed to parse while growing";
      } catch (const Error&) {
      }
    } catch (const ParseError& e) {
      ++rejected;
      EXPECT_EQ(std::string(e.what()).rfind(file + ":", 0), 0u) << e.what();
    }
  }
  EXPECT_GT(rejected, 30) << name;
}

TEST(LsystemFile, DamagedFilesNeverCrash) {
  const auto grow = [](const LSystemSpecies& s) {
    LSystem small = s.system;
    small.iterations = std::min(small.iterations, 7);
    interpret_lsystem(expand_lsystem(small, 1, 200000), small.turtle);
  };
  fuzz("abop_monopodial.lsys", "fuzz.lsys", parse_lsystem, grow);
  fuzz("abop_bush.lsys", "fuzz.lsys", parse_lsystem, grow);
}

TEST(AspenGrammarFile, DamagedFilesNeverCrash) {
  fuzz("quaking_aspen.grammar", "fuzz.grammar", parse_aspen_grammar,
       [](const AspenGrammarSpecies& s) { make_aspen_grammar_tree(s.params, 1); });
}

}  // namespace
}  // namespace sylva
