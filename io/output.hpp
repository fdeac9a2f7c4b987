#pragma once
// Writing files for the user: all or nothing, so a failed or interrupted command never leaves a half-written file.
// A regular file (or a new one) is written to a temporary file beside it and renamed into place; a device, FIFO,
// socket or a name for one of the process's own streams (/dev/stdout) is written through, never replaced. Every
// failure to write (a full disk, a closed pipe, a missing directory, a directory given as a file) is a
// DeviceError naming the output (exit status 3).
#include <cstdint>
#include <cstdio>
#include <initializer_list>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "io/temp_files.hpp"

namespace polarcam {

// Checks, before any work, that `path` can be an output: not a directory, in a directory that exists.
// DeviceError naming the path otherwise.
void check_output_path(const std::string& path);

// Checks that `path` names a file of one of `extensions` (".html", lower case; compared ignoring case), for an output
// written in that format: InputError naming the path and `what` ("the report", written as the first extension)
// otherwise. A device, FIFO or socket (written through, output_writes_through) takes any name.
void check_output_extension(const std::string& path, std::initializer_list<const char*> extensions,
                            const std::string& what);

// True when `path` names something written through rather than replaced (a device, FIFO, socket, or a link to
// one of the process's own standard streams).
bool output_writes_through(const std::string& path);

// The size of a regular file, none for anything else (a device, a FIFO).
std::optional<uint64_t> regular_file_size(const std::string& path);

// An output written in pieces (a tape): the pieces go to a seekable temporary file, and commit() puts the whole
// in place (renamed over a regular file; copied into a device or FIFO). Destroyed without commit(): the temporary
// is removed and the output untouched.
class OutputFile {
 public:
  explicit OutputFile(std::string path);  // DeviceError as check_output_path, or when the temporary cannot be made
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;
  std::FILE* stream() const { return f_; }  // the temporary, open for writing; the caller checks its writes
  const std::string& path() const { return path_; }
  // Flushes and closes the temporary (every write checked), then puts it in place. DeviceError naming the output.
  void commit();
  // True when commit() copies into a device, FIFO or socket rather than renaming over a file.
  bool writes_through() const { return through_; }

 private:
  std::string path_, rename_to_;
  bool through_ = false;
  std::unique_ptr<TempFile> tmp_;
  std::FILE* f_ = nullptr;
};

// An output written as a stream (an export of any size): the bytes go through a buffer straight into an
// OutputFile, so nothing holds the whole. commit() flushes, checks every write and puts the file in place;
// destroyed without commit(), the output is untouched. A failed write sets the stream's badbit and commit()
// throws the DeviceError.
class OutputStream {
 public:
  explicit OutputStream(std::string path);
  ~OutputStream();
  OutputStream(const OutputStream&) = delete;
  OutputStream& operator=(const OutputStream&) = delete;
  std::ostream& stream();
  uint64_t bytes() const;  // written so far
  void commit();

 private:
  class Buffer;
  OutputFile file_;
  std::unique_ptr<Buffer> buf_;
  std::unique_ptr<std::ostream> os_;
};

// Copies the file `from` into the output `path` (as OutputFile does).
void copy_to_output(const std::string& from, const std::string& path);

}  // namespace polarcam

namespace polarcam::cli {

// `content` into `path` through an OutputFile.
void write_file_atomic(const std::string& path, const std::string& content);

// Several outputs of one command (path, content), all or nothing: every one written to its temporary file first,
// then all put in place, those written through (devices, FIFOs) before those renamed over files, so that a device
// that fails (a full one) leaves every file output untouched.
void write_files_atomic(const std::vector<std::pair<std::string, std::string>>& files);

// "1234567" -> "1,234,567"
std::string thousands(unsigned long long v);

// v to `digits` significant digits, as a stream prints it by default ("0.0254", "1.5e+06")
std::string significant(double v, int digits);

// The value of --rate: "5000", "5000 Hz", "5 kHz" (above 0, up to 1 GHz); InputError naming the option otherwise.
double parse_rate_option(const std::string& text);

}  // namespace polarcam::cli
