#pragma once
// Telling a step tape from other inputs: commands that take a job, a pattern or a tape (preview, servo) read a
// file as a tape when it is named *.tape or begins with the tape's magic bytes (docs/tape-format.md), whatever its
// name (`polarcam dda -o limacon.dda` writes a tape too).
#include <string>

namespace polarcam {

// True when `path` ends in ".tape" or the file begins with the tape's magic; false otherwise (also when it cannot
// be read: the reader that follows names the problem).
bool is_tape_file(const std::string& path);

}  // namespace polarcam
