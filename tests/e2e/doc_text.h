// Reading the repository's Markdown for the documentation tests (test_docs, test_error_messages).
#pragma once
#include <filesystem>
#include <string>
#include <vector>

namespace bp::test {

// The whole file (empty when it cannot be read).
std::string read_text(const std::filesystem::path& path);
std::vector<std::string> lines_of(const std::string& text);
// The lines of a Markdown file's section, from its heading (a whole line, e.g. "## Exit codes") to
// the next heading of its level or above.
std::vector<std::string> section(const std::string& markdown, const std::string& heading);

}  // namespace bp::test
