#include "io/output.hpp"

#include "cam/format.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <streambuf>
#include <vector>

#include "cam/error.hpp"
#include "cam/input_file.hpp"
#include "cam/units.hpp"

namespace polarcam {
namespace {

std::string reason(int e) { return std::string(" (") + std::strerror(e) + ")"; }

// The standard stream (0, 1, 2) this process has open on the same file, or -1.
int standard_stream(const struct stat& st) {
  for (int fd = 0; fd <= 2; ++fd) {
    struct stat s {};
    if (::fstat(fd, &s) == 0 && s.st_dev == st.st_dev && s.st_ino == st.st_ino) return fd;
  }
  return -1;
}
bool is_standard_stream(const struct stat& st) { return standard_stream(st) >= 0; }

// Where a finished output goes. Renamed (`rename_to` set): a new file, or a regular file (through a link: the
// file it names, so the link stays). Written through (`rename_to` empty): anything else that is not a directory.
std::string rename_target(const std::string& path) {
  struct stat ls {}, st {};
  if (::lstat(path.c_str(), &ls) != 0) {
    if (errno != ENOENT) throw DeviceError("cannot write here" + reason(errno), path);
    std::filesystem::path dir = std::filesystem::path(path).parent_path();
    if (dir.empty()) dir = ".";
    struct stat ds {};
    if (::stat(dir.c_str(), &ds) != 0)
      throw DeviceError("the directory " + dir.string() + " does not exist: create it or write elsewhere", path);
    if (!S_ISDIR(ds.st_mode)) throw DeviceError(dir.string() + " is not a directory", path);
    return path;
  }
  if (::stat(path.c_str(), &st) != 0) return {};  // a dangling link: written through (creates what it names)
  if (S_ISDIR(st.st_mode)) throw DeviceError("is a directory: give a file name", path);
  if (S_ISREG(ls.st_mode)) return path;
  if (S_ISLNK(ls.st_mode) && S_ISREG(st.st_mode) && !is_standard_stream(st)) {
    char* real = ::realpath(path.c_str(), nullptr);
    if (real) {
      std::string r(real);
      std::free(real);
      return r;
    }
  }
  return {};
}

// Writes the bytes of the open file `from` (from its start) into `path`, opened for appending without replacing it.
void write_through(std::FILE* from, const std::string& path) {
  if (std::fseek(from, 0, SEEK_SET) != 0) throw DeviceError("cannot read back the temporary file" + reason(errno), path);
  // the standard output or error by another name: written through that descriptor, after what is buffered for
  // it, so that the two share one file position
  struct stat st {};
  const int stream = ::stat(path.c_str(), &st) == 0 ? standard_stream(st) : -1;
  if (stream == 1) std::fflush(stdout);
  if (stream == 2) std::fflush(stderr);
  const int fd = stream > 0 ? ::dup(stream) : ::open(path.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0666);
  if (fd < 0) throw DeviceError("cannot open for writing" + reason(errno), path);
  char buf[1 << 16];
  for (;;) {
    const size_t n = std::fread(buf, 1, sizeof buf, from);
    for (size_t done = 0; done < n;) {
      const ssize_t w = ::write(fd, buf + done, n - done);
      if (w < 0 && errno == EINTR) continue;
      if (w <= 0) {
        const int e = w < 0 ? errno : EIO;
        ::close(fd);
        throw DeviceError("cannot write" + reason(e), path);
      }
      done += static_cast<size_t>(w);
    }
    if (n < sizeof buf) break;
  }
  const bool read_error = std::ferror(from) != 0;
  if (::close(fd) != 0 && errno != EINTR) throw DeviceError("cannot write" + reason(errno), path);
  if (read_error) throw DeviceError("cannot read back the temporary file", path);
}

std::string through_temporary() {
  static std::atomic<unsigned> counter{0};
  std::error_code ec;
  std::filesystem::path dir = std::filesystem::temp_directory_path(ec);
  if (ec) dir = "/tmp";
  return (dir / ("polarcam-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + ".partial")).string();
}

}  // namespace

void check_output_path(const std::string& path) {
  if (path.empty()) throw DeviceError("the output file name is empty");
  (void)rename_target(path);
}

void check_output_extension(const std::string& path, std::initializer_list<const char*> extensions,
                            const std::string& what) {
  if (output_writes_through(path)) return;
  const std::string ext = lower_extension(path);
  std::string names;
  for (const char* e : extensions) {
    if (ext == e) return;
    names += std::string(names.empty() ? "" : " or ") + e;
  }
  throw InputError(what + " is written as " + names + ": give the file that extension", path);
}

bool output_writes_through(const std::string& path) { return rename_target(path).empty(); }

std::optional<uint64_t> regular_file_size(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return std::nullopt;
  return static_cast<uint64_t>(st.st_size);
}

OutputFile::OutputFile(std::string path) : path_(std::move(path)) {
  if (path_.empty()) throw DeviceError("the output file name is empty");
  rename_to_ = rename_target(path_);
  through_ = rename_to_.empty();
  tmp_ = std::make_unique<TempFile>(through_ ? through_temporary()
                                             : rename_to_ + ".partial-" + std::to_string(::getpid()));
  f_ = std::fopen(tmp_->path().c_str(), through_ ? "w+b" : "wb");
  if (!f_) {
    const int e = errno;
    tmp_.reset();
    throw DeviceError("cannot create the file" + reason(e), path_);
  }
}

OutputFile::~OutputFile() {
  if (f_) std::fclose(f_);
}

void OutputFile::commit() {
  if (!f_) throw DeviceError("the file was already written", path_);
  if (through_) {
    bool ok = std::fflush(f_) == 0 && !std::ferror(f_);
    const int e = errno;
    if (!ok) throw DeviceError("cannot write the temporary file" + reason(e), path_);
    write_through(f_, path_);
    std::fclose(f_);
    f_ = nullptr;
    tmp_.reset();
    return;
  }
  bool ok = std::fflush(f_) == 0 && !std::ferror(f_);
  int e = errno;
  ok = (std::fclose(f_) == 0) && ok;
  if (!ok && e == 0) e = errno;
  f_ = nullptr;
  if (!ok) throw DeviceError("cannot write the file" + reason(e), path_);
  if (std::rename(tmp_->path().c_str(), rename_to_.c_str()) != 0)
    throw DeviceError("cannot move the finished file into place" + reason(errno), path_);
  tmp_->keep();
  tmp_.reset();
}

// A stream buffer over the OutputFile's FILE*: writes in blocks of 64 KiB; a short write fails the stream.
class OutputStream::Buffer : public std::streambuf {
 public:
  explicit Buffer(std::FILE* f) : f_(f), block_(1 << 16) { setp(block_.data(), block_.data() + block_.size()); }
  uint64_t bytes() const { return written_ + static_cast<uint64_t>(pptr() - pbase()); }
  int error() const { return errno_; }

 protected:
  int_type overflow(int_type ch) override {
    if (!drain()) return traits_type::eof();
    if (traits_type::eq_int_type(ch, traits_type::eof())) return traits_type::not_eof(ch);
    *pptr() = traits_type::to_char_type(ch);
    pbump(1);
    return ch;
  }
  int sync() override { return drain() ? 0 : -1; }

 private:
  bool drain() {
    const size_t n = static_cast<size_t>(pptr() - pbase());
    if (n > 0 && std::fwrite(pbase(), 1, n, f_) != n) {
      if (!errno_) errno_ = errno ? errno : EIO;
      return false;
    }
    written_ += n;
    setp(block_.data(), block_.data() + block_.size());
    return true;
  }
  std::FILE* f_;
  std::vector<char> block_;
  uint64_t written_ = 0;
  int errno_ = 0;
};

OutputStream::OutputStream(std::string path)
    : file_(std::move(path)), buf_(std::make_unique<Buffer>(file_.stream())), os_(std::make_unique<std::ostream>(buf_.get())) {}

OutputStream::~OutputStream() = default;

std::ostream& OutputStream::stream() { return *os_; }

uint64_t OutputStream::bytes() const { return buf_->bytes(); }

void OutputStream::commit() {
  os_->flush();
  if (!*os_) throw DeviceError("cannot write the file" + (buf_->error() ? reason(buf_->error()) : std::string()), file_.path());
  file_.commit();
}

void copy_to_output(const std::string& from, const std::string& path) {
  std::FILE* in = std::fopen(from.c_str(), "rb");
  if (!in) throw DeviceError("cannot read the temporary file " + from + reason(errno), path);
  try {
    OutputFile out(path);
    char buf[1 << 16];
    size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, in)) > 0)
      if (std::fwrite(buf, 1, n, out.stream()) != n) throw DeviceError("cannot write" + reason(errno), path);
    if (std::ferror(in)) throw DeviceError("cannot read the temporary file " + from, path);
    out.commit();
  } catch (...) {
    std::fclose(in);
    throw;
  }
  std::fclose(in);
}

}  // namespace polarcam

namespace polarcam::cli {

void write_file_atomic(const std::string& path, const std::string& content) {
  OutputFile out(path);
  if (std::fwrite(content.data(), 1, content.size(), out.stream()) != content.size())
    throw DeviceError("cannot write the file" + reason(errno), path);
  out.commit();
}

void write_files_atomic(const std::vector<std::pair<std::string, std::string>>& files) {
  std::vector<std::unique_ptr<OutputFile>> outs;
  for (const auto& [path, content] : files) {
    outs.push_back(std::make_unique<OutputFile>(path));
    if (std::fwrite(content.data(), 1, content.size(), outs.back()->stream()) != content.size())
      throw DeviceError("cannot write the file" + reason(errno), path);
  }
  // the outputs written through (a device, a FIFO) first: a copy into one can fail (a full device) after its
  // temporary was written, a rename over a file hardly, so a failure leaves every file output as it was
  for (auto& out : outs)
    if (out->writes_through()) out->commit();
  for (auto& out : outs)
    if (!out->writes_through()) out->commit();
}

std::string thousands(unsigned long long v) {
  std::string s = std::to_string(v), out;
  int n = 0;
  for (auto it = s.rbegin(); it != s.rend(); ++it) {
    if (n && n % 3 == 0) out.insert(out.begin(), ',');
    out.insert(out.begin(), *it);
    ++n;
  }
  return out;
}

std::string significant(double v, int digits) { return polarcam::significant(v, digits); }

double parse_rate_option(const std::string& text) {
  try {
    Quantity q = parse_quantity(text);
    if (q.dim != dim::none && q.dim != dim::frequency) throw InputError("'" + text + "' is not a frequency");
    if (!(q.value > 0.0) || q.value > 1e9) throw InputError("the interrupt rate must be above 0 and up to 1 GHz");
    return q.value;
  } catch (const InputError& e) {
    throw InputError(std::string("--rate: ") + e.what());
  }
}

}  // namespace polarcam::cli
