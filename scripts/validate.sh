#!/usr/bin/env bash
# Runs polarcam on the source documents' worked cases and compares with their printed values.
#   bash scripts/validate.sh [POLARCAM]        (default ./build/polarcam; run from the repository's root)
# Every part scripts/validate/*.sh (one per document) prints one JSON object per line,
#   {"id": ..., "paper": ..., "polarcam": ..., "unit": ...}
# and writes its markdown section; this driver collects the sections into docs/validation.md (written whole,
# replacing the old file only when every part succeeded).
set -euo pipefail
cd "$(dirname "$0")/.."
POLARCAM=${1:-./build/polarcam}
[ -x "$POLARCAM" ] || { echo "validate.sh: no polarcam executable at $POLARCAM (build it, or give its path)" >&2; exit 2; }
command -v jq >/dev/null || { echo "validate.sh: needs jq (scripts/deps.txt)" >&2; exit 2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
{
  echo "# Validation against the source documents"
  echo
  echo "Written by \`scripts/validate.sh\`, which runs \`polarcam\` on each document's worked cases. \"paper\" is"
  echo "the value as printed, \"polarcam\" what the program computes, the difference is relative to the paper."
  echo "Where they differ by more than the printed rounding, the last column says why (docs/process.md has the"
  echo "corrections in full)."
} > "$tmp/validation.md"
for part in scripts/validate/*.sh; do
  echo >> "$tmp/validation.md"
  bash "$part" "$POLARCAM" "$tmp/validation.md"
done
mv "$tmp/validation.md" docs/validation.md.tmp && mv docs/validation.md.tmp docs/validation.md
