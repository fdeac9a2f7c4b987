#pragma once
// The whole of a user's input file as bytes, for the parsers that take text (drives, simulation, chatter,
// signal and response files). InputError naming the file when it cannot be opened or read.
#include <fstream>
#include <sstream>
#include <string>

#include "cam/error.hpp"

namespace polarcam {

inline std::string read_input_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("cannot open the file", path);
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw InputError("cannot read the file", path);
  return std::move(ss).str();
}

}  // namespace polarcam
