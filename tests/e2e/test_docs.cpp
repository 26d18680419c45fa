// The documentation stays true: every option of `render --help-all` is in docs/guide.md's table and
// back, every option the guide names is one the program knows, the README's quick start runs, the
// user-facing text cites no issue numbers nor names from the code, the results book opens with a
// summary and a contents list of every section, and every link between the documents lands.
#include "e2e/cli_runner.h"
#include "e2e/doc_text.h"

#include <gtest/gtest.h>
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace bp::test {
namespace {

namespace fs = std::filesystem;

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

// ---- Markdown headings and links, as GitHub renders them ----

// UTF-8: the code point at text[i] (its byte count in `length`); a stray byte reads as itself.
char32_t code_point_at(const std::string& text, std::size_t i, std::size_t& length) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char b = byte(i);
  length = b < 0x80 ? 1 : b >> 5 == 0x6 ? 2 : b >> 4 == 0xE ? 3 : b >> 3 == 0x1E ? 4 : 1;
  if (i + length > text.size()) length = 1;
  if (length == 1) return b;
  char32_t cp = b & (0x7F >> length);
  for (std::size_t k = 1; k < length; ++k) cp = (cp << 6) | (byte(i + k) & 0x3F);
  return cp;
}

void append_utf8(std::string& out, char32_t cp) {
  if (cp < 0x80) {
    out += static_cast<char>(cp);
  } else if (cp < 0x800) {
    out += static_cast<char>(0xC0 | (cp >> 6));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  } else if (cp < 0x10000) {
    out += static_cast<char>(0xE0 | (cp >> 12));
    out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  } else {
    out += static_cast<char>(0xF0 | (cp >> 18));
    out += static_cast<char>(0x80 | ((cp >> 12) & 0x3F));
    out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  }
}

// The rendered text of a heading's Markdown: a link or image is its text, an HTML tag nothing.
std::string heading_text(const std::string& markdown) {
  static const std::regex link(R"(!?\[([^\]]*)\]\([^)]*\))"), tag(R"(<[^>]*>)");
  return std::regex_replace(std::regex_replace(markdown, link, "$1"), tag, "");
}

// GitHub's anchor for a heading (github-slugger): lower case; letters, digits, '_' and '-' kept,
// spaces turned into '-', everything else dropped (backticks, '(', ':', '?', '.', '/', '×', '–').
// Outside ASCII, letters are kept (Latin-1, Greek, Cyrillic upper case lowered) and the blocks of
// punctuation and symbols are dropped: Latin-1's symbols, U+2000-U+2BFF (dashes, quotes,
// super- and subscripts, arrows, mathematical operators), U+3000-U+303F.
std::string github_slug(const std::string& heading) {
  const std::string text = heading_text(heading);
  std::string slug;
  for (std::size_t i = 0, length = 1; i < text.size(); i += length) {
    char32_t cp = code_point_at(text, i, length);
    if (cp < 0x80) {
      const char c = static_cast<char>(cp);
      if (std::isalnum(static_cast<unsigned char>(c))) slug += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      else if (c == ' ') slug += '-';
      else if (c == '-' || c == '_') slug += c;
      continue;
    }
    const bool symbol = (cp >= 0x80 && cp <= 0xBF && cp != 0xAA && cp != 0xB5 && cp != 0xBA) || cp == 0xD7 ||
                        cp == 0xF7 || (cp >= 0x2000 && cp <= 0x2BFF) || (cp >= 0x3000 && cp <= 0x303F);
    if (symbol) continue;
    if ((cp >= 0xC0 && cp <= 0xDE) || (cp >= 0x391 && cp <= 0x3A9) || (cp >= 0x410 && cp <= 0x42F)) cp += 0x20;
    else if (cp >= 0x400 && cp <= 0x40F) cp += 0x50;
    append_utf8(slug, cp);
  }
  return slug;
}

// A Markdown line's place: inside a fenced code block or not. Feed it every line in order.
class FenceTracker {
 public:
  // True where the line is Markdown (not a fence line nor inside a fenced block).
  bool markdown(const std::string& line) {
    static const std::regex fence(R"(^ {0,3}(```+|~~~+))");
    std::smatch m;
    if (std::regex_search(line, m, fence)) {
      const std::string marker = m[1];
      if (open_.empty()) open_ = marker;
      else if (marker[0] == open_[0] && marker.size() >= open_.size()) open_.clear();
      return false;
    }
    return open_.empty();
  }

 private:
  std::string open_;
};

// The headings' anchors of a Markdown file, as GitHub makes them (a repeated one gets -1, -2, ...),
// and the anchors of explicit `<a name="...">` / `id="..."` tags.
std::set<std::string> markdown_anchors(const std::string& markdown) {
  static const std::regex heading(R"(^ {0,3}#{1,6}[ \t]+(.*?)(?:[ \t]+#+)?[ \t]*$)");
  static const std::regex html_anchor(R"(<a\s+(?:name|id)="([^"]+)\")");
  std::set<std::string> anchors;
  std::map<std::string, int> seen;
  FenceTracker fences;
  for (const std::string& line : lines_of(markdown)) {
    if (!fences.markdown(line)) continue;
    std::smatch m;
    if (std::regex_search(line, m, heading)) {
      const std::string slug = github_slug(m[1]);
      const int n = seen[slug]++;
      anchors.insert(n == 0 ? slug : slug + "-" + std::to_string(n));
    }
    for (std::sregex_iterator it(line.begin(), line.end(), html_anchor), end; it != end; ++it)
      anchors.insert((*it)[1]);
  }
  return anchors;
}

struct MarkdownLink {
  int line;            // 1-based
  std::string target;  // as written: "docs/guide.md#every-option", "#scenes", "../bench/README.md"
};

// The link and image targets of a Markdown text outside code: inline `[text](target "title")` and
// reference definitions `[label]: target`.
std::vector<MarkdownLink> markdown_links(const std::string& markdown) {
  static const std::regex code_span(R"(`+[^`]*`+)");
  static const std::regex inline_link(R"(\]\(\s*<?([^)\s>]*)>?(?:\s+"[^"]*")?\s*\))");
  static const std::regex definition(R"(^ {0,3}\[[^\]]+\]:\s+<?([^\s>]+)>?)");
  std::vector<MarkdownLink> links;
  FenceTracker fences;
  int number = 0;
  for (const std::string& raw : lines_of(markdown)) {
    ++number;
    if (!fences.markdown(raw)) continue;
    const std::string line = std::regex_replace(raw, code_span, "");
    for (std::sregex_iterator it(line.begin(), line.end(), inline_link), end; it != end; ++it)
      links.push_back({number, (*it)[1]});
    std::smatch m;
    if (std::regex_search(line, m, definition)) links.push_back({number, m[1]});
  }
  return links;
}

std::string percent_decoded(const std::string& text) {
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '%' && i + 2 < text.size() && std::isxdigit(static_cast<unsigned char>(text[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(text[i + 2]))) {
      out += static_cast<char>(std::stoi(text.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += text[i];
    }
  }
  return out;
}

// What is wrong with each internal link of a Markdown file (relative to the source tree): a file
// that does not exist, or an anchor that no heading of its Markdown file makes. Links with a
// scheme (https:, mailto:) are not followed.
std::vector<std::string> broken_links(const fs::path& source, const std::string& file) {
  static const std::regex scheme(R"(^[A-Za-z][A-Za-z0-9+.-]*:)");
  std::vector<std::string> broken;
  std::map<fs::path, std::set<std::string>> anchors_of;
  const auto anchors = [&](const fs::path& path) -> const std::set<std::string>& {
    auto it = anchors_of.find(path);
    if (it == anchors_of.end()) it = anchors_of.emplace(path, markdown_anchors(read_text(path))).first;
    return it->second;
  };
  const fs::path self = (source / file).lexically_normal();
  for (const MarkdownLink& link : markdown_links(read_text(self))) {
    const std::string where = file + ":" + std::to_string(link.line) + ": (" + link.target + ") ";
    if (std::regex_search(link.target, scheme)) continue;
    if (link.target.empty()) {
      broken.push_back(where + "an empty link");
      continue;
    }
    const std::size_t hash = link.target.find('#');
    const std::string path = percent_decoded(link.target.substr(0, hash));
    const std::string anchor = hash == std::string::npos ? "" : percent_decoded(link.target.substr(hash + 1));
    const fs::path target = path.empty() ? self : (self.parent_path() / path).lexically_normal();
    if (!fs::exists(target)) {
      broken.push_back(where + "no file " + target.lexically_relative(source).string());
      continue;
    }
    if (hash != std::string::npos && target.extension() == ".md" && !anchors(target).count(anchor))
      broken.push_back(where + "no heading of " + target.lexically_relative(source).string() + " has the anchor #" +
                       anchor);
  }
  return broken;
}

// README.md and every docs/*.md, relative to the source tree.
std::vector<std::string> user_documents(const fs::path& source) {
  std::vector<std::string> files = {"README.md"};
  for (const auto& entry : fs::directory_iterator(source / "docs"))
    if (entry.path().extension() == ".md") files.push_back("docs/" + entry.path().filename().string());
  std::sort(files.begin() + 1, files.end());
  return files;
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
                                        "--oidn",                                            // scripts/setup.sh
                                        "--install", "--prefix"};                            // cmake --install
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
}

TEST(Docs, GithubSlugsFollowGithubsRules) {
  EXPECT_EQ(github_slug("Scenes from Blender (`bench/blender_compare.sh`)"), "scenes-from-blender-benchblender_comparesh");
  EXPECT_EQ(github_slug("Who takes the eye vertex's direct light (`--eye-direct`)"),
            "who-takes-the-eye-vertexs-direct-light---eye-direct");
  EXPECT_EQ(github_slug("Ray-bundle level on the house: bias or noise? (`bench/rb_bias.sh`)"),
            "ray-bundle-level-on-the-house-bias-or-noise-benchrb_biassh");
  EXPECT_EQ(github_slug("3. The pdf state: q and r (eq. 8–10)"), "3-the-pdf-state-q-and-r-eq-810");
  EXPECT_EQ(github_slug("The house at 1280×720, **30 s**"), "the-house-at-1280720-30-s");
  EXPECT_EQ(github_slug("Résumé of [the guide](guide.md#scenes)"), "résumé-of-the-guide");
  EXPECT_EQ(github_slug("ÉTÉ Δ"), "été-δ");

  const std::set<std::string> anchors = markdown_anchors("# A\n## A\n```\n## B\n```\n### A ##\n#nope\n## C\n");
  EXPECT_EQ(anchors, (std::set<std::string>{"a", "a-1", "a-2", "c"}));

  const std::vector<MarkdownLink> links =
      markdown_links("[x](a.md#b) and `[y](code.md)` and ![z](pic.png \"title\")\n```\n[w](fenced.md)\n```\n[r]: ref.md\n");
  ASSERT_EQ(links.size(), 3u);
  EXPECT_EQ(links[0].target, "a.md#b");
  EXPECT_EQ(links[1].target, "pic.png");
  EXPECT_EQ(links[2].target, "ref.md");
  EXPECT_EQ(links[2].line, 5);
}

// The results book opens with a one-screen summary, then a contents list that links every `## `
// section (and nothing else), all before the first section.
TEST(Docs, ResultsBookOpensWithASummaryThenContentsOfEverySection) {
  const std::vector<std::string> lines = lines_of(read_text(kSource / "docs/results.md"));
  ASSERT_FALSE(lines.empty()) << "docs/results.md";

  std::vector<std::string> sections;
  std::size_t first_section = lines.size();
  FenceTracker fences;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (!fences.markdown(lines[i]) || lines[i].rfind("## ", 0) != 0) continue;
    if (sections.empty()) first_section = i;
    sections.push_back(lines[i].substr(3));
  }
  ASSERT_GE(sections.size(), 10u) << "the parse found the sections";

  std::size_t summary = 0;
  while (summary < first_section && lines[summary].rfind("**In one screen", 0) != 0) ++summary;
  ASSERT_LT(summary, first_section) << "docs/results.md: no \"**In one screen**\" summary before its first section";
  std::size_t bullets = 0;
  for (std::size_t i = summary + 1; i < first_section && !lines[i].empty(); ++i) bullets += lines[i].rfind("* ", 0) == 0;
  EXPECT_GE(bullets, 3u) << "the summary's findings, one bullet each";

  static const std::regex contents_line(R"(^[*-] \[[^\]]+\]\(#[^)\s]+\)(, \[[^\]]+\]\(#[^)\s]+\))*\s*$)");
  std::size_t begin = summary + 1;
  while (begin < first_section && !std::regex_match(lines[begin], contents_line)) ++begin;
  ASSERT_LT(begin, first_section) << "docs/results.md: no contents list (lines \"* [Section](#anchor)\") between "
                                     "the summary and the first section";
  EXPECT_LE(begin - summary, 40u) << "the summary fills one screen, and the contents follow it";
  std::size_t end = begin;
  while (end < first_section && std::regex_match(lines[end], contents_line)) ++end;

  static const std::regex anchor_link(R"(\]\(#([^)\s]+)\))");
  std::set<std::string> listed;
  for (std::size_t i = begin; i < end; ++i)
    for (std::sregex_iterator it(lines[i].begin(), lines[i].end(), anchor_link), e; it != e; ++it)
      listed.insert((*it)[1]);

  std::set<std::string> section_anchors;
  for (const std::string& section : sections) {
    section_anchors.insert(github_slug(section));
    EXPECT_TRUE(listed.count(github_slug(section)))
        << "docs/results.md's contents list (lines " << begin + 1 << "-" << end << ") has no link to \"## " << section
        << "\" (#" << github_slug(section) << ")";
  }
  for (const std::string& anchor : listed)
    EXPECT_TRUE(section_anchors.count(anchor)) << "docs/results.md's contents list links #" << anchor
                                               << ", which is no `## ` section";
}

// Every link between the user's documents lands: the file exists, and so does the heading.
TEST(Docs, EveryInternalLinkOfTheReadmeAndTheDocsResolves) {
  const std::vector<std::string> files = user_documents(kSource);
  ASSERT_GE(files.size(), 5u) << join(std::set<std::string>(files.begin(), files.end()));
  std::size_t links = 0;
  for (const std::string& file : files) {
    links += markdown_links(read_text(kSource / file)).size();
    for (const std::string& problem : broken_links(kSource, file)) ADD_FAILURE() << problem;
  }
  EXPECT_GT(links, 50u) << "the parse found the links";
}

// The README, the guide and the results book speak to users: no issue numbers, and no names from the
// code (constants `kName`, `Class::member`, test names `Suite.Test`, calls `function()`).
TEST(Docs, UserDocumentsNameNoIssuesAndNoCodeIdentifiers) {
  static const std::regex issue(R"((^|[^&\w/])#[0-9]+\b|[Ii]ssue [0-9#])");
  static const std::regex identifier(
      R"(\bk[A-Z][a-z][A-Za-z0-9]*\b|\b\w+::\w+|\b[A-Z][a-z]\w*\.[A-Z][a-z]\w+|\b[a-z_][a-z0-9_]*\(\))");
  for (const char* file : {"README.md", "docs/guide.md", "docs/results.md"}) {
    const std::vector<std::string> lines = lines_of(read_text(kSource / file));
    ASSERT_FALSE(lines.empty()) << file;
    FenceTracker fences;
    for (std::size_t i = 0; i < lines.size(); ++i) {
      if (!fences.markdown(lines[i])) continue;
      std::smatch m;
      if (std::regex_search(lines[i], m, issue)) ADD_FAILURE() << file << ":" << i + 1 << ": an issue number: " << lines[i];
      if (std::regex_search(lines[i], m, identifier))
        ADD_FAILURE() << file << ":" << i + 1 << ": a name from the code, " << m.str() << ": say what it means";
    }
  }
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

// Every "docs/design.md §N" the code cites names a numbered section of the design document, and no
// code cites the notes it was first written from ("DESIGN §N").
TEST(Docs, EveryDesignSectionTheCodeCitesExists) {
  std::set<int> sections;
  static const std::regex heading(R"(^## (\d+)\. )");
  std::smatch m;
  for (const std::string& line : lines_of(read_text(kSource / "docs/design.md")))
    if (std::regex_search(line, m, heading)) sections.insert(std::stoi(m[1]));
  ASSERT_GE(sections.size(), 10u) << "docs/design.md's numbered sections were not found";
  static const std::regex cite(R"(design\.md §(\d+))"), old_cite(R"(\bDESIGN §)");
  int citations = 0;
  for (const char* folder : {"host", "kernels", "tests"})
    for (const auto& entry : fs::recursive_directory_iterator(kSource / folder)) {
      const std::string ext = entry.path().extension().string();
      if (!entry.is_regular_file() || (ext != ".cpp" && ext != ".h" && ext != ".cl")) continue;
      if (entry.path().filename() == "test_docs.cpp") continue;  // this test names both forms
      const std::string text = read_text(entry.path());
      for (auto it = std::sregex_iterator(text.begin(), text.end(), cite); it != std::sregex_iterator(); ++it) {
        ++citations;
        EXPECT_TRUE(sections.count(std::stoi((*it)[1]))) << entry.path() << " cites " << it->str(0) << ", which does not exist";
      }
      EXPECT_FALSE(std::regex_search(text, old_cite)) << entry.path() << " cites DESIGN §, a file the repository does not have";
    }
  EXPECT_GT(citations, 50) << "the test found too few citations to be reading the code";
}

}  // namespace
}  // namespace bp::test
