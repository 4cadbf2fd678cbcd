// Species files under mutation: every damaged TOML or Arbaro XML file either parses or throws a
// ParseError naming the file and line; none crashes or hangs.

#include "core/error.h"
#include "core/rng.h"
#include "scenes/species.h"

#include "tests/support/mutate.h"

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

namespace sylva {
namespace {

void fuzz_species(const std::string& name, const std::string& extension) {
  std::ifstream in(std::string(SYLVA_SOURCE_DIR "/data/species/") + name);
  const std::string base((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_GT(base.size(), 100u) << name;
  Pcg32 rng(7);
  const char junk[] = "[]{}=\"<>/.#\n 0123456789e-+abcxyz\t'";
  const std::string file = "fuzz" + extension;
  int rejected = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const std::string text = mutate_text(base, trial, rng, std::string_view(junk, sizeof(junk) - 1));
    try {
      parse_species(text, file);
    } catch (const ParseError& e) {
      ++rejected;
      EXPECT_EQ(std::string(e.what()).rfind(file + ":", 0), 0u) << e.what();
    }
  }
  EXPECT_GT(rejected, 30) << name;
}

TEST(SpeciesFuzz, DamagedTomlNeverCrashes) { fuzz_species("california_black_oak.toml", ".toml"); }
TEST(SpeciesFuzz, DamagedArbaroXmlNeverCrashes) { fuzz_species("quaking_aspen_arbaro.xml", ".xml"); }
TEST(SpeciesFuzz, DamagedTreeMakerTemplateNeverCrashes) { fuzz_species("dogwood.tmpl", ".tmpl"); }

}  // namespace
}  // namespace sylva

namespace sylva {
namespace {

TEST(SpeciesFuzz, RunawayBranchingIsAClearErrorNotAnOutOfMemory) {
  std::ifstream in(SYLVA_SOURCE_DIR "/data/species/california_black_oak.toml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // Each value is within its range; together they ask for ~10^8 stems.
  for (const auto& [from, to] :
       {std::pair{"Branches = 40", "Branches = 3000"}, std::pair{"Branches = 120", "Branches = 90000"}}) {
    const auto pos = text.find(from);
    ASSERT_NE(pos, std::string::npos) << from;
    text.replace(pos, std::string(from).size(), to);
  }
  const Species s = parse_species(text, "runaway.toml");
  try {
    make_species_mesh(s, 1);
    FAIL() << "a tree with ~10^8 stems was generated";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("tree too large"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace sylva
