#!/usr/bin/env bash
# Configures the sanitized build directory (default build-asan/) that serves both the ASan+UBSan run of the test
# suite (SANITIZE=1 scripts/test.sh) and the libFuzzer harnesses (scripts/fuzz.sh): clang-14, -O1 -g1 (line tables
# for the reports, a lighter compile), AddressSanitizer + UndefinedBehaviorSanitizer everywhere, libFuzzer's
# coverage instrumentation in the libraries (POLARCAM_FUZZ). One build for both saves CI a third compile of the
# libraries. ccache is used when the environment names it (CMAKE_CXX_COMPILER_LAUNCHER=ccache).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
dir="${1:-build-asan}"
log="$(mktemp)"
if ! cmake -S . -B "$dir" -G Ninja -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" -DPOLARCAM_FUZZ=ON -DPOLARCAM_BUILD_BENCH=OFF > "$log" 2>&1; then
  cat "$log"
  rm -f "$log"
  exit 1
fi
rm -f "$log"
