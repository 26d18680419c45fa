// Run statistics as JSON, written atomically (temporary file, then rename).
#pragma once
#include <nlohmann/json.hpp>
#include <string>

namespace bp {

// Throws std::runtime_error naming the file if it cannot be written.
void write_json_file(const std::string& path, const nlohmann::json& value);

}  // namespace bp
