// The documentation stays true: every option of `render --help-all` is in docs/guide.md's table and
// back, every option the guide names is one the program knows, the README's quick start runs, and
// the user-facing text cites no issue numbers.
#include "e2e/cli_runner.h"

#include <gtest/gtest.h>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace bp::test {
namespace {

namespace fs = std::filesystem;

std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::string join(const std::set<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : " ") + n;
  return out;
}

// The options a help text documents: each option line starts with two spaces, then the option
// ("-h, --help" names --help).
std::set<std::string> help_options(const std::string& help) {
  static const std::regex option_line(R"(^  (?:-h, )?(--[a-z][a-z0-9-]*))");
  std::set<std::string> options;
  std::smatch m;
  for (const std::string& line : lines_of(help))
    if (std::regex_search(line, m, option_line)) options.insert(m[1]);
  return options;
}

// The lines of a Markdown file's section, from its heading to the next heading of its level or above.
std::vector<std::string> section(const std::string& markdown, const std::string& heading) {
  std::vector<std::string> out;
  bool inside = false;
  const std::size_t level = heading.find(' ');
  for (const std::string& line : lines_of(markdown)) {
    if (line == heading) {
      inside = true;
      continue;
    }
    if (inside && line.rfind(std::string(level, '#') + " ", 0) == 0) break;
    if (inside && line.rfind(std::string(level - 1, '#') + " ", 0) == 0 && level > 1) break;
    if (inside) out.push_back(line);
  }
  return out;
}

// The options of the guide's table "Every option": the `--name` tokens of each row's first cell.
std::set<std::string> guide_table_options(const std::string& guide) {
  static const std::regex token(R"(--[a-z][a-z0-9-]*)");
  std::set<std::string> options;
  for (const std::string& line : section(guide, "## Every option")) {
    if (line.rfind("| `", 0) != 0) continue;
    const std::string first_cell = line.substr(1, line.find('|', 1) - 1);
    for (std::sregex_iterator it(first_cell.begin(), first_cell.end(), token), end; it != end; ++it)
      options.insert(it->str());
  }
  return options;
}

// Every `--name` the text mentions (an option's value joined with '=' included).
std::set<std::string> mentioned_options(const std::string& text) {
  static const std::regex token(R"((?:^|[^a-zA-Z0-9_-])(--[a-z][a-z0-9-]*))");
  std::set<std::string> options;
  for (std::sregex_iterator it(text.begin(), text.end(), token), end; it != end; ++it) options.insert((*it)[1]);
  return options;
}

const fs::path kSource = BP_SOURCE_DIR;

TEST(Docs, EveryRenderOptionIsInTheGuideAndEveryGuideOptionInTheHelp) {
  const CliResult help = run_cli("render --help"), help_all = run_cli("render --help-all");
  ASSERT_EQ(help.exit_code, 0) << help.output;
  ASSERT_EQ(help_all.exit_code, 0) << help_all.output;
  const std::set<std::string> everyday = help_options(help.output), all = help_options(help_all.output);
  ASSERT_GT(all.size(), 40u) << help_all.output;  // the parse above found the option lines

  for (const std::string& o : everyday) EXPECT_TRUE(all.count(o)) << o << " is in --help but not in --help-all";

  const std::string guide = read_text(kSource / "docs/guide.md");
  const std::set<std::string> table = guide_table_options(guide);
  for (const std::string& o : all)
    EXPECT_TRUE(table.count(o)) << o << " is in `render --help-all` but not in docs/guide.md's table \"Every option\"";
  for (const std::string& o : table)
    EXPECT_TRUE(all.count(o)) << o << " is in docs/guide.md's table \"Every option\" but not in `render --help-all`";

  // Options of other commands and programs that the guide may name.
  const std::set<std::string> others = {"--version", "--layer", "--json",  // bundlepath --version, compare
                                        "--oversubscribe", "--allow-run-as-root", "--mca",  // mpirun
                                        "--oidn"};  // scripts/setup.sh
  for (const std::string& o : mentioned_options(guide))
    EXPECT_TRUE(all.count(o) || others.count(o)) << "docs/guide.md names " << o << ", which `render --help-all` does not";

  // And the parser knows each documented option (a missing value or a bad scene, never "unknown option").
  for (const std::string& o : all) {
    const CliResult r = run_cli("render /nonexistent.gltf " + o);
    EXPECT_EQ(r.output.find("unknown option"), std::string::npos) << o << "\n" << r.output;
  }
  SCOPED_TRACE("--help: " + join(everyday));
}

TEST(Docs, NoIssueNumbersInTheReadmeTheGuideOrTheHelp) {
  static const std::regex issue(R"((^|[^&\w/])#[0-9]+\b|[Ii]ssue [0-9#])");
  const CliResult help_all = run_cli("render --help-all");
  const std::pair<std::string, std::string> texts[] = {{"README.md", read_text(kSource / "README.md")},
                                                       {"docs/guide.md", read_text(kSource / "docs/guide.md")},
                                                       {"render --help-all", help_all.output},
                                                       {"--help", run_cli("--help").output}};
  for (const auto& [name, text] : texts) {
    ASSERT_FALSE(text.empty()) << name;
    for (const std::string& line : lines_of(text))
      EXPECT_FALSE(std::regex_search(line, issue)) << name << ": " << line;
  }
  EXPECT_LE(lines_of(texts[0].second).size(), 220u) << "the README is the front door: keep it short";
}

// Runs each command of the README's "Quick start" block, in a fresh folder beside a link to scenes/,
// every render at 32x32 pixels and for at most a second.
TEST(Docs, ReadmeQuickStartRuns) {
  std::vector<std::string> commands;
  bool in_block = false;
  std::string pending;
  for (const std::string& line : section(read_text(kSource / "README.md"), "## Quick start")) {
    if (line.rfind("```", 0) == 0) {
      if (in_block) break;
      in_block = true;
      continue;
    }
    if (!in_block) continue;
    std::string text = pending + line;
    pending.clear();
    if (!text.empty() && text.back() == '\\') {
      pending = text.substr(0, text.size() - 1);
      continue;
    }
    if (const std::size_t hash = text.find(" #"); hash != std::string::npos) text.erase(hash);
    while (!text.empty() && text.back() == ' ') text.pop_back();
    if (!text.empty()) commands.push_back(text);
  }
  ASSERT_GE(commands.size(), 3u) << "no quick start block found in README.md";
  EXPECT_LE(commands.size(), 8u);

  const std::string dir = fresh_dir("readme_quick_start");
  fs::create_directory_symlink(kSource / "scenes", fs::path(dir) / "scenes");
  const std::string prefix = "build/bundlepath ";
  for (const std::string& command : commands) {
    ASSERT_EQ(command.rfind(prefix, 0), 0u) << "a quick-start line that is not a bundlepath command: " << command;
    std::string args = command.substr(prefix.size());
    if (args.rfind("render ", 0) == 0) args += " --width 32 --height 32 --time 1";
    const CliResult r = run_shell("cd '" + dir + "' && '" + BP_BINARY + "' " + args);
    EXPECT_EQ(r.exit_code, 0) << command << "\n" << r.output;
  }
}

}  // namespace
}  // namespace bp::test
