// Test support for the command-line tools (hadal-mesh-info, hadal-ocean, hadal-validate-*, ...): a
// strict minimal JSON reader, running a command with its stdout, stderr and exit code captured, and a
// GoogleTest fixture with a scratch directory. Header-only.
#pragma once

#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/wait.h>

#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace hadal::test {

// Minimal JSON reader (objects, arrays, numbers, strings without escapes beyond \" and \\,
// true/false/null): enough for the tools' JSON output, and strict, so malformed output fails.
struct Json {
  enum class Type { kNull, kBool, kNumber, kString, kArray, kObject } type = Type::kNull;
  bool boolean = false;
  double number = 0.0;
  std::string string;
  std::vector<Json> array;
  std::map<std::string, Json> object;

  const Json& operator[](const std::string& key) const {
    static const Json missing;
    const auto it = object.find(key);
    return it == object.end() ? missing : it->second;
  }
  const Json& operator[](std::size_t i) const { return array.at(i); }
};

class JsonParser {
 public:
  explicit JsonParser(const std::string& text) : s_(text) {}
  bool parse(Json& out) {
    if (!value(out)) return false;
    space();
    return i_ == s_.size();
  }

 private:
  void space() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_;
  }
  bool literal(const char* word) {
    const std::string w = word;
    if (s_.compare(i_, w.size(), w) != 0) return false;
    i_ += w.size();
    return true;
  }
  bool string(std::string& out) {
    if (s_[i_] != '"') return false;
    for (++i_; i_ < s_.size() && s_[i_] != '"'; ++i_) {
      if (s_[i_] == '\\' && i_ + 1 < s_.size()) ++i_;
      out += s_[i_];
    }
    return i_ < s_.size() && s_[i_++] == '"';
  }
  bool value(Json& out) {
    space();
    if (i_ >= s_.size()) return false;
    const char c = s_[i_];
    if (c == '{') {
      out.type = Json::Type::kObject;
      ++i_;
      space();
      if (s_[i_] == '}') return ++i_, true;
      for (;;) {
        space();
        std::string key;
        if (!string(key)) return false;
        space();
        if (s_[i_++] != ':') return false;
        if (!value(out.object[key])) return false;
        space();
        if (s_[i_] == ',') {
          ++i_;
          continue;
        }
        return s_[i_++] == '}';
      }
    }
    if (c == '[') {
      out.type = Json::Type::kArray;
      ++i_;
      space();
      if (s_[i_] == ']') return ++i_, true;
      for (;;) {
        out.array.emplace_back();
        if (!value(out.array.back())) return false;
        space();
        if (s_[i_] == ',') {
          ++i_;
          continue;
        }
        return s_[i_++] == ']';
      }
    }
    if (c == '"') {
      out.type = Json::Type::kString;
      return string(out.string);
    }
    if (literal("true")) return out.type = Json::Type::kBool, out.boolean = true, true;
    if (literal("false")) return out.type = Json::Type::kBool, true;
    if (literal("null")) return true;
    char* end = nullptr;
    out.number = std::strtod(s_.c_str() + i_, &end);
    if (end == s_.c_str() + i_) return false;
    out.type = Json::Type::kNumber;
    i_ = static_cast<std::size_t>(end - s_.c_str());
    return true;
  }
  const std::string& s_;
  std::size_t i_ = 0;
};

struct RunResult {
  int exit_code = -1;
  std::string out, err;
};

// Runs `command_line` through the shell; stderr goes through `stderr_file` (a scratch path).
inline RunResult run_command(const std::string& command_line, const std::string& stderr_file) {
  RunResult r;
  FILE* pipe = popen((command_line + " 2>" + stderr_file).c_str(), "r");
  if (!pipe) return r;
  char buffer[4096];
  std::size_t n;
  while ((n = std::fread(buffer, 1, sizeof(buffer), pipe)) > 0) r.out.append(buffer, n);
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream err(stderr_file);
  std::stringstream text;
  text << err.rdbuf();
  r.err = text.str();
  return r;
}

// Fixture for tests of a command-line tool: a fresh scratch directory dir_ per test (removed after
// it), run() of a command line with stderr captured there, and parse() of a JSON text.
class CliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string pattern = (std::filesystem::temp_directory_path() / "hadal_cli_test_XXXXXX").string();
    ASSERT_NE(mkdtemp(pattern.data()), nullptr);
    dir_ = pattern;
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  RunResult run(const std::string& command_line) const {
    return run_command(command_line, dir_ + "/stderr.txt");
  }
  static Json parse(const std::string& text) {
    Json json;
    EXPECT_TRUE(JsonParser(text).parse(json)) << text;
    return json;
  }

  std::string dir_;
};

}  // namespace hadal::test
