#include "e2e/doc_text.h"

#include <fstream>
#include <sstream>

namespace bp::test {

std::string read_text(const std::filesystem::path& path) {
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

std::vector<std::string> section(const std::string& markdown, const std::string& heading) {
  std::vector<std::string> out;
  bool inside = false;
  const std::size_t level = heading.find(' ');
  for (const std::string& line : lines_of(markdown)) {
    if (line == heading) {
      inside = true;
      continue;
    }
    if (!inside) continue;
    bool higher = false;
    for (std::size_t l = 1; l <= level; ++l) higher = higher || line.rfind(std::string(l, '#') + " ", 0) == 0;
    if (higher) break;
    out.push_back(line);
  }
  return out;
}

}  // namespace bp::test
