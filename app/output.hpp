#pragma once
// Writing files for the user: all or nothing (a temporary file renamed into place), so a failed command never
// leaves a half-written file behind.
#include <string>

namespace polarcam::cli {

void write_file_atomic(const std::string& path, const std::string& content);

// "1234567" -> "1,234,567"
std::string thousands(unsigned long long v);

}  // namespace polarcam::cli
