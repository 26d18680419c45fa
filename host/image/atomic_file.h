// Atomic file output: write "<path>.tmp-<pid>", then rename it over <path>, so a failed or
// interrupted write never leaves a partial file under the final name.
#pragma once
#include <functional>
#include <string>

namespace bp {

// Calls write(temporary_path), then renames the temporary file to path. Any failure (including an
// exception from write) removes the temporary file and throws std::runtime_error naming path.
void write_file_atomically(const std::string& path, const std::string& what,
                           const std::function<void(const std::string& temporary_path)>& write);

}  // namespace bp
