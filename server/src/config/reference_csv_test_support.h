// Reading the published tables under docs/reference/ in tests, so a preset's test recomputes it from the
// table it cites (config/preset.h): rows by their first column, and a cell's figures.
#pragma once

#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace hadal::reference_tables {

// The CSV's fields, quoted fields kept whole (without their quotes).
inline std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (char c : line) {
    if (c == '"') {
      quoted = !quoted;
    } else if (c == ',' && !quoted) {
      fields.emplace_back();
    } else {
      fields.back() += c;
    }
  }
  return fields;
}

// The rows of a CSV file by their first column, each the other columns; lines starting with '#' are
// comments, and the first other line is the header, which must start with `header`. A row with more than
// `columns` fields has an unquoted comma in its label (a published table's "Clayey soil (Thailand, 38%
// ..."): whatever comes before the last columns - 1 fields is the label.
inline std::map<std::string, std::vector<std::string>> csv_rows(const std::string& path, const std::string& header,
                                                                std::size_t columns) {
  std::map<std::string, std::vector<std::string>> rows;
  std::ifstream in(path);
  EXPECT_TRUE(in) << path;
  std::string line;
  bool at_header = true;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (at_header) {
      EXPECT_EQ(line.rfind(header, 0), 0u) << path << ": header " << line;
      at_header = false;
      continue;
    }
    std::vector<std::string> fields = split_csv(line);
    while (fields.size() > columns) {
      fields[0] += "," + fields[1];
      fields.erase(fields.begin() + 1);
    }
    rows[fields[0]] = std::vector<std::string>(fields.begin() + 1, fields.end());
  }
  return rows;
}

// A cell's figures: its leading number ("1.72 (unverified)" is 1.72, "~614" is 614); a range
// "0.010-0.025" gives both ends; none for an empty or wordy cell ("none listed").
inline std::vector<double> cell_figures(std::string text) {
  if (!text.empty() && text[0] == '~') text.erase(0, 1);
  std::vector<double> out;
  std::istringstream in(text);
  double value = 0.0;
  if (in >> value) out.push_back(value);
  if (in.peek() == '-' && in.get() && in >> value) out.push_back(value);
  return out;
}

}  // namespace hadal::reference_tables
