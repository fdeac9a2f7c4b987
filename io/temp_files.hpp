#pragma once
// Temporary files that an interrupted run must not leave behind. Every temporary file polarcam makes (an output
// being written before it is renamed into place, a tape measured and thrown away, a plot being rendered) is a
// TempFile while it exists; the handlers that remove_temporaries_on_signal() installs remove all of them when
// SIGINT, SIGTERM or SIGHUP arrives, then end the process by that same signal, as if it had not been caught.
#include <string>

namespace polarcam {

// Installs the handlers (once, from main()). A signal the process was started ignoring stays ignored.
void remove_temporaries_on_signal();

// A temporary file's name, registered while the object lives. The destructor removes the file unless keep() was
// called (the file was renamed into place). Without a free slot (more than 64 at once) or with a name longer than
// 4095 bytes the file is not registered: it is still removed by the destructor, but not on a signal.
class TempFile {
 public:
  explicit TempFile(std::string path);
  ~TempFile();
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  const std::string& path() const { return path_; }
  // The file is not temporary any more: forget it without removing it.
  void keep();

 private:
  std::string path_;
  int slot_ = -1;
  bool kept_ = false;
};

// How many temporary files are registered now (for tests).
int registered_temporaries();

}  // namespace polarcam
