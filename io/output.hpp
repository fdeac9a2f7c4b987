#pragma once
// Writing files for the user: all or nothing (a temporary file renamed into place), so a failed command never
// leaves a half-written file behind.
#include <string>

namespace polarcam::cli {

void write_file_atomic(const std::string& path, const std::string& content);

// "1234567" -> "1,234,567"
std::string thousands(unsigned long long v);

// v to `digits` significant digits, as a stream prints it by default ("0.0254", "1.5e+06")
std::string significant(double v, int digits);

// The value of --rate: "5000", "5000 Hz", "5 kHz" (above 0, up to 1 GHz); InputError naming the option otherwise.
double parse_rate_option(const std::string& text);

}  // namespace polarcam::cli
