#include "hadal/config/yaml_reader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

namespace hadal::config {
namespace {

// Parses `text` as the root of a file "t.yaml"; diagnostics go to `sink`.
Value parse(const std::string& text, DiagnosticSink* sink) {
  auto source = std::make_shared<const Source>(Source{"t.yaml", sink, nullptr, nullptr, {}});
  return Value::root(YAML::Load(text), source);
}

std::vector<std::string> formatted(const DiagnosticSink& sink) {
  std::vector<std::string> lines;
  for (const Diagnostic& diagnostic : sink.sorted()) lines.push_back(diagnostic.format());
  return lines;
}

TEST(YamlReaderTest, NumbersFollowTheCoreSchema) {
  const std::pair<std::string, double> valid[] = {
      {"0", 0.0},          {"-5", -5.0},    {"+2.5", 2.5},
      {"1.", 1.0},         {".5", 0.5},     {"1e3", 1000.0},
      {"-1.5E-2", -0.015}, {"1e-400", 0.0}, {"0." + std::string(400, '0') + "1", 0.0}};
  for (const auto& [text, expected] : valid) {
    DiagnosticSink sink;
    EXPECT_EQ(parse(text, &sink).number(), expected) << text;
    EXPECT_TRUE(sink.empty()) << text;
  }
  for (const char* text : {"0x10", "1_000", "1e", "e3", "-", ".", "1.2.3", "true", "five", "'5'", "[1]"}) {
    DiagnosticSink sink;
    EXPECT_FALSE(parse(text, &sink).number().has_value()) << text;
    ASSERT_EQ(formatted(sink).size(), 1u) << text;
    EXPECT_EQ(formatted(sink)[0].rfind("t.yaml:1:1: error: expected a number (got ", 0), 0u)
        << formatted(sink)[0];
  }
  for (const std::string& text :
       {std::string(".nan"), std::string(".NaN"), std::string(".inf"), std::string("-.Inf"),
        std::string("+.INF"), std::string("1e999"), "1" + std::string(400, '0')}) {
    DiagnosticSink sink;
    EXPECT_FALSE(parse(text, &sink).number().has_value()) << text;
    EXPECT_EQ(formatted(sink),
              std::vector<std::string>{"t.yaml:1:1: error: must be a finite number (got " + text + ")"});
  }
}

TEST(YamlReaderTest, NonNegativeIntegersCoverUint64) {
  DiagnosticSink sink;
  EXPECT_EQ(parse("18446744073709551615", &sink).non_negative_integer(), 18446744073709551615u);
  EXPECT_FALSE(parse("18446744073709551616", &sink).non_negative_integer().has_value());
  EXPECT_EQ(formatted(sink), std::vector<std::string>{"t.yaml:1:1: error: must be <= 18446744073709551615 "
                                                      "(got 18446744073709551616)"});
}

TEST(YamlReaderTest, BooleansArePlainTrueOrFalse) {
  DiagnosticSink sink;
  EXPECT_EQ(parse("true", &sink).boolean(), true);
  EXPECT_EQ(parse("false", &sink).boolean(), false);
  EXPECT_TRUE(sink.empty());
  EXPECT_EQ(parse("TRUE", &sink).boolean(), true);
  for (const char* text : {"yes", "on", "1", "'true'", "tRue"}) {
    DiagnosticSink bad;
    EXPECT_FALSE(parse(text, &bad).boolean().has_value()) << text;
    ASSERT_EQ(formatted(bad).size(), 1u) << text;
    EXPECT_EQ(formatted(bad)[0].rfind("t.yaml:1:1: error: expected true or false (got ", 0), 0u)
        << formatted(bad)[0];
  }
}

TEST(YamlReaderTest, RangesDescribeThemselves) {
  EXPECT_EQ(Range::positive().describe(), "> 0");
  EXPECT_EQ(Range::non_negative().describe(), ">= 0");
  EXPECT_EQ(Range::closed(50, 100000).describe(), "in [50, 100000]");
  EXPECT_EQ(Range::left_open(0, 2000).describe(), "in (0, 2000]");
  EXPECT_EQ(Range::finite().describe(), "finite");
  EXPECT_FALSE(Range::positive().contains(0.0));
  EXPECT_TRUE(Range::non_negative().contains(0.0));
  EXPECT_FALSE(Range::finite().contains(INFINITY));
  EXPECT_TRUE(Range::closed(-1, 1).contains(-1.0));
}

TEST(YamlReaderTest, NumbersFormatShortestExact) {
  EXPECT_EQ(format_number(500.0), "500");
  EXPECT_EQ(format_number(100000.0), "100000");
  EXPECT_EQ(format_number(-0.1), "-0.1");
  EXPECT_EQ(format_number(1e-7), "1e-07");
  EXPECT_EQ(format_approximate(-0.9999999999999998), "-1");
}

TEST(YamlReaderTest, SuggestionsAreCloseKeysOnly) {
  const std::vector<std::string> keys = {"mass", "inertia", "physics_rate_hz", "radius"};
  EXPECT_EQ(closest_match("mas", keys), "mass");
  EXPECT_EQ(closest_match("Mass", keys), "mass");
  EXPECT_EQ(closest_match("intertia", keys), "inertia");
  EXPECT_EQ(closest_match("nmae", {"name"}), "name");  // a transposition is one edit
  EXPECT_EQ(closest_match("physics_rate", keys), "physics_rate_hz");
  EXPECT_EQ(closest_match("colour", keys), std::nullopt);
  EXPECT_EQ(closest_match("ma", keys), std::nullopt);
}

TEST(YamlReaderTest, MapReaderReportsEveryKeyProblemAtTheKey) {
  DiagnosticSink sink;
  const MapReader map(parse("radius: 1\nradios: 2\nradius: 3\nlength: x\n", &sink), {"radius", "length"});
  ASSERT_TRUE(map.ok());
  EXPECT_EQ(map.optional("radius")->node().Scalar(), "1");  // the first of duplicates
  double length = 7.0;
  EXPECT_FALSE(map.read_number("length", Need::kRequired, Range::positive(), &length));
  EXPECT_EQ(length, 7.0);
  EXPECT_EQ(
      formatted(sink),
      (std::vector<std::string>{"t.yaml:2:1: error: radios: unknown key 'radios'; did you mean 'radius'?",
                                "t.yaml:3:1: error: radius: duplicate key 'radius' (first defined at line 1)",
                                "t.yaml:4:9: error: length: expected a number (got 'x')"}));
}

TEST(YamlReaderTest, DiagnosticsSortByFileOrderThenPosition) {
  DiagnosticSink sink;
  sink.add_file("z.yaml");
  sink.add_file("a.yaml");
  YAML::Mark mark;
  mark.line = 4;
  mark.column = 0;
  sink.report("a.yaml", mark, "p", "second file");
  mark.line = 9;
  sink.report("z.yaml", mark, "p", "first file, later line");
  mark.line = 2;
  sink.report("z.yaml", mark, "p", "first file, earlier line");
  EXPECT_EQ(formatted(sink), (std::vector<std::string>{"z.yaml:3:1: error: p: first file, earlier line",
                                                       "z.yaml:10:1: error: p: first file, later line",
                                                       "a.yaml:5:1: error: p: second file"}));
}

}  // namespace
}  // namespace hadal::config
