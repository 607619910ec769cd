// The tools' command-line reader: arguments read in order, each usage error in the tool's own words with
// the usage text and exit status 2, --help on stdout with 0, and the ranges' numbers and texts.
#include "cli_args.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

namespace {

using hadal::tools::CommandLine;
using hadal::tools::NumberRange;
using hadal::tools::OptionSyntax;
using hadal::tools::read_number;

constexpr const char* kUsage = "usage: tool [--time T] [--name N] [--fast] FILE...\n";

// What parse() returned and printed.
struct Parsed {
  std::optional<int> status;
  std::string out, err;
};

Parsed parse(const CommandLine& command_line, std::vector<std::string> args) {
  args.insert(args.begin(), "tool");
  std::vector<char*> argv;
  for (std::string& arg : args) argv.push_back(arg.data());
  testing::internal::CaptureStdout();
  testing::internal::CaptureStderr();
  Parsed parsed;
  parsed.status = command_line.parse(static_cast<int>(argv.size()), argv.data());
  parsed.out = testing::internal::GetCapturedStdout();
  parsed.err = testing::internal::GetCapturedStderr();
  return parsed;
}

// A tool with every kind of argument; what it read is kept in the fixture.
class CommandLineTest : public testing::Test {
 protected:
  CommandLine tool() {
    CommandLine command_line("tool", kUsage);
    command_line.number("--time", &time_, NumberRange::at_least(0.0))
        .text("--name", &name_)
        .flag("--fast", [this] { fast_ = true; })
        .positional([this](const std::string& arg) -> std::string {
          if (arg == "bad") return "FILE 'bad' is not allowed";
          files_.push_back(arg);
          return "";
        });
    return command_line;
  }

  double time_ = -1.0;
  std::string name_;
  bool fast_ = false;
  std::vector<std::string> files_;
};

TEST_F(CommandLineTest, ReadsOptionsFlagsAndPositionalArgumentsInOrder) {
  const Parsed parsed = parse(tool(), {"a", "--time", "2.5", "b", "--fast", "--name", "--x", "c"});
  EXPECT_EQ(parsed.status, std::nullopt);
  EXPECT_EQ(time_, 2.5);
  EXPECT_EQ(name_, "--x");  // a value is the next argument, whatever it looks like
  EXPECT_TRUE(fast_);
  EXPECT_EQ(files_, (std::vector<std::string>{"a", "b", "c"}));
  EXPECT_EQ(parsed.out + parsed.err, "");
}

TEST_F(CommandLineTest, HelpPrintsTheUsageOnStdoutAndStops) {
  for (const char* help : {"-h", "--help"}) {
    files_.clear();
    const Parsed parsed = parse(tool(), {"a", help, "b", "--bogus"});
    EXPECT_EQ(parsed.status, 0);
    EXPECT_EQ(parsed.out, kUsage);
    EXPECT_EQ(parsed.err, "");
    EXPECT_EQ(files_, std::vector<std::string>{"a"});
  }
  CommandLine with_footer = tool();
  with_footer.after_help([] { std::printf("footer\n"); });
  EXPECT_EQ(parse(with_footer, {"--help"}).out, std::string(kUsage) + "footer\n");
  EXPECT_EQ(parse(with_footer, {"--bogus"}).err, std::string("tool: unknown option '--bogus'\n") + kUsage);
}

TEST_F(CommandLineTest, TheFirstUsageErrorIsPrintedWithTheUsageAndExitsTwo) {
  const auto error = [&](std::vector<std::string> args) {
    const Parsed parsed = parse(tool(), std::move(args));
    EXPECT_EQ(parsed.status, 2);
    EXPECT_EQ(parsed.out, "");
    return parsed.err;
  };
  EXPECT_EQ(error({"--time"}), std::string("tool: --time needs a value\n") + kUsage);
  EXPECT_EQ(error({"--time", "-1"}), std::string("tool: --time must be a number >= 0 (got '-1')\n") + kUsage);
  EXPECT_EQ(error({"--bogus", "--time"}), std::string("tool: unknown option '--bogus'\n") + kUsage);
  EXPECT_EQ(error({"-x"}), std::string("tool: unknown option '-x'\n") + kUsage);
  EXPECT_EQ(error({"ok", "bad", "--bogus"}), std::string("tool: FILE 'bad' is not allowed\n") + kUsage);
}

TEST_F(CommandLineTest, AToolKeepsItsOwnWords) {
  CommandLine command_line = tool();
  command_line.error_prefix("error: ")
      .missing_value_words("option %s needs a value")
      .unknown_words("unknown argument %s")
      .option("--axis", [](const std::string&) { return std::string(); }, "--axis needs y or z");
  EXPECT_EQ(parse(command_line, {"--name"}).err, std::string("tool: error: option --name needs a value\n") + kUsage);
  EXPECT_EQ(parse(command_line, {"--axis"}).err, std::string("tool: error: --axis needs y or z\n") + kUsage);
  EXPECT_EQ(parse(command_line, {"--x"}).err, std::string("tool: error: unknown argument --x\n") + kUsage);
  testing::internal::CaptureStderr();
  EXPECT_EQ(command_line.usage_error("no FILE given"), 2);
  EXPECT_EQ(testing::internal::GetCapturedStderr(), std::string("tool: error: no FILE given\n") + kUsage);
}

TEST_F(CommandLineTest, WithoutPositionalArgumentsEveryOtherArgumentIsUnknown) {
  CommandLine command_line("tool", kUsage);
  command_line.unknown_words("unknown argument '%s'");
  const Parsed parsed = parse(command_line, {"file"});
  EXPECT_EQ(parsed.status, 2);
  EXPECT_EQ(parsed.err, std::string("tool: unknown argument 'file'\n") + kUsage);
}

TEST(OnePositionalTest, ASecondOneIsAUsageErrorNamingBoth) {
  std::string scenario;
  CommandLine command_line("tool", kUsage);
  command_line.one_positional(&scenario, "one scenario only (got '%s' and '%s')");
  EXPECT_EQ(parse(command_line, {"a.yaml"}).status, std::nullopt);
  EXPECT_EQ(scenario, "a.yaml");
  const Parsed parsed = parse(command_line, {"b.yaml"});  // a.yaml is still there: the second one
  EXPECT_EQ(parsed.status, 2);
  EXPECT_EQ(parsed.err, std::string("tool: one scenario only (got 'a.yaml' and 'b.yaml')\n") + kUsage);
  std::string file;
  CommandLine without_names("tool", kUsage);
  without_names.one_positional(&file, "more than one FILE");
  EXPECT_EQ(parse(without_names, {"x", "y"}).err, std::string("tool: more than one FILE\n") + kUsage);
}

TEST_F(CommandLineTest, OptionSyntaxDecidesWhatIsAnUnknownOption) {
  const auto reads_as_file = [&](OptionSyntax syntax, const std::string& arg) {
    files_.clear();
    CommandLine command_line = tool();
    command_line.option_syntax(syntax);
    return parse(command_line, {arg}).status == std::nullopt && files_ == std::vector<std::string>{arg};
  };
  EXPECT_FALSE(reads_as_file(OptionSyntax::kDash, "-x"));
  EXPECT_FALSE(reads_as_file(OptionSyntax::kDash, "-5"));
  EXPECT_FALSE(reads_as_file(OptionSyntax::kDash, "-"));
  EXPECT_TRUE(reads_as_file(OptionSyntax::kDash, ""));
  EXPECT_TRUE(reads_as_file(OptionSyntax::kDoubleDash, "-x"));
  EXPECT_FALSE(reads_as_file(OptionSyntax::kDoubleDash, "--x"));
  EXPECT_TRUE(reads_as_file(OptionSyntax::kDashNotNumber, "-12.5"));
  EXPECT_TRUE(reads_as_file(OptionSyntax::kDashNotNumber, "-.5"));
  EXPECT_TRUE(reads_as_file(OptionSyntax::kDashNotNumber, "-"));
  EXPECT_FALSE(reads_as_file(OptionSyntax::kDashNotNumber, "-x"));
}

TEST(NumberRangeTest, BoundsAreOpenOrClosedAsNamed) {
  const NumberRange left_open = NumberRange::left_open(0.0, 100.0);
  EXPECT_FALSE(left_open.contains(0.0));
  EXPECT_TRUE(left_open.contains(1e-300));
  EXPECT_TRUE(left_open.contains(100.0));
  EXPECT_FALSE(left_open.contains(std::nextafter(100.0, 200.0)));
  EXPECT_TRUE(NumberRange::closed(1.0, 2.0).contains(1.0));
  EXPECT_FALSE(NumberRange::closed(1.0, 2.0).contains(std::nextafter(1.0, 0.0)));
  EXPECT_TRUE(NumberRange::at_least(0.0).contains(0.0));
  EXPECT_FALSE(NumberRange::greater_than(0.0).contains(0.0));
  EXPECT_TRUE(NumberRange::greater_than(0.0).contains(1e300));
  EXPECT_TRUE(NumberRange::any().contains(-1e300));
}

TEST(NumberRangeTest, TextAsUsageErrorsShowIt) {
  EXPECT_EQ(NumberRange::left_open(0.0, 1e6).text(), "in (0, 1e6]");
  EXPECT_EQ(NumberRange::closed(0.1, 86400.0).text(), "in [0.1, 86400]");
  EXPECT_EQ(NumberRange::closed(-2.5e-7, 10900.0).text(), "in [-2.5e-7, 10900]");
  EXPECT_EQ(NumberRange::at_least(0.0).text(), ">= 0");
  EXPECT_EQ(NumberRange::greater_than(0.0).text(), "> 0");
  EXPECT_EQ(NumberRange::any().text(), "");
}

TEST(ReadNumberTest, AWholeFiniteNumberInRangeOrTheUsageError) {
  double x = 7.0;
  EXPECT_EQ(read_number("--hours", "100", NumberRange::left_open(0.0, 100.0), &x), "");
  EXPECT_EQ(x, 100.0);
  for (const char* bad : {"0", "100.5", "1x", "", "inf", "nan"}) {
    EXPECT_EQ(read_number("--hours", bad, NumberRange::left_open(0.0, 100.0), &x),
              std::string("--hours must be a number in (0, 100] (got '") + bad + "')");
    EXPECT_EQ(x, 100.0) << "unchanged on error";
  }
  EXPECT_EQ(read_number("--magnus", "x", NumberRange::any(), &x), "--magnus must be a number (got 'x')");
  EXPECT_EQ(read_number("--magnus", "-3e2", NumberRange::any(), &x), "");
  EXPECT_EQ(x, -300.0);
}

}  // namespace
