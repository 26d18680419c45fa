#include "image/stats_io.h"
#include "image/atomic_file.h"

#include <fstream>
#include <stdexcept>

namespace bp {

void write_json_file(const std::string& path, const nlohmann::json& value) {
  write_file_atomically(path, "stats file", [&](const std::string& tmp) {
    std::ofstream out(tmp);
    out << value.dump(2) << '\n';
    if (!out) throw std::runtime_error("cannot write " + tmp);
  });
}

}  // namespace bp
