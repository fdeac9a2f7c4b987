#pragma once
// Errors that polarcam reports to its user, typed: the kind of failure, the place it concerns (a file, FILE:LINE,
// a key, a record or an option) and what is wrong. The CLI maps the kind to the exit status in one place
// (exit_status below, called by app/main.cpp) and prints "polarcam: error: PLACE: MESSAGE" on one line. No code
// decides anything on the text of a message: it asks the kind and the place.
//
//   kind       exit status  meaning
//   input      2            bad input: a file, key, value, record or option; the message says what to change
//   device     3            I/O or device: a port that cannot be opened, a controller that stops answering
//   internal   4            a bug: anything else escaping to the CLI
#include <stdexcept>
#include <string>
#include <utility>

namespace polarcam {

enum class ErrorKind { input, device, internal };

// The documented exit status of each kind (0 is success, 1 a computed NO-GO; neither is an error).
constexpr int exit_status(ErrorKind k) {
  switch (k) {
    case ErrorKind::input: return 2;
    case ErrorKind::device: return 3;
    case ErrorKind::internal: return 4;
  }
  return 4;
}

class Error : public std::runtime_error {
 public:
  // what() is "PLACE: MESSAGE", or MESSAGE when the place is not known (yet).
  Error(ErrorKind kind, std::string message, std::string place = {})
      : std::runtime_error(place.empty() ? message : place + ": " + message),
        kind_(kind),
        place_(std::move(place)),
        message_(std::move(message)) {}

  ErrorKind kind() const noexcept { return kind_; }
  // The file, FILE:LINE, key, record or option the error concerns; empty when not known.
  const std::string& place() const noexcept { return place_; }
  // What is wrong and what to change, without the place.
  const std::string& message() const noexcept { return message_; }
  // True when the place starts with `file` (the error already names it).
  bool names(const std::string& file) const noexcept {
    return !file.empty() && place_.compare(0, file.size(), file) == 0;
  }

 protected:
  // The place with `file` in front, unless it already names that file.
  std::string place_in(const std::string& file) const {
    if (file.empty() || names(file)) return place_;
    return place_.empty() ? file : file + ": " + place_;
  }

 private:
  ErrorKind kind_;
  std::string place_;
  std::string message_;
};

// Bad input (exit status 2).
class InputError : public Error {
 public:
  explicit InputError(std::string message, std::string place = {})
      : Error(ErrorKind::input, std::move(message), std::move(place)) {}
  // The same error, placed in `file` (unless its place already names that file): for a reader that calls a
  // library on the contents of a file and knows the file's name.
  InputError in_file(const std::string& file) const { return InputError(message(), place_in(file)); }
};

// Runs f() and returns what it returns; an InputError it throws is placed in `file` (InputError::in_file).
template <class F>
decltype(auto) in_file(const std::string& file, F&& f) {
  try {
    return f();
  } catch (const InputError& e) {
    throw e.in_file(file);
  }
}

// An I/O or device failure (exit status 3).
class DeviceError : public Error {
 public:
  explicit DeviceError(std::string message, std::string place = {})
      : Error(ErrorKind::device, std::move(message), std::move(place)) {}
};

}  // namespace polarcam
