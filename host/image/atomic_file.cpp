#include "image/atomic_file.h"

#include <unistd.h>

#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace bp {

void write_file_atomically(const std::string& path, const std::string& what,
                           const std::function<void(const std::string&)>& write) {
  const std::string temporary = path + ".tmp-" + std::to_string(::getpid());
  auto fail = [&](const std::string& reason) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw std::runtime_error("cannot write " + what + " '" + path + "': " + reason);
  };
  try {
    write(temporary);
  } catch (const std::exception& e) {
    fail(e.what());
  }
  std::error_code ec;
  std::filesystem::rename(temporary, path, ec);
  if (ec) fail("rename from '" + temporary + "' failed: " + ec.message());
}

}  // namespace bp
