#!/usr/bin/env bash
# Second command of README.md: build (if needed) and run the whole test suite.
# SANITIZE=1 builds and runs it under AddressSanitizer + UndefinedBehaviorSanitizer with clang in build-asan/, the
# directory the libFuzzer harnesses of scripts/fuzz.sh share (scripts/configure-sanitized.sh).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
bash scripts/install-deps.sh
if [ "${SANITIZE:-0}" = 1 ]; then
  dir=build-asan
  bash scripts/configure-sanitized.sh "$dir"
  export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
else
  dir=build
  cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=Release
fi
cmake --build "$dir" --parallel "$(nproc)"
ctest --test-dir "$dir" --output-on-failure --parallel "$(nproc)" --timeout 600
