// The README's front page keeps its promises: at most 200 lines, a results table of at most 8 rows,
// and every ratio its text states ("5× below") is the ratio of two figures in one row of that table,
// to the digits stated; every relMSE figure in the comparison's text is one of the table's.
#include "e2e/doc_text.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace bp::test {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> readme_lines() { return lines_of(read_text(fs::path(BP_SOURCE_DIR) / "README.md")); }

constexpr const char* kTableSection = "## How it compares";

// The table's rows (header and separator dropped), each as its renderers' cells' first numbers: not
// the first cell (the scene, its size and time) nor the reference's own noise.
std::vector<std::vector<double>> table_rows(const std::vector<std::string>& lines) {
  std::vector<std::vector<double>> rows;
  bool in_section = false;
  std::vector<bool> renderer_column;  // from the header
  static const std::regex number(R"((\d+(?:\.\d+)?))");
  for (const std::string& line : lines) {
    if (line.rfind("## ", 0) == 0) in_section = line == kTableSection;
    if (!in_section || line.rfind("|", 0) != 0) continue;
    std::vector<std::string> cells;
    std::stringstream in(line.substr(1));
    for (std::string cell; std::getline(in, cell, '|');) cells.push_back(cell);
    if (renderer_column.empty()) {
      for (std::size_t c = 0; c < cells.size(); ++c)
        renderer_column.push_back(c > 0 && cells[c].find("reference") == std::string::npos);
      continue;
    }
    if (line.rfind("|---", 0) == 0) continue;
    std::vector<double> figures;
    for (std::size_t c = 0; c < cells.size() && c < renderer_column.size(); ++c) {
      std::smatch m;
      if (renderer_column[c] && std::regex_search(cells[c], m, number)) figures.push_back(std::stod(m[1]));
    }
    rows.push_back(figures);
  }
  return rows;
}

// The README's prose: no table rows, no code blocks.
std::vector<std::string> prose(const std::vector<std::string>& lines, bool table_section_only) {
  std::vector<std::string> out;
  bool in_code = false, in_section = false;
  for (const std::string& line : lines) {
    if (line.rfind("```", 0) == 0) in_code = !in_code;
    if (line.rfind("## ", 0) == 0) in_section = line == kTableSection;
    if (in_code || line.rfind("|", 0) == 0 || (table_section_only && !in_section)) continue;
    out.push_back(line);
  }
  return out;
}

// "5×" or "1.6×" (not "640×360"), joined over line ends.
struct Ratio {
  double value;
  int decimals;
  std::string text;
};
std::vector<Ratio> stated_ratios(const std::vector<std::string>& text) {
  std::string all;
  for (const std::string& line : text) all += line + " ";
  static const std::regex ratio("(\\d+)(?:\\.(\\d+))?\u00D7(?![0-9])");  // × in UTF-8
  std::vector<Ratio> out;
  for (auto it = std::sregex_iterator(all.begin(), all.end(), ratio); it != std::sregex_iterator(); ++it) {
    const std::smatch& m = *it;
    out.push_back({std::stod(m.str(1) + (m[2].matched ? "." + m.str(2) : "")), m[2].matched ? int(m.length(2)) : 0,
                   m.str(0)});
  }
  return out;
}

bool in_some_row(const std::vector<std::vector<double>>& rows, const Ratio& r) {
  const double tolerance = 0.5 * std::pow(10.0, -r.decimals) + 1e-9;
  for (const std::vector<double>& row : rows)
    for (std::size_t a = 0; a < row.size(); ++a)
      for (std::size_t b = 0; b < row.size(); ++b)
        if (a != b && row[b] > 0.0 && std::abs(row[a] / row[b] - r.value) <= tolerance) return true;
  return false;
}

TEST(Readme, IsShortWithATableOfAtMostEightRows) {
  const std::vector<std::string> lines = readme_lines();
  ASSERT_FALSE(lines.empty());
  EXPECT_LE(lines.size(), 200u) << "the README is the front door: keep it short";
  const std::vector<std::vector<double>> rows = table_rows(lines);
  EXPECT_GE(rows.size(), 1u) << "no table under '" << kTableSection << "'";
  EXPECT_LE(rows.size(), 8u) << "the full tables belong in docs/results.md";
}

TEST(Readme, EveryRatioInItsTextIsOneOfTheTables) {
  const std::vector<std::string> lines = readme_lines();
  const std::vector<std::vector<double>> rows = table_rows(lines);
  const std::vector<Ratio> ratios = stated_ratios(prose(lines, false));
  EXPECT_GE(ratios.size(), 1u) << "the test reads no ratio: has the README's wording changed?";
  for (const Ratio& r : ratios)
    EXPECT_TRUE(in_some_row(rows, r)) << "'" << r.text << "' is not the ratio of two figures in one row of the table";
}

TEST(Readme, EveryRelMseInTheComparisonsTextIsInTheTable) {
  const std::vector<std::string> lines = readme_lines();
  std::vector<double> figures;
  for (const std::vector<double>& row : table_rows(lines)) figures.insert(figures.end(), row.begin(), row.end());
  std::string text;
  for (const std::string& line : prose(lines, true)) text += line + " ";
  static const std::regex small(R"(\b(0\.0\d+)\b)");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), small); it != std::sregex_iterator(); ++it) {
    const double value = std::stod(it->str(1));
    bool found = false;
    for (double f : figures) found = found || std::abs(f - value) <= 1e-12;
    EXPECT_TRUE(found) << it->str(1) << " is in the comparison's text but not in its table";
  }
}

}  // namespace
}  // namespace bp::test
