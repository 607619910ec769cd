// Shared by Hadal's command-line tools (hadal-ocean, hadal-render, hadal-validate-*, ...): reading the
// arguments in order — `--option value`, flags, positional arguments, -h / --help — and the usage text
// printed with a usage error (exit status 2) or for --help (on stdout, exit status 0). Header-only.
//
//   CommandLine command_line("hadal-ocean", kUsage);
//   command_line.number("--time", &time, NumberRange::at_least(0.0))
//       .one_positional(&scenario, "more than one scenario file");
//   if (const std::optional<int> status = command_line.parse(argc, argv)) return *status;
//
// Each tool keeps the words its usage errors have always had (error_prefix, missing_value_words,
// unknown_words, option_syntax): scripts and tests read them.
#pragma once

#include <cctype>
#include <cmath>
#include <cstdio>
#include <functional>
#include <initializer_list>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "json_number.h"
#include "parse_number.h"

namespace hadal::tools {

// An interval of the real line that an option's number must lie in; text() is how usage errors show it.
class NumberRange {
 public:
  static NumberRange any() { return {}; }
  static NumberRange at_least(double min) { return {min, kInf, false, false}; }
  static NumberRange greater_than(double min) { return {min, kInf, true, false}; }
  static NumberRange left_open(double min, double max) { return {min, max, true, false}; }  // (min, max]
  static NumberRange closed(double min, double max) { return {min, max, false, false}; }   // [min, max]

  bool contains(double x) const {
    return (min_open_ ? x > min_ : x >= min_) && (max_open_ ? x < max_ : x <= max_);
  }
  // "in (0, 100]", ">= 0", "> 0"; "" for any number.
  std::string text() const {
    if (max_ == kInf) {
      if (min_ == -kInf) return "";
      return (min_open_ ? "> " : ">= ") + bound(min_);
    }
    return std::string("in ") + (min_open_ ? "(" : "[") + bound(min_) + ", " + bound(max_) + (max_open_ ? ")" : "]");
  }

 private:
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  NumberRange() = default;
  NumberRange(double min, double max, bool min_open, bool max_open)
      : min_(min), max_(max), min_open_(min_open), max_open_(max_open) {}

  // As a person writes it: 0.1, 86400, 1e6 (not %g's 1e+06).
  static std::string bound(double x) {
    std::string text = json_number(x);
    const std::size_t e = text.find('e');
    if (e == std::string::npos) return text;
    std::string exponent = text.substr(e + 1);
    const bool negative = exponent[0] == '-';
    exponent.erase(0, exponent.find_first_not_of("+-0"));
    return text.substr(0, e + 1) + (negative ? "-" : "") + exponent;
  }

  double min_ = -kInf, max_ = kInf;
  bool min_open_ = false, max_open_ = false;
};

// The whole of `text` as a number in `range` into *out: "" when it is one, else the usage error
// "NAME must be a number RANGE (got 'TEXT')" (*out unchanged).
inline std::string read_number(const std::string& name, const std::string& text, const NumberRange& range,
                               double* out) {
  double x = 0.0;
  if (parse_number(text, &x) && range.contains(x)) {
    *out = x;
    return "";
  }
  const std::string range_text = range.text();
  return name + " must be a number" + (range_text.empty() ? "" : " " + range_text) + " (got '" + text + "')";
}

// Which arguments that name no declared option are unknown options rather than positional arguments.
enum class OptionSyntax {
  kDash,            // "-x", "--x"
  kDoubleDash,      // "--x" only ("-x" is positional)
  kDashNotNumber,   // as kDash, but "-12.5" and "-.5" are negative numbers, and "-" is positional
};

// One tool's command line: declare what it takes, then parse(argc, argv). Arguments are read in order;
// the first problem is reported as "TOOL: [ERROR_PREFIX]MESSAGE" followed by the usage text.
class CommandLine {
 public:
  // Reads an option's value (or a positional argument): "" when it is right, else the usage error.
  using ReadText = std::function<std::string(const std::string& text)>;

  CommandLine(std::string tool, std::string usage) : tool_(std::move(tool)), usage_(std::move(usage)) {}

  // --name VALUE, read by `read`. missing_value_message, when given, replaces the "needs a value" words for
  // this option.
  CommandLine& option(std::string name, ReadText read, std::string missing_value_message = "") {
    options_.push_back({std::move(name), std::move(read), {}, std::move(missing_value_message)});
    return *this;
  }
  // --name VALUE, kept as it is into *out.
  CommandLine& text(std::string name, std::string* out) {
    return option(std::move(name), [out](const std::string& value) {
      *out = value;
      return std::string();
    });
  }
  // --name NUMBER, a number in `range` (read_number's usage error otherwise).
  CommandLine& number(std::string name, double* out, NumberRange range) {
    return option(name, [name, out, range](const std::string& value) { return read_number(name, value, range, out); });
  }
  // --name, no value.
  CommandLine& flag(std::string name, std::function<void()> on_flag) {
    options_.push_back({std::move(name), {}, std::move(on_flag), ""});
    return *this;
  }
  // The arguments that are not options, in order; without this, each of them is an unknown argument.
  CommandLine& positional(ReadText read) {
    read_positional_ = std::move(read);
    return *this;
  }
  // The one argument that is not an option, into *out (empty until then); a second one is the usage error
  // `too_many_words`, whose "%s"s stand for the first and the second.
  CommandLine& one_positional(std::string* out, std::string too_many_words) {
    return positional([out, too_many_words](const std::string& arg) {
      if (!out->empty()) return fill(too_many_words, {*out, arg});
      *out = arg;
      return std::string();
    });
  }
  // Printed after the usage text on --help only.
  CommandLine& after_help(std::function<void()> print) {
    after_help_ = std::move(print);
    return *this;
  }

  // The words of the tool's usage errors; "%s" stands for the option or argument.
  CommandLine& error_prefix(std::string prefix) {  // after "TOOL: ", e.g. "error: "
    error_prefix_ = std::move(prefix);
    return *this;
  }
  CommandLine& missing_value_words(std::string format) {  // default "%s needs a value"
    missing_value_ = std::move(format);
    return *this;
  }
  CommandLine& unknown_words(std::string format) {  // default "unknown option '%s'"
    unknown_ = std::move(format);
    return *this;
  }
  CommandLine& option_syntax(OptionSyntax syntax) {  // default kDash
    syntax_ = syntax;
    return *this;
  }

  // Reads argv[first..argc): nullopt to go on, or the exit status main returns: 0 after printing the
  // usage text for -h / --help, 2 after a usage error.
  std::optional<int> parse(int argc, char** argv, int first = 1) const {
    for (int i = first; i < argc; ++i) {
      const std::string arg = argv[i];
      if (arg == "-h" || arg == "--help") {
        std::fputs(usage_.c_str(), stdout);
        if (after_help_) after_help_();
        return 0;
      }
      if (const Option* option = find(arg)) {
        if (option->on_flag) {
          option->on_flag();
          continue;
        }
        if (i + 1 >= argc) {
          return usage_error(option->missing_value_message.empty() ? fill(missing_value_, {arg})
                                                                   : option->missing_value_message);
        }
        if (const std::string error = option->read(argv[++i]); !error.empty()) return usage_error(error);
        continue;
      }
      if (!read_positional_ || is_option(arg)) return usage_error(fill(unknown_, {arg}));
      if (const std::string error = read_positional_(arg); !error.empty()) return usage_error(error);
    }
    return std::nullopt;
  }

  // Prints "TOOL: [ERROR_PREFIX]MESSAGE" and the usage text on stderr; returns the exit status 2.
  int usage_error(const std::string& message) const {
    std::fprintf(stderr, "%s: %s%s\n%s", tool_.c_str(), error_prefix_.c_str(), message.c_str(), usage_.c_str());
    return 2;
  }

 private:
  struct Option {
    std::string name;
    ReadText read;                 // options with a value
    std::function<void()> on_flag;  // flags
    std::string missing_value_message;
  };

  const Option* find(const std::string& arg) const {
    for (const Option& option : options_) {
      if (option.name == arg) return &option;
    }
    return nullptr;
  }

  bool is_option(const std::string& arg) const {
    switch (syntax_) {
      case OptionSyntax::kDash:
        return !arg.empty() && arg[0] == '-';
      case OptionSyntax::kDoubleDash:
        return arg.rfind("--", 0) == 0;
      case OptionSyntax::kDashNotNumber:
        return arg.size() >= 2 && arg[0] == '-' &&
               !(std::isdigit(static_cast<unsigned char>(arg[1])) || arg[1] == '.');
    }
    return true;
  }

  // `format` with its "%s"s replaced by `args` in order.
  static std::string fill(const std::string& format, std::initializer_list<std::string> args) {
    std::string text = format;
    std::size_t from = 0;
    for (const std::string& arg : args) {
      const std::size_t at = text.find("%s", from);
      if (at == std::string::npos) break;
      text.replace(at, 2, arg);
      from = at + arg.size();
    }
    return text;
  }

  std::string tool_, usage_;
  std::vector<Option> options_;
  ReadText read_positional_;
  std::function<void()> after_help_;
  std::string error_prefix_;
  std::string missing_value_ = "%s needs a value";
  std::string unknown_ = "unknown option '%s'";
  OptionSyntax syntax_ = OptionSyntax::kDash;
};

}  // namespace hadal::tools
