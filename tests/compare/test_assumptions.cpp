// What a comparison assumes of its images (compare/assumptions.h): equal seeds and different
// settings are refused unless intended, attributes recorded on one side only are noted.

#include "compare/assumptions.h"
#include "core/error.h"

#include <gtest/gtest.h>

namespace sylva {
namespace assumptions_test {
namespace {

Image with(std::vector<std::pair<std::string, std::string>> attributes) {
  Image image = make_image(1, 1, {"R"});
  image.attributes = std::move(attributes);
  return image;
}

const std::vector<std::pair<std::string, std::string>> kRef{
    {"sylva:seed", "1"},        {"sylva:spp", "4096"},          {"sylva:scene_hash", "abc"},
    {"sylva:bands", "rgb,nir"}, {"sylva:quantity", "radiance"}, {"sylva:max_depth", "8"},
    {"sylva:sampler", "sobol"}, {"sylva:version", "0.1.0"}};

Image changed(const std::string& key, const std::string& value) {
  Image image = with(kRef);
  image.set_attribute(key, value);
  return image;
}

TEST(Assumptions, AnotherSeedAndSppAloneIsClean) {
  Image test = changed("sylva:seed", "2");
  test.set_attribute("sylva:spp", "64");
  const AssumptionReport r = check_assumptions(test, with(kRef), {});
  EXPECT_TRUE(r.findings.empty());
  EXPECT_FALSE(r.refused());
}

TEST(Assumptions, TheSameSeedIsRefusedUnlessAllowed) {
  const AssumptionReport r = check_assumptions(with(kRef), with(kRef), {});
  ASSERT_TRUE(r.refused());
  EXPECT_NE(r.refusal().find("same seed (1)"), std::string::npos) << r.refusal();
  EXPECT_NE(r.refusal().find("--allow-same-seed"), std::string::npos) << r.refusal();
  const AssumptionReport allowed = check_assumptions(with(kRef), with(kRef), {.allow_same_seed = true});
  EXPECT_FALSE(allowed.refused());
  ASSERT_EQ(allowed.findings.size(), 1u);  // still reported
  EXPECT_EQ(allowed.findings[0].key, "seed");
}

TEST(Assumptions, EveryDifferenceIsRefusedAndNamed) {
  const std::vector<std::pair<std::string, std::string>> cases{{"sylva:scene_hash", "scene"},
                                                               {"sylva:bands", "bands"},
                                                               {"sylva:quantity", "quantity"},
                                                               {"sylva:max_depth", "depth"},
                                                               {"sylva:sampler", "sampler"},
                                                               {"sylva:irradiance", "spectral"},
                                                               {"sylva:wavelength_sampling", "spectral"}};
  for (const auto& [attribute, key] : cases) {
    Image test = changed("sylva:seed", "2");
    Image ref = with(kRef);
    test.set_attribute(attribute, "one");
    ref.set_attribute(attribute, "other");
    const AssumptionReport r = check_assumptions(test, ref, {});
    EXPECT_TRUE(r.refused()) << attribute;
    EXPECT_NE(r.refusal().find(attribute + " differs: test one, reference other"), std::string::npos) << r.refusal();
    EXPECT_NE(r.refusal().find("--allow-difference " + key), std::string::npos) << r.refusal();
    EXPECT_FALSE(check_assumptions(test, ref, {.allowed = {key}}).refused()) << key;
    EXPECT_FALSE(check_assumptions(test, ref, {.allowed = {"all"}}).refused()) << key;
    EXPECT_EQ(check_assumptions(test, ref, {.allowed = {key}}).findings.size(), 1u);
  }
}

TEST(Assumptions, VersionIsNotedAndOneSidedAttributesAreNotCompared) {
  Image test = changed("sylva:seed", "2");
  test.set_attribute("sylva:version", "0.2.0");
  Image ref = with(kRef);
  ref.attributes.erase(ref.attributes.begin() + 6);  // no sylva:sampler: an older reference
  const AssumptionReport r = check_assumptions(test, ref, {});
  EXPECT_FALSE(r.refused());
  ASSERT_EQ(r.findings.size(), 2u);
  EXPECT_EQ(r.findings[0].key, "sampler");
  EXPECT_NE(r.findings[0].message.find("recorded only in the test"), std::string::npos) << r.findings[0].message;
  EXPECT_EQ(r.findings[1].key, "version");
}

TEST(Assumptions, NumbersAgreeToTheirLastPrintedDigit) {
  Image test = changed("sylva:seed", "2");
  Image ref = with(kRef);
  test.set_attribute("sylva:irradiance", "R=1.072743,B=0.8534513,nir.Y=0.4847446");
  ref.set_attribute("sylva:irradiance", "R=1.072743,B=0.8534512,nir.Y=0.4847446");
  EXPECT_FALSE(check_assumptions(test, ref, {}).refused());
  test.set_attribute("sylva:irradiance", "R=1.072743,B=0.8535,nir.Y=0.4847446");
  EXPECT_TRUE(check_assumptions(test, ref, {}).refused());
  test.set_attribute("sylva:irradiance", "R=1.072743,B=0.8534513,nir.Y=0.4847446,swir.Y=1");
  EXPECT_TRUE(check_assumptions(test, ref, {}).refused());
}

TEST(Assumptions, UnknownKeyIsAnError) {
  EXPECT_THROW(check_assumptions(with(kRef), with(kRef), {.allowed = {"colour"}}), Error);
}

}  // namespace
}  // namespace assumptions_test
}  // namespace sylva
