#pragma once
// Errors that polarcam reports to its user. InputError is bad input (a file, a key, a value): the CLI prints its
// message on one line and exits with status 2. Anything else escaping to the CLI is an internal error.
#include <stdexcept>
#include <string>

namespace polarcam {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace polarcam
