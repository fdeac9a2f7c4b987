#!/usr/bin/env bash
# First command of README.md: install the dependencies, build polarcam, and digitize the bundled limacon example.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
bash scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build --parallel "$(nproc)"
./build/polarcam digitize examples/limacon.toml -o limacon.tape
