// Params (core/params.h): typed, range-checked access with file:line errors and the unknown-key
// check; and the variant registry (core/registry.h).

#include "core/error.h"
#include "core/params.h"
#include "core/registry.h"

#include <gtest/gtest.h>

#include <functional>

#include <string>
#include <variant>

namespace sylva {
namespace {

ParamValue number(double x, int line) {
  ParamValue v;
  v.kind = ParamValue::Kind::Real;
  v.real = x;
  v.line = line;
  return v;
}
ParamValue integer(int64_t i, int line) {
  ParamValue v;
  v.kind = ParamValue::Kind::Integer;
  v.integer = i;
  v.line = line;
  return v;
}
ParamValue text(std::string s, int line) {
  ParamValue v;
  v.kind = ParamValue::Kind::String;
  v.string = std::move(s);
  v.line = line;
  return v;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const ParseError& e) {
    return e.what();
  }
  return "no error";
}

TEST(Params, TypedAccessWithFallbacks) {
  Params p("a.toml", 3, "[t]");
  p.add("x", number(2.5, 4));
  p.add("n", integer(7, 5));
  p.add("s", text("hello", 6));
  EXPECT_EQ(p.number("x", 0, 0, 10), 2.5);
  EXPECT_EQ(p.integer("n", 0, 0, 10), 7);
  EXPECT_EQ(p.string("s"), "hello");
  EXPECT_EQ(p.number("missing", 1.25, 0, 10), 1.25);
  EXPECT_EQ(p.string("missing", "fallback"), "fallback");
  EXPECT_EQ(p.vec3("missing", Vec3(1, 2, 3)), Vec3(1, 2, 3));
  EXPECT_NO_THROW(p.check_unused());
}

TEST(Params, ErrorsNameFileLineAndKey) {
  Params p("a.toml", 3, "[t]");
  p.add("x", number(20, 4));
  p.add("f", number(2.5, 5));
  p.add("s", text("word", 6));
  EXPECT_EQ(error_of([&] { p.number("x", 0, 0, 10); }), "a.toml:4: 'x' must lie in [0, 10], not 20");
  EXPECT_EQ(error_of([&] { p.integer("f", 0, 0, 10); }), "a.toml:5: 'f' must be an integer, not 2.5");
  EXPECT_EQ(error_of([&] { p.integer("s", 0, 0, 10); }), "a.toml:6: 's' must be an integer");
  EXPECT_EQ(error_of([&] { p.string("missing"); }), "a.toml:3: missing key 'missing' in [t]");
  EXPECT_EQ(error_of([&] { p.add("x", number(1, 9)); }), "a.toml:9: parameter 'x' given twice (first on line 4)");
}

TEST(Params, SchemaTablesReadPresentFieldsAndKeepDefaults) {
  Params p("a.toml", 1, "[species]");
  p.add("height", number(12.5, 2));
  p.add("count", integer(4, 3));
  float height = 1.0f, width = 0.5f;
  int count = 1, depth = 2;
  const RealField reals[] = {{"height", &height, 0, 100}, {"width", &width, 0, 10}};
  const IntField ints[] = {{"count", &count, 0, 10}, {"depth", &depth, 0, 10}};
  p.read_fields(reals, ints);
  EXPECT_EQ(height, 12.5f);
  EXPECT_EQ(width, 0.5f);
  EXPECT_EQ(count, 4);
  EXPECT_EQ(depth, 2);
  const IntField narrow[] = {{"count", &count, 0, 3}};
  EXPECT_EQ(error_of([&] { p.read_fields({}, narrow); }), "a.toml:3: 'count' must lie in [0, 3], not 4");
}

TEST(Params, UnknownKeysAreReportedWithWhatWasExpected) {
  Params p("a.toml", 1, "[camera]");
  p.add("vfov", number(40, 2));
  p.add("fov", number(40, 3));
  p.number("vfov", 45, 0, 180);
  p.number("aperture", 0, 0, 1);
  EXPECT_EQ(error_of([&] { p.check_unused(); }),
            "a.toml:3: unknown key 'fov' in [camera] (expected one of: vfov, aperture)");
  EXPECT_EQ(error_of([&] { p.check_keys({"vfov"}); }),
            "a.toml:3: unknown key 'fov' in [camera] (expected one of: vfov)");
  EXPECT_EQ(error_of([&] { p.with_where("material 'm'").check_keys({"vfov"}); }),
            "a.toml:3: unknown key 'fov' in material 'm' (expected one of: vfov)");
}

TEST(Params, SpectraFromNumbersNamesAndInlineTables) {
  Params p("a.toml", 1, "[m]");
  p.add("c", number(0.25, 2));
  p.add("n", text("astm-g173-direct", 3));
  auto inline_table = std::make_shared<Params>("a.toml", 4, "[m]");
  ParamValue l, v;
  l.kind = v.kind = ParamValue::Kind::Array;
  l.line = v.line = 4;
  l.array = {number(400, 4), number(800, 4)};
  v.array = {number(0.2, 4), number(0.6, 4)};
  inline_table->add("lambda_nm", l);
  inline_table->add("value", v);
  ParamValue t;
  t.kind = ParamValue::Kind::Table;
  t.table = inline_table;
  t.line = 4;
  p.add("i", t);
  p.add("bad", text("moonlight", 5));
  EXPECT_FLOAT_EQ(p.spectrum("c", Extrapolate::Clamp)[0], 0.25f);
  EXPECT_FLOAT_EQ(p.spectrum("n", Extrapolate::Zero).max_value(), astm_g173_direct().max_value());
  const DenseSpectrum s = p.spectrum("i", Extrapolate::Clamp);
  EXPECT_NEAR(s.eval(600.0f), 0.4f, 1e-4f);
  EXPECT_EQ(error_of([&] { p.spectrum("bad", Extrapolate::Zero); }).rfind("a.toml:5: unknown spectrum 'moonlight'", 0),
            0u);
}

struct Alpha {
  static constexpr std::string_view kType = "alpha";
  int value = 0;
  static Alpha create(int v) { return {v}; }
};
struct Beta {
  static constexpr std::string_view kType = "beta";
  int value = 0;
  static Beta create(int v) { return {2 * v}; }
};
using Registered = std::variant<Alpha, Beta>;

TEST(Registry, CreatesByNameAndListsNames) {
  const std::optional<Registered> b = create_registered<Registered>("beta", 5);
  ASSERT_TRUE(b.has_value());
  ASSERT_TRUE(std::holds_alternative<Beta>(*b));
  EXPECT_EQ(std::get<Beta>(*b).value, 10);
  EXPECT_EQ(registered_name(*b), "beta");
  EXPECT_FALSE(create_registered<Registered>("gamma", 1).has_value());
  EXPECT_EQ(registered_names<Registered>(), "\"alpha\", \"beta\"");
}

}  // namespace
}  // namespace sylva
