// Every message the program gives a user on an error, and every warning, has a row in
// docs/guide.md's Troubleshooting table that says what to do, with the exit code it ends with; the
// exit codes are one table, worded alike in README.md, `bundlepath --help` and the guide; an
// unknown command lists every command.
//
// The messages are read from the sources (host/**/*.cpp and .h) when the test runs:
// * `throw TYPE(message)`: the types are kKinds, each with the exit code main.cpp's catch clauses
//   give it (read from main.cpp); a new type fails the test until it is added there;
// * `throw helper(message)` where `helper` is a lambda of the same file returning the exception;
// * the warnings `note("warning: …")` and `fprintf(stderr, "bundlepath: warning: …")`, and the
//   printed `fprintf(stderr, "bundlepath: error: …")` of a device that failed mid-render.
// A message is a template: string literals (with printf_text's and fprintf's conversions, and a
// local `std::string NAME = …` it names, spelled out) and variable parts between them. Not
// matched: `throw X(e.what())` (the caught message, collected where it was thrown) and a throw in
// the callback of a function that wraps its messages in its own (kWrappers).
//
// The matching rule. A row's first cell holds patterns (its `code spans`), where `…` stands for
// any text and a placeholder (FILE, N, X, …: kPlaceholders) for text without spaces. A pattern
// documents a message when it matches the message's start: the message's literal text against the
// pattern's literal text (after normalising quotes, `...` and white space), a variable part of the
// message against the pattern's `…`, a placeholder or an example (a name or a number: `--reference`
// for an option the message names), and the pattern's `…` and placeholders against anything but
// the message's lead. The lead is the message's literal text from its start (or, where it starts
// with a variable part, a file name or an option, from its first literal text) to the end of its
// first word: the pattern spells it out, so no row documents a message whose start it does not
// name. The row's exit column must hold the code the message ends with ("—" for a warning).
//
// kExempt is the explicit list of the rest, each with its reason: messages whose start is built
// from variables (with the row that documents them all), and internal invariants, which no user
// input reaches (they would be bugs, reported like any other error).
#include "e2e/cli_runner.h"
#include "e2e/doc_text.h"

#include <gtest/gtest.h>
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace bp::test {
namespace {

namespace fs = std::filesystem;

std::string trimmed(const std::string& s) {
  const std::size_t b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t") - b + 1);
}

// A Markdown table's rows (header and separator left out) as cells: the table is the one whose
// header row is `header` exactly, in `lines`.
std::vector<std::vector<std::string>> table_rows(const std::vector<std::string>& lines, const std::string& header) {
  std::vector<std::vector<std::string>> rows;
  bool inside = false;
  for (const std::string& line : lines) {
    if (line == header) {
      inside = true;
      continue;
    }
    if (!inside) continue;
    if (line.rfind("|", 0) != 0) break;
    if (line.rfind("|---", 0) == 0) continue;
    std::vector<std::string> cells;
    std::string cell;
    for (std::size_t i = 1; i < line.size(); ++i) {
      if (line[i] == '\\' && i + 1 < line.size() && line[i + 1] == '|') {
        cell += '|';
        ++i;
      } else if (line[i] == '|') {
        cells.push_back(trimmed(cell));
        cell.clear();
      } else {
        cell += line[i];
      }
    }
    rows.push_back(cells);
  }
  return rows;
}

// ------------------------------------------------------------------ reading the sources

// One source file twice, offsets alike: `code` without comments (blanked), `mask` without the
// contents of string and character literals too (blanked, the quotes kept), where keywords,
// parentheses, commas and `+` are looked for.
struct Source {
  std::string path;  // under host/
  std::string code, mask;
  int line_of(std::size_t at) const { return 1 + int(std::count(code.begin(), code.begin() + long(at), '\n')); }
};

bool identifier_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

Source read_source(const fs::path& file, const std::string& path) {
  Source s{path, read_text(file), ""};
  std::string& code = s.code;
  s.mask = code;
  std::string& mask = s.mask;
  auto blank = [](std::string& t, std::size_t b, std::size_t e) {
    for (std::size_t k = b; k < e && k < t.size(); ++k)
      if (t[k] != '\n') t[k] = ' ';
  };
  for (std::size_t i = 0; i < code.size();) {
    if (code.compare(i, 2, "//") == 0) {
      const std::size_t e = std::min(code.find('\n', i), code.size());
      blank(code, i, e);
      blank(mask, i, e);
      i = e;
    } else if (code.compare(i, 2, "/*") == 0) {
      const std::size_t e = std::min(code.find("*/", i + 2) + 2, code.size());
      blank(code, i, e);
      blank(mask, i, e);
      i = e;
    } else if (code[i] == 'R' && i + 1 < code.size() && code[i + 1] == '"' && (i == 0 || !identifier_char(code[i - 1]))) {
      const std::size_t open = code.find('(', i + 2);
      const std::string end = ")" + code.substr(i + 2, open - i - 2) + "\"";
      const std::size_t e = code.find(end, open) + end.size();
      blank(mask, i + 2, e - 1);
      i = e;
    } else if (code[i] == '"' || (code[i] == '\'' && (i == 0 || !std::isxdigit(static_cast<unsigned char>(code[i - 1]))))) {
      const char quote = code[i];
      std::size_t e = i + 1;
      while (e < code.size() && code[e] != quote) e += code[e] == '\\' ? 2 : 1;
      blank(mask, i + 1, e);
      i = e + 1;
    } else {
      ++i;
    }
  }
  return s;
}

// The index of the bracket closing the one at `open`.
std::size_t closing(const Source& s, std::size_t open) {
  int depth = 0;
  for (std::size_t i = open; i < s.mask.size(); ++i) {
    const char c = s.mask[i];
    if (c == '(' || c == '[' || c == '{') ++depth;
    if ((c == ')' || c == ']' || c == '}') && --depth == 0) return i;
  }
  return std::string::npos;
}

struct Range {
  std::size_t begin, end;
};

Range trim(const Source& s, Range r) {
  while (r.begin < r.end && std::isspace(static_cast<unsigned char>(s.mask[r.begin]))) ++r.begin;
  while (r.end > r.begin && std::isspace(static_cast<unsigned char>(s.mask[r.end - 1]))) --r.end;
  return r;
}

// The parts of `r` between the separators `sep` outside brackets.
std::vector<Range> split(const Source& s, Range r, char sep) {
  std::vector<Range> parts;
  int depth = 0;
  std::size_t start = r.begin;
  for (std::size_t i = r.begin; i < r.end; ++i) {
    const char c = s.mask[i];
    if (c == '(' || c == '[' || c == '{') ++depth;
    if (c == ')' || c == ']' || c == '}') --depth;
    if (c == sep && depth == 0) {
      parts.push_back(trim(s, {start, i}));
      start = i + 1;
    }
  }
  parts.push_back(trim(s, {start, r.end}));
  return parts;
}

// A message: literal text and variable parts.
struct Piece {
  bool variable;
  std::string text;
};
using Template = std::vector<Piece>;

void append(Template& t, const Piece& p) {
  if (!p.variable && p.text.empty()) return;
  if (!t.empty() && t.back().variable == p.variable) {
    t.back().text += p.text;
    return;
  }
  t.push_back(p);
}

void append(Template& t, const Template& more) {
  for (const Piece& p : more) append(t, p);
}

const Piece kVariable{true, ""};

// The string literals (adjacent ones joined) at `at`, unescaped; npos in `next` where `at` holds none.
std::string literal_at(const Source& s, std::size_t at, std::size_t& next) {
  std::string out;
  next = std::string::npos;
  while (at < s.code.size() && s.code[at] == '"') {
    std::size_t i = at + 1;
    for (; s.code[i] != '"'; ++i) {
      if (s.code[i] != '\\') {
        out += s.code[i];
        continue;
      }
      const char e = s.code[++i];
      out += e == 'n' ? '\n' : e == 't' ? '\t' : e;
    }
    next = i + 1;
    at = next;
    while (at < s.code.size() && std::isspace(static_cast<unsigned char>(s.code[at]))) ++at;
  }
  return out;
}

// A printf format: its conversions are variable parts.
Template printf_template(const std::string& format) {
  static const std::regex conversion(R"(%[-+ #0]*[0-9*]*(?:\.[0-9*]+)?(?:hh|h|ll|l|z|j|t|L)?[diouxXeEfFgGaAcsp])");
  Template t;
  std::size_t at = 0;
  for (std::sregex_iterator it(format.begin(), format.end(), conversion), end; it != end; ++it) {
    std::string text = format.substr(at, std::size_t(it->position()) - at);
    append(t, Piece{false, std::regex_replace(text, std::regex("%%"), "%")});
    append(t, kVariable);
    at = std::size_t(it->position() + it->length());
  }
  append(t, Piece{false, std::regex_replace(format.substr(at), std::regex("%%"), "%")});
  return t;
}

using Bindings = std::map<std::string, Template>;

Template expression_template(const Source& s, Range r, std::size_t site, const Bindings& bound, int depth);

// `std::string NAME = …;` nearest before `site`: its value; nullopt where there is none.
std::optional<Template> local_string(const Source& s, const std::string& name, std::size_t site, int depth) {
  const std::regex declaration("std::string\\s+" + name + "\\s*=[^=]");
  std::optional<std::size_t> found;
  const std::string before = s.mask.substr(0, site);
  for (std::sregex_iterator it(before.begin(), before.end(), declaration), end; it != end; ++it)
    found = std::size_t(it->position() + it->length()) - 1;
  if (!found || depth > 4) return std::nullopt;
  int block = 0;  // the declaration's block must hold the site: no '}' closes it in between
  for (std::size_t k = *found; k < site; ++k) {
    block += s.mask[k] == '{' ? 1 : s.mask[k] == '}' ? -1 : 0;
    if (block < 0) return std::nullopt;
  }
  std::size_t e = *found;
  for (int d = 0; e < s.mask.size() && !(s.mask[e] == ';' && d == 0); ++e) {
    if (s.mask[e] == '(' || s.mask[e] == '[' || s.mask[e] == '{') ++d;
    if (s.mask[e] == ')' || s.mask[e] == ']' || s.mask[e] == '}') --d;
  }
  return expression_template(s, trim(s, {*found, e}), *found, {}, depth + 1);
}

Template operand_template(const Source& s, Range r, std::size_t site, const Bindings& bound, int depth) {
  const std::string text = s.code.substr(r.begin, r.end - r.begin);
  std::size_t next = 0;
  if (text.rfind('"', 0) == 0) {
    const std::string literal = literal_at(s, r.begin, next);
    if (next == r.end) return {Piece{false, literal}};
    return {kVariable};
  }
  static const std::regex call(R"(^([A-Za-z_][\w:]*)\s*\()");
  std::smatch m;
  if (std::regex_search(text, m, call) && closing(s, r.begin + std::size_t(m.length()) - 1) == r.end - 1) {
    const Range inside{r.begin + std::size_t(m.length()), r.end - 1};
    const std::string f = m[1];
    if (f == "std::string" || f == "one_line") return expression_template(s, inside, site, bound, depth);
    if (f == "printf_text") {
      const std::string format = literal_at(s, split(s, inside, ',').front().begin, next);
      if (next != std::string::npos) return printf_template(format);
    }
    return {kVariable};
  }
  if (text.front() == '(' && closing(s, r.begin) == r.end - 1)
    return expression_template(s, {r.begin + 1, r.end - 1}, site, bound, depth);
  if (std::regex_match(text, std::regex(R"([A-Za-z_]\w*)"))) {
    if (const auto b = bound.find(text); b != bound.end()) return b->second;
    if (std::optional<Template> value = local_string(s, text, site, depth)) return *value;
  }
  return {kVariable};
}

Template expression_template(const Source& s, Range r, std::size_t site, const Bindings& bound, int depth) {
  Template t;
  for (const Range& operand : split(s, r, '+')) append(t, operand_template(s, operand, site, bound, depth));
  return t;
}

std::string template_text(const Template& t) {
  std::string out;
  for (const Piece& p : t) out += p.variable ? "…" : p.text;
  return out;
}

// The exit code a site ends the program with; nullopt for a warning, and where the sources decide
// it case by case (kinds main does not catch by name that are converted on some paths only).
struct Kind {
  const char* name;
  const char* exits_as;  // the kind main.cpp's catch clauses see, or nullptr: case by case
  const char* why;
};
const Kind kKinds[] = {
    {"UsageError", "UsageError", ""},
    {"SceneError", "SceneError", ""},
    {"NoPlatformError", "NoPlatformError", ""},
    {"DeviceError", "std::exception", ""},
    {"std::runtime_error", "std::exception", ""},
    {"DenoiserUnavailable", "UsageError", "render_job.cpp rethrows it as a UsageError"},
    {"std::invalid_argument", nullptr,
     "rethrown as a UsageError where user input can cause it (render_scene.cpp, render_passes.cpp), exit 1 elsewhere"},
    {"printed error", nullptr, "a device failed mid-render: run_render returns 1 (render_command.cpp)"},
    {"warning", nullptr, "the render goes on"},
};

// Where the program says something to its user.
struct Site {
  std::string where;   // host/FILE:LINE
  std::string kind;    // the exception type, or "warning", or "printed error"
  std::string source;  // the throw's or print's text, white space collapsed
  Template message;
  bool rethrow = false;  // throw X(e.what()): the message is the caught one, collected where it was thrown
  bool wrapped = false;  // inside the callback of a function that wraps its messages (kWrappers)
};

// Calls whose callback's exceptions the user never sees as they are: write_file_atomically turns
// each into "cannot write WHAT 'PATH': REASON" (image/atomic_file.cpp), which is collected itself.
const char* const kWrappers[] = {"write_file_atomically"};

std::string collapsed(const std::string& text) {
  return std::regex_replace(trimmed(text), std::regex(R"(\s+)"), " ");
}

std::vector<Site> sites_in(const Source& s) {
  std::vector<Site> sites;
  std::vector<Range> wrapped;
  for (const char* w : kWrappers) {
    const std::regex call(std::string("\\b") + w + "\\s*\\(");
    for (std::sregex_iterator it(s.mask.begin(), s.mask.end(), call), end; it != end; ++it) {
      const std::size_t open = std::size_t(it->position() + it->length()) - 1;
      wrapped.push_back({open, closing(s, open)});
    }
  }
  auto site_at = [&](std::size_t at, std::size_t end, const std::string& kind) {
    Site site;
    site.where = "host/" + s.path + ":" + std::to_string(s.line_of(at));
    site.kind = kind;
    site.source = collapsed(s.code.substr(at, end - at));
    for (const Range& w : wrapped) site.wrapped = site.wrapped || (at > w.begin && at < w.end);
    return site;
  };

  static const std::regex throw_keyword(R"(\bthrow\b\s*([A-Za-z_][\w:]*)?\s*([({;]?))");
  for (std::sregex_iterator it(s.mask.begin(), s.mask.end(), throw_keyword), end; it != end; ++it) {
    const std::size_t at = std::size_t(it->position());
    std::string type = (*it)[1];
    const std::string bracket = (*it)[2];
    if (type.empty() && bracket == ";") continue;  // `throw;`: rethrows what was caught
    if (type.rfind("bp::", 0) == 0) type = type.substr(4);
    const std::size_t open = std::size_t(it->position() + it->length()) - 1;
    const std::size_t close = bracket.empty() || bracket == ";" ? open : closing(s, open);
    Site site = site_at(at, close + 1, type);
    if (bracket != "(") {  // a type without a message
      sites.push_back(site);
      continue;
    }
    const Range argument = split(s, {open + 1, close}, ',').front();
    const std::string argument_text = s.code.substr(argument.begin, argument.end - argument.begin);
    site.rethrow = std::regex_match(argument_text, std::regex(R"(\w+\.what\(\))"));
    // A helper of this file, `const auto NAME = [&](const std::string& P) { return TYPE(…P…); };`.
    const std::regex helper("\\b" + type + R"(\s*=\s*\[[^\]]*\]\s*\(\s*const std::string&\s*(\w+)\s*\)\s*\{\s*return\s+([\w:]+)\s*\()");
    std::smatch h;
    const bool exception_type = std::any_of(std::begin(kKinds), std::end(kKinds), [&](const Kind& k) { return type == k.name; });
    if (!exception_type && std::regex_search(s.mask, h, helper)) {
      const std::size_t helper_open = std::size_t(h.position() + h.length()) - 1;
      site.kind = h[2];
      site.message = expression_template(s, {helper_open + 1, closing(s, helper_open)}, helper_open,
                                         {{h[1], expression_template(s, argument, at, {}, 0)}}, 0);
    } else {
      site.message = expression_template(s, argument, at, {}, 0);
    }
    sites.push_back(site);
  }

  // Warnings given to the observer: note("warning: …").
  static const std::regex note_call(R"(\bnote\s*\()");
  for (std::sregex_iterator it(s.mask.begin(), s.mask.end(), note_call), end; it != end; ++it) {
    const std::size_t open = std::size_t(it->position() + it->length()) - 1, close = closing(s, open);
    Site site = site_at(std::size_t(it->position()), close + 1, "warning");
    site.message = expression_template(s, split(s, {open + 1, close}, ',').front(), open, {}, 0);
    if (!site.message.empty() && !site.message.front().variable && site.message.front().text.rfind("warning: ", 0) == 0)
      sites.push_back(site);
  }

  // Printed warnings and errors: fprintf(stderr, "bundlepath: warning: …") and "bundlepath: error: …".
  static const std::regex print_call(R"(\bfprintf\s*\(\s*stderr\s*,\s*)");
  for (std::sregex_iterator it(s.mask.begin(), s.mask.end(), print_call), end; it != end; ++it) {
    const std::size_t format_at = std::size_t(it->position() + it->length());
    std::size_t next = 0;
    const std::string format = literal_at(s, format_at, next);
    for (const char* kind : {"warning", "error"}) {
      const std::string prefix = std::string("bundlepath: ") + kind + ": ";
      if (format.rfind(prefix, 0) != 0) continue;
      Site site = site_at(std::size_t(it->position()), next, kind == std::string("warning") ? "warning" : "printed error");
      std::string line = format.substr(std::string("bundlepath: ").size());
      if (!line.empty() && line.back() == '\n') line.pop_back();
      site.message = printf_template(line);
      sites.push_back(site);
    }
  }
  return sites;
}

std::vector<Site> all_sites() {
  const fs::path host = fs::path(BP_SOURCE_DIR) / "host";
  std::vector<fs::path> files;
  for (const fs::directory_entry& e : fs::recursive_directory_iterator(host))
    if (e.is_regular_file() && (e.path().extension() == ".cpp" || e.path().extension() == ".h")) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  std::vector<Site> sites;
  for (const fs::path& f : files) {
    const std::vector<Site> more = sites_in(read_source(f, fs::relative(f, host).string()));
    sites.insert(sites.end(), more.begin(), more.end());
  }
  return sites;
}

// ------------------------------------------------------------------ how they reach the user

// The exit code main.cpp gives an exception type, read from its catch clauses
// (`catch (const bp::UsageError& e) { return fail(session, e, 2); }`); "std::exception" is the rest.
std::map<std::string, int> main_exit_codes() {
  const std::string main_cpp = read_text(fs::path(BP_SOURCE_DIR) / "host/main.cpp");
  static const std::regex clause(R"(catch \(const (?:bp::)?([\w:]+)& \w+\) \{\s*return fail\(session, \w+, (\d+)\);)");
  std::map<std::string, int> codes;
  for (std::sregex_iterator it(main_cpp.begin(), main_cpp.end(), clause), end; it != end; ++it)
    codes[(*it)[1]] = std::stoi((*it)[2]);
  return codes;
}

// Sites a table row cannot be matched against, each with the reason; `row` is the pattern of the
// guide's table that documents them, exactly as the table spells it, or nullptr where no user
// input leads there (an internal invariant: it would be a bug, reported like any other error).
struct Exempt {
  const char* file;  // host/…
  const char* text;  // in the site's source text
  const char* row;
  const char* why;
};
const Exempt kExempt[] = {
    // Built from variables (or their start is): documented by a row for all of them.
    {"host/scene/gltf_loader.cpp", "throw SceneError(one_line(path_ + \": \" + what))", "FILE: <glTF object> …",
     "the loader's fail(what): some hundred checks of the file, each naming the glTF object at fault"},
    {"host/scene/camera_views.cpp", "throw SceneError(node.animation_error)", "FILE: <glTF object> …",
     "a glTF loader message (fail(what)) kept until --camera-animation plays that animation"},
    {"host/scene/camera_path.cpp", "throw SceneError(where + \" \\\"\" + name", "FILE: key N …",
     "vector_of's `where` is read_camera_path's `path + \": key \" + k`"},
    {"host/render/parallel_pass.cpp", "throw PassFailure(lane_label", "error: …; the image holds the rounds completed before it",
     "caught by the render loop (passes/render_loop.cpp) and printed as the `error:` line"},
    {"host/render/rank_pass.cpp", "throw PassFailure(failure)", "error: …; the image holds the rounds completed before it",
     "the first rank's PassFailure, passed on to every rank: printed as the `error:` line"},
    {"host/image/exr_io.cpp", "throw std::runtime_error(\"no layer '\"", "cannot read layer '…' of EXR 'FILE': …",
     "thrown inside read_exr's try, whose catch puts it after `cannot read layer … of EXR …: `"},
    // Internal: no user input leads there.
    {"host/scene/bvh.cpp", "throw DepthExceeded{}", nullptr, "control flow inside the BVH builder, caught there"},
    {"host/render/parallel_pass.cpp", "simulated failure", nullptr, "the tests' device-failure hook (an environment variable)"},
    {"host/passes/combined.cpp", "--ratio must be 0", nullptr, "the command line's --ratio is checked first (cli/options.cpp)"},
    {"host/scene/camera_views.cpp", "--fps must be a number > 0", nullptr, "the command line's --fps is checked first"},
    {"host/passes/ray_bundles.cpp", "views must have one image size", nullptr, "a walkthrough's views share one size"},
    {"host/image/metrics.cpp", "compare_images: image is", nullptr,
     "compare and --reference check the sizes first and say so (collected there)"},
    {"host/image/contact_sheet.cpp", "a contact sheet needs at least one image", nullptr, "a render has an image"},
    {"host/image/exr_io.cpp", "\"cannot read EXR '\"", nullptr, "exr_layer_names, which only the tests call"},
    {"host/device/kernel_source.cpp", "is not embedded in this binary", nullptr, "the build embeds every kernel"},
};

// Rows for messages built outside a throw and handed to one of kExempt's (so the sites above do
// not show them): the file must still hold `text`.
const Exempt kBuiltElsewhere[] = {
    {"host/scene/gltf_extensions.cpp", "(extensionsRequired), which this renderer does not support",
     "FILE: requires EXTENSION (extensionsRequired), which this renderer does not support …",
     "gltf_extension_error's message, given to the loader's fail(what)"},
    {"host/scene/gltf_loader.cpp", "\"no emitter: the image will be black\"", "warning: FILE: no emitter: the image will be black",
     "one of the scene's warnings, printed as `warning: FILE: …` (render/render_scene.cpp)"},
};

// Messages that are more than one line, against the guide's "one line"; each says why.
const Exempt kMultiLine[] = {
    {"host/device/program_cache.cpp", "kernel build of kernels/", nullptr,
     "the compiler's log follows the message line, as the guide says"},
};

// ------------------------------------------------------------------ the table

const std::set<std::string> kPlaceholders = {"FILE", "REF", "PREFIX", "OPTION", "N", "X", "M", "W", "H", "WxH", "EXTENSION"};

std::string normalised(std::string text) {
  for (const auto& [from, to] : std::vector<std::pair<std::string, std::string>>{
           {"...", "…"}, {"‘", "'"}, {"’", "'"}, {"“", "\""}, {"”", "\""}, {"×", "x"}, {"\n", " "}, {"\t", " "}})
    for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
      text.replace(at, from.size(), to);
  return std::regex_replace(text, std::regex("  +"), " ");
}

enum class Token { literal, variable, any, word_first, word_rest };
struct Tok {
  Token kind;
  char c = 0;
  bool lead = false;  // a message's lead: matched by the pattern's literal text alone
};

const std::string kEllipsis = "…";

std::vector<Tok> message_tokens(const Template& t) {
  std::vector<Tok> out;
  for (const Piece& p : t) {
    if (p.variable) {
      out.push_back({Token::variable});
      continue;
    }
    const std::string text = normalised(p.text);
    for (char c : text) out.push_back({Token::literal, c});
  }
  // The lead: from the first literal character to the end of the first word (two letters or more).
  const auto letter = [&](std::size_t i) {
    return i < out.size() && out[i].kind == Token::literal && std::isalpha(static_cast<unsigned char>(out[i].c));
  };
  std::size_t first = std::string::npos, word_end = std::string::npos;
  for (std::size_t i = 0; i < out.size() && word_end == std::string::npos; ++i) {
    if (out[i].kind != Token::literal) continue;
    first = std::min(first, i);
    if (letter(i) && i > 0 && letter(i - 1) && !letter(i + 1)) word_end = i + 1;
  }
  if (word_end == std::string::npos) return {};  // no word: nothing to match
  for (std::size_t i = first; i < word_end; ++i)
    if (out[i].kind == Token::literal) out[i].lead = true;
  return out;
}

bool has_word(const Template& t) { return !message_tokens(t).empty(); }

std::vector<Tok> pattern_tokens(const std::string& pattern) {
  const std::string text = normalised(pattern);
  std::vector<Tok> out;
  for (std::size_t i = 0; i < text.size();) {
    if (text.compare(i, kEllipsis.size(), kEllipsis) == 0) {
      out.push_back({Token::any});
      i += kEllipsis.size();
      continue;
    }
    if (std::isalpha(static_cast<unsigned char>(text[i])) && (i == 0 || !identifier_char(text[i - 1]))) {
      std::size_t e = i;
      while (e < text.size() && identifier_char(text[e])) ++e;
      if (kPlaceholders.count(text.substr(i, e - i))) {
        out.push_back({Token::word_first});
        out.push_back({Token::word_rest});
        i = e;
        continue;
      }
    }
    out.push_back({Token::literal, text[i]});
    ++i;
  }
  return out;
}

bool example_char(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || std::string("-_./[]").find(c) != std::string::npos;
}

// Whether the pattern matches the message's start (the rule at the top of this file).
bool matches(const std::vector<Tok>& m, const std::vector<Tok>& p) {
  std::size_t lead_end = 0;
  for (std::size_t i = 0; i < m.size(); ++i)
    if (m[i].lead) lead_end = i + 1;
  std::vector<std::vector<signed char>> memo(m.size() + 1, std::vector<signed char>(p.size() + 1, -1));
  std::function<bool(std::size_t, std::size_t)> f = [&](std::size_t i, std::size_t j) -> bool {
    signed char& r = memo[i][j];
    if (r >= 0) return r;
    bool ok = false;
    if (j == p.size()) {
      ok = i >= lead_end;
    } else if (i == m.size()) {
      ok = std::all_of(p.begin() + long(j), p.end(), [](const Tok& t) { return t.kind == Token::any || t.kind == Token::word_rest; });
    } else if (m[i].kind == Token::variable) {
      // The variable part ends, or it stands for the pattern's next token: `…`, a placeholder, or
      // an example of it in the pattern (a name, a number or a path: no space or punctuation).
      ok = f(i + 1, j) || ((p[j].kind != Token::literal || example_char(p[j].c)) && f(i, j + 1));
    } else {
      const bool free = !m[i].lead;
      const bool word_char = !std::isspace(static_cast<unsigned char>(m[i].c));
      switch (p[j].kind) {
        case Token::literal: ok = p[j].c == m[i].c && f(i + 1, j + 1); break;
        case Token::any: ok = f(i, j + 1) || (free && f(i + 1, j)); break;
        case Token::word_first: ok = free && word_char && f(i + 1, j + 1); break;
        case Token::word_rest: ok = f(i, j + 1) || (free && word_char && f(i + 1, j)); break;
        case Token::variable: break;
      }
    }
    r = ok;
    return ok;
  };
  return f(0, 0);
}

struct Row {
  std::vector<std::string> patterns;  // the first cell's code spans
  std::string exit;                   // the second cell
  std::string what;                   // the third
};

const char* const kMessageHeader = "| message (start) | exit | what to do |";
const char* const kExitHeader = "| exit code | meaning |";

std::vector<Row> guide_rows() {
  const std::string guide = read_text(fs::path(BP_SOURCE_DIR) / "docs/guide.md");
  std::vector<Row> rows;
  static const std::regex span("`([^`]+)`");
  for (const std::vector<std::string>& cells : table_rows(section(guide, "## Troubleshooting"), kMessageHeader)) {
    Row row;
    if (cells.size() != 3) {
      ADD_FAILURE() << "a row of the guide's message table without three cells: " << cells.front();
      continue;
    }
    for (std::sregex_iterator it(cells[0].begin(), cells[0].end(), span), end; it != end; ++it)
      row.patterns.push_back((*it)[1]);
    row.exit = cells[1];
    row.what = cells[2];
    rows.push_back(row);
  }
  return rows;
}

// The codes a row's exit cell names: "2", "1 or 2"; "—" (a warning) names none.
std::set<int> row_codes(const std::string& cell) {
  std::set<int> codes;
  static const std::regex number(R"(\d+)");
  for (std::sregex_iterator it(cell.begin(), cell.end(), number), end; it != end; ++it) codes.insert(std::stoi(it->str()));
  return codes;
}

const Exempt* exemption(const Site& site, const Exempt* begin, const Exempt* end) {
  for (const Exempt* e = begin; e != end; ++e)
    if (site.where.rfind(std::string(e->file) + ":", 0) == 0 && site.source.find(e->text) != std::string::npos) return e;
  return nullptr;
}

// BP_LIST_MESSAGES=1 lists what the test reads: where, kind, message.
TEST(ErrorMessages, SourcesYieldTheMessagesThisTestLooksFor) {
  if (std::getenv("BP_LIST_MESSAGES"))
    for (const Site& s : all_sites()) {
      std::string rows;
      for (const Row& row : guide_rows())
        for (const std::string& pattern : row.patterns)
          if (has_word(s.message) && matches(message_tokens(s.message), pattern_tokens(pattern))) rows += " `" + pattern + "`";
      std::printf("%s\t%s%s%s\t%s\t->%s\n", s.where.c_str(), s.kind.c_str(), s.rethrow ? " (rethrow)" : "",
                  s.wrapped ? " (wrapped)" : "", template_text(s.message).c_str(), rows.c_str());
    }
  // The reader itself: a few messages it must find as templates, so that a change in how the
  // sources are written cannot leave the real test below with nothing to check.
  const std::vector<Site> sites = all_sites();
  ASSERT_GT(sites.size(), 100u);
  std::map<std::string, std::string> found;
  for (const Site& s : sites) found[template_text(s.message)] = s.kind;
  for (const auto& [text, kind] : std::vector<std::pair<std::string, std::string>>{
           {"no scene file given (usage: bundlepath render SCENE.gltf [options])", "UsageError"},
           {"…: environment map: no such file", "SceneError"},                       // a helper lambda
           {"no OpenCL device matches --device '…'; available:", "DeviceError"},       // a local string
           {"… view(s) of …x… need about … MiB of … memory, more than … offers (… MiB): "
            "lower --width/--height or the number of views", "UsageError"},            // printf_text
           {"warning: … NaN/Inf samples were dropped", "warning"},                      // fprintf
           {"warning: --mode … runs on one device: … stays idle", "warning"},           // note
           {"error: …; the image holds the rounds completed before it", "printed error"}}) {
    const auto it = found.find(text);
    ASSERT_NE(it, found.end()) << text;
    EXPECT_EQ(it->second, kind) << text;
  }
}

TEST(ErrorMessages, EveryMessageHasARowInTheGuidesTroubleshootingTable) {
  const std::vector<Site> sites = all_sites();
  const std::vector<Row> rows = guide_rows();
  ASSERT_GT(rows.size(), 20u) << "the guide's table: " << kMessageHeader;
  const std::map<std::string, int> main_codes = main_exit_codes();
  ASSERT_EQ(main_codes.count("std::exception"), 1u) << "main.cpp's last catch clause";

  std::set<std::string> all_patterns;
  for (const Row& row : rows) all_patterns.insert(row.patterns.begin(), row.patterns.end());
  std::set<const Row*> used;
  std::set<const Exempt*> exemptions_used;
  auto mark_row_of = [&](const char* pattern) {
    for (const Row& row : rows)
      if (std::find(row.patterns.begin(), row.patterns.end(), pattern) != row.patterns.end()) used.insert(&row);
  };

  for (const Site& site : sites) {
    const Kind* kind = nullptr;
    for (const Kind& k : kKinds)
      if (site.kind == k.name) kind = &k;
    if (site.rethrow && kind) continue;  // its message is collected where it was first thrown
    if (site.wrapped) continue;          // the wrapper's message is what the user sees (kWrappers)
    if (const Exempt* e = exemption(site, std::begin(kExempt), std::end(kExempt))) {
      exemptions_used.insert(e);
      if (e->row) {
        EXPECT_TRUE(all_patterns.count(e->row)) << site.where << ": kExempt names `" << e->row
                                                << "`, which no row of the guide's table has";
        mark_row_of(e->row);
      }
      continue;
    }
    if (!kind) {
      ADD_FAILURE() << site.where << ": throws a " << site.kind << " (" << site.source
                    << "): add it to kKinds with the exit code main gives it, or to kExempt";
      continue;
    }
    const std::string text = template_text(site.message);
    if (!has_word(site.message)) {
      ADD_FAILURE() << site.where << ": a message built from variables (" << site.source
                    << "): spell out its start, or add it to kExempt with the row that documents it";
      continue;
    }
    const std::vector<Tok> message = message_tokens(site.message);
    std::vector<const Row*> matching;
    for (const Row& row : rows)
      for (const std::string& pattern : row.patterns)
        if (matches(message, pattern_tokens(pattern))) {
          matching.push_back(&row);
          break;
        }
    if (matching.empty()) {
      ADD_FAILURE() << site.where << ": no row of the guide's Troubleshooting table documents\n  " << text
                    << "\n(" << site.kind << "); add one: | `" << text << "` | exit | what to do |";
      continue;
    }
    used.insert(matching.begin(), matching.end());
    // The exit column: the code main gives this kind, or "—" for a warning.
    std::optional<int> code;
    if (kind->exits_as) code = main_codes.count(kind->exits_as) ? main_codes.at(kind->exits_as) : main_codes.at("std::exception");
    if (site.kind == "printed error") code = 1;
    const bool warning = site.kind == "warning";
    const bool some_row_agrees = std::any_of(matching.begin(), matching.end(), [&](const Row* row) {
      return warning ? row->exit == "—" : !code || row_codes(row->exit).count(*code);
    });
    EXPECT_TRUE(some_row_agrees) << site.where << ": " << text << " ends with exit "
                                 << (warning ? std::string("— (a warning)") : std::to_string(code.value_or(-1)))
                                 << ", but its row says " << matching.front()->exit;
    if (site.message.size() && text.find('\n') != std::string::npos &&
        !exemption(site, std::begin(kMultiLine), std::end(kMultiLine)))
      ADD_FAILURE() << site.where << ": more than one line, where the guide says every error is one: " << text;
  }
  for (const Exempt& e : kBuiltElsewhere) {
    EXPECT_NE(read_text(fs::path(BP_SOURCE_DIR) / e.file).find(e.text), std::string::npos)
        << "kBuiltElsewhere's entry: " << e.file << " no longer holds `" << e.text << "`";
    EXPECT_TRUE(all_patterns.count(e.row)) << "kBuiltElsewhere names `" << e.row << "`, which no row of the guide's table has";
    mark_row_of(e.row);
  }
  for (const Exempt& e : kExempt)
    EXPECT_TRUE(exemptions_used.count(&e)) << "kExempt's entry " << e.file << " `" << e.text
                                           << "` matches nothing there any more: remove it";
  for (const Row& row : rows)
    EXPECT_TRUE(used.count(&row)) << "the guide's row for `" << (row.patterns.empty() ? "" : row.patterns.front())
                                  << "` documents no message the program has (give each row a `pattern`)";
}

// ------------------------------------------------------------------ exit codes and commands

// An exit-code table as code -> meaning (backticks dropped): the guide's Markdown table under
// kExitHeader, the README's paragraph, or the help's "exit codes:" list (each code at two spaces'
// indent, its wrapped lines deeper).
std::map<int, std::string> markdown_exit_codes(const std::vector<std::string>& lines) {
  std::map<int, std::string> codes;
  for (const std::vector<std::string>& cells : table_rows(lines, kExitHeader)) {
    if (cells.size() != 2 || !std::regex_match(cells[0], std::regex(R"(\d+)"))) {
      ADD_FAILURE() << "an exit-code row that is not | CODE | meaning |: " << cells.front();
      continue;
    }
    codes[std::stoi(cells[0])] = std::regex_replace(cells[1], std::regex("`"), "");
  }
  return codes;
}

// The README's: one paragraph, "0 done; 1 …; 2 …." (the README is kept short).
std::map<int, std::string> paragraph_exit_codes(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) text += (text.empty() || line.empty() ? "" : " ") + trimmed(line);
  if (!text.empty() && text.back() == '.') text.pop_back();
  text = std::regex_replace(text, std::regex("`"), "");
  std::map<int, std::string> codes;
  static const std::regex entry(R"((?:^|; )(\d+) ((?:(?!; \d+ ).)+))");
  for (std::sregex_iterator it(text.begin(), text.end(), entry), end; it != end; ++it)
    codes[std::stoi((*it)[1])] = (*it)[2];
  return codes;
}

std::map<int, std::string> help_exit_codes(const std::string& help) {
  std::map<int, std::string> codes;
  bool inside = false;
  int code = -1;
  std::smatch m;
  static const std::regex entry(R"(  (\d+) +(\S.*))"), more(R"( {5,}(\S.*))");
  for (const std::string& line : lines_of(help)) {
    if (line == "exit codes:") {
      inside = true;
    } else if (inside && std::regex_match(line, m, entry)) {
      code = std::stoi(m[1]);
      codes[code] = m[2];
    } else if (inside && code >= 0 && std::regex_match(line, m, more)) {
      codes[code] += " " + m[1].str();
    } else if (inside) {
      break;
    }
  }
  return codes;
}

// The codes the program ends with: main.cpp's catch clauses and its and run_render's returns.
std::set<int> program_exit_codes() {
  std::set<int> codes;
  static const std::regex returned(R"(\b(?:return|fail\(session, \w+,) (?:[\w.()!]+ \? )?(\d+)(?: : (\d+))?\)?;)");
  for (const char* file : {"host/main.cpp", "host/cli/render_command.cpp"}) {
    const std::string text = read_text(fs::path(BP_SOURCE_DIR) / file);
    for (std::sregex_iterator it(text.begin(), text.end(), returned), end; it != end; ++it)
      for (int k : {1, 2})
        if ((*it)[k].matched) codes.insert(std::stoi((*it)[k]));
  }
  return codes;
}

TEST(ErrorMessages, OneExitCodeTableInTheReadmeTheHelpAndTheGuide) {
  const std::map<int, std::string> readme =
      paragraph_exit_codes(section(read_text(fs::path(BP_SOURCE_DIR) / "README.md"), "## Exit codes"));
  const std::map<int, std::string> guide =
      markdown_exit_codes(section(read_text(fs::path(BP_SOURCE_DIR) / "docs/guide.md"), "## Troubleshooting"));
  const CliResult help = run_cli("--help");
  ASSERT_EQ(help.exit_code, 0) << help.output;
  const std::map<int, std::string> usage = help_exit_codes(help.output);
  std::set<int> documented;
  for (const auto& [code, meaning] : readme) documented.insert(code);
  EXPECT_EQ(documented, program_exit_codes()) << "README.md's exit codes and the ones the program ends with";
  EXPECT_EQ(guide, readme) << "docs/guide.md's exit-code table and README.md's";
  EXPECT_EQ(usage, readme) << "`bundlepath --help`'s exit codes and README.md's";
}

// The commands --help's usage lists (`  bundlepath NAME …`) are the ones an unknown command names.
TEST(ErrorMessages, AnUnknownCommandListsEveryCommand) {
  const CliResult help = run_cli("--help");
  std::set<std::string> commands;
  std::smatch m;
  for (const std::string& line : lines_of(help.output))
    if (std::regex_search(line, m, std::regex(R"(^  bundlepath ([a-z]+)\b)"))) commands.insert(m[1]);
  ASSERT_GE(commands.size(), 3u) << help.output;
  const CliResult r = run_cli("frobnicate");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << "one line: " << r.output;
  ASSERT_TRUE(std::regex_search(r.output, m, std::regex(R"(\(commands: ([a-z, ]+);)"))) << r.output;
  std::set<std::string> listed;
  const std::string list = m[1];
  const std::regex name("[a-z]+");
  for (std::sregex_iterator it(list.begin(), list.end(), name), end; it != end; ++it) listed.insert(it->str());
  EXPECT_EQ(listed, commands) << r.output;
}

}  // namespace
}  // namespace bp::test
