// Names of enumeration values (enum_names.hpp), and every table of names the
// public headers declare beside their enums: a name gives its value, a bad
// name is refused with the choices, and every value's name reads back as it.
#include "animanifold/enum_names.hpp"

#include "animanifold/errors.hpp"
#include "animanifold/laplacian.hpp"
#include "animanifold/morph.hpp"
#include "animanifold/refine.hpp"
#include "animanifold/skeleton.hpp"
#include "animanifold/subdivide.hpp"

#include <gtest/gtest.h>

#include <cstddef>
#include <functional>
#include <set>
#include <string_view>
#include <string>

using namespace animanifold;

namespace {

enum class Colour { Red, Green, Blue, Unnamed };

constexpr NameTable<Colour, 3> kColourNames{{{Colour::Red, "red"}, {Colour::Green, "green"}, {Colour::Blue, "blue"}}};

std::string input_error_of(const std::function<void()>& call) {
  try {
    call();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

// Every entry of `names` parses back to its value, its name is the table's
// (name_of), and names and values are each listed once.
template <class Enum, std::size_t N>
void expect_round_trip(const NameTable<Enum, N>& names, const char* what) {
  std::set<std::string> seen_names;
  std::set<Enum> seen_values;
  for (const auto& [value, name] : names) {
    SCOPED_TRACE(std::string(what) + " '" + name + "'");
    EXPECT_EQ(parse_name(name, names, what), value);
    EXPECT_STREQ(name_of(value, names), name);
    EXPECT_TRUE(seen_names.insert(name).second) << "name listed twice";
    EXPECT_TRUE(seen_values.insert(value).second) << "value listed twice";
  }
}

}  // namespace

TEST(EnumNames, ANameGivesItsValue) {
  EXPECT_EQ(parse_name("red", kColourNames, "colour"), Colour::Red);
  EXPECT_EQ(parse_name("green", kColourNames, "colour"), Colour::Green);
  EXPECT_EQ(parse_name("blue", kColourNames, "colour"), Colour::Blue);
}

TEST(EnumNames, ABadNameIsRefusedNamingItAndTheChoices) {
  EXPECT_EQ(input_error_of([] { parse_name("purple", kColourNames, "colour"); }),
            "unknown colour 'purple': use 'red', 'green' or 'blue'");
  // Names are matched exactly: another case or surrounding space is another name.
  EXPECT_EQ(input_error_of([] { parse_name("Red", kColourNames, "colour"); }),
            "unknown colour 'Red': use 'red', 'green' or 'blue'");
  EXPECT_EQ(input_error_of([] { parse_name(" red", kColourNames, "colour"); }),
            "unknown colour ' red': use 'red', 'green' or 'blue'");
  EXPECT_EQ(input_error_of([] { parse_name("", kColourNames, "colour"); }),
            "unknown colour '': use 'red', 'green' or 'blue'");
}

TEST(EnumNames, TheChoicesAreQuotedInTableOrder) {
  EXPECT_EQ(quoted_choices(kColourNames), "'red', 'green' or 'blue'");
  EXPECT_EQ(quoted_choices(NameTable<Colour, 2>{{{Colour::Red, "red"}, {Colour::Blue, "blue"}}}), "'red' or 'blue'");
  EXPECT_EQ(quoted_choices(NameTable<Colour, 1>{{{Colour::Green, "green"}}}), "'green'");
}

TEST(EnumNames, AValueMissingFromTheTableIsNamedWithAQuestionMark) {
  EXPECT_STREQ(name_of(Colour::Unnamed, kColourNames), "?");
}

TEST(EnumNames, NameOfIsAConstantExpression) {
  static_assert(std::string_view(name_of(Colour::Blue, kColourNames)) == "blue");
  SUCCEED();
}

TEST(EnumNames, EveryTableOfTheHeadersRoundTrips) {
  expect_round_trip(kLaplacianMethodNames, "Laplacian method");
  expect_round_trip(kBoundaryRuleNames, "boundary rule");
  expect_round_trip(kMorphMethodNames, "morph method");
  expect_round_trip(kFillTriangulationNames, "fill");
  expect_round_trip(kPerturbationNames, "perturbation");
  expect_round_trip(kRefineOrderNames, "refine order");
  expect_round_trip(kWrapShapeNames, "wrap shape");
  expect_round_trip(kSkeletonSideNames, "skeleton side");
  expect_round_trip(kManifoldSchemeNames, "manifold subdivision scheme");
  expect_round_trip(kFrameSchemeNames, "frame subdivision scheme");
}

TEST(EnumNames, ToStringRoundTripsThroughTheHeadersParsers) {
  for (const auto& [method, name] : kLaplacianMethodNames) {
    EXPECT_EQ(to_string(method), name);
    EXPECT_EQ(parse_laplacian_method(to_string(method)), method);
  }
  for (const auto& [rule, name] : kBoundaryRuleNames) {
    EXPECT_EQ(to_string(rule), name);
    EXPECT_EQ(parse_boundary_rule(to_string(rule)), rule);
  }
  for (const auto& [shape, name] : kWrapShapeNames) EXPECT_EQ(parse_wrap_shape(name), shape);
  for (const auto& [scheme, name] : kManifoldSchemeNames) EXPECT_EQ(parse_manifold_scheme(name), scheme);
  for (const auto& [scheme, name] : kFrameSchemeNames) EXPECT_EQ(parse_frame_scheme(name), scheme);
}

TEST(EnumNames, TheHeadersParsersRefuseABadNameNamingTheChoices) {
  EXPECT_EQ(input_error_of([] { parse_laplacian_method("cotan"); }),
            "unknown Laplacian method 'cotan': use 'dual', 'graph', 'uniform' or 'cotangent'");
  EXPECT_EQ(input_error_of([] { parse_boundary_rule("ghost"); }),
            "unknown boundary rule 'ghost': use 'grow', 'ghost_anchors' or 'error'");
  EXPECT_EQ(input_error_of([] { parse_wrap_shape("cube"); }),
            "unknown wrap shape 'cube': use 'box', 'sphere' or 'none'");
  EXPECT_EQ(input_error_of([] { parse_manifold_scheme("loop"); }),
            "unknown manifold subdivision scheme 'loop': use 'schaefer' or 'linear'");
  EXPECT_EQ(input_error_of([] { parse_frame_scheme("catmull-clark"); }),
            "unknown frame subdivision scheme 'catmull-clark': use 'loop', 'catmull_clark' or 'bspline'");
}

TEST(EnumNames, AnEmptyWrapShapeIsNone) {
  EXPECT_EQ(parse_wrap_shape(""), WrapShape::None);
  EXPECT_EQ(parse_wrap_shape("none"), WrapShape::None);
}

TEST(EnumNames, TheFirstEntryIsTheDefaultWhereTheOptionsHaveOne) {
  EXPECT_EQ(kLaplacianMethodNames[0].first, LaplacianOptions{}.method);
  EXPECT_EQ(kBoundaryRuleNames[0].first, DeformerOptions{}.boundary);
  EXPECT_EQ(kMorphMethodNames[0].first, MorphOptions{}.method);
  EXPECT_EQ(kFillTriangulationNames[0].first, MorphOptions{}.fill);
  EXPECT_EQ(kPerturbationNames[0].first, MorphOptions{}.perturbation);
  EXPECT_EQ(kWrapShapeNames[0].first, SkeletonOptions{}.wrap);
  EXPECT_EQ(kManifoldSchemeNames[0].first, ManifoldSubdivisionOptions{}.scheme);
  EXPECT_EQ(kFrameSchemeNames[0].first, FrameSubdivisionOptions{}.scheme);
}
