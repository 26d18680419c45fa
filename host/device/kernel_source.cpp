#include "device/kernel_source.h"
#include "device/embedded_kernels.h"

#include <set>
#include <sstream>
#include <stdexcept>

namespace bp {
namespace {

const char* find_embedded(const std::string& path) {
  for (const EmbeddedFile& f : embedded_kernel_files())
    if (path == f.path) return f.text;
  return nullptr;
}

void append_file(const std::string& path, std::set<std::string>& included, std::string& out) {
  if (!included.insert(path).second) return;  // every header has include guards; inline once
  const char* text = find_embedded(path);
  if (!text) throw std::runtime_error("kernel source '" + path + "' is not embedded in this binary");
  std::istringstream lines(text);
  std::string line;
  int number = 0;
  out += "#line 1 \"kernels/" + path + "\"\n";
  while (std::getline(lines, line)) {
    ++number;
    auto first = line.find_first_not_of(" \t");
    if (first != std::string::npos && line.compare(first, 8, "#include") == 0) {
      auto open = line.find('"', first), close = line.rfind('"');
      if (open != std::string::npos && close > open) {
        append_file(line.substr(open + 1, close - open - 1), included, out);
        out += "#line " + std::to_string(number + 1) + " \"kernels/" + path + "\"\n";
        continue;
      }
    }
    out += line;
    out += '\n';
  }
}

}  // namespace

std::string assemble_kernel_source(const std::string& main_file) {
  std::set<std::string> included;
  std::string out;
  append_file(main_file, included, out);
  return out;
}

}  // namespace bp
