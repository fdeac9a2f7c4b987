#pragma once
// The whole of a user's input file as bytes, for the parsers that take text (drives, simulation, chatter,
// signal and response files). InputError naming the file when it cannot be opened or read. And the kind of an
// input file by its name.
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "cam/error.hpp"

namespace polarcam {

// A directory given where a file is read: refused by name (an ifstream opens a directory and reads nothing, which
// the parsers would report as an empty or foreign file).
inline void refuse_directory(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError("is a directory: give the path of a file in it", path);
}

// An input file opened for reading (binary: on POSIX the same bytes as text mode): a directory refused as one, a
// file that cannot be opened with `cannot` naming it. Every reader of an input file by its name opens it here, so none
// forgets the directory.
inline std::ifstream open_input_file(const std::string& path, const std::string& cannot) {
  refuse_directory(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(cannot, path);
  return in;
}

inline std::string read_input_file(const std::string& path) {
  std::ifstream in = open_input_file(path, "cannot open the file");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw InputError("cannot read the file", path);
  return std::move(ss).str();
}

// The extension of a file's name in lower case (".thr" for "A.THR"), by which its kind is told; "" for none.
inline std::string lower_extension(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  return e;
}

}  // namespace polarcam
