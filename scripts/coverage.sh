#!/usr/bin/env bash
# Line coverage of the library, the ITK classes and the command-line program by the whole CTest suite: which code no
# test runs, so that a deliberate bug there could not be caught (the mutation check's blind spots).
#
#   scripts/coverage.sh [BUILD_DIRECTORY]   # default: build-coverage beside the checkout's build
#
# Builds the project with gcc's --coverage into its own directory (Release, so the suite takes about as long as
# usual; lines are then attributed to the code the optimiser kept, close enough to find what never runs), runs the
# suite, and prints every source file's covered share and every line no test ran. Needs gcovr (Debian: gcovr).
# Parallel tests update the same counters, so a few branch counts come out negative: gcovr is told to ignore them
# (branches are not reported, lines are).
set -euo pipefail

repository=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-"$repository/build-coverage"}
command -v gcovr >/dev/null || {
  echo "coverage: gcovr is missing (apt-get install gcovr)" >&2
  exit 1
}

cmake -S "$repository" -B "$build" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS=--coverage \
  -DCMAKE_EXE_LINKER_FLAGS=--coverage -DCMAKE_SHARED_LINKER_FLAGS=--coverage >/dev/null
cmake --build "$build" -j"$(nproc)"
find "$build" -name '*.gcda' -delete
(cd "$build" && ctest -j"$(nproc)" --timeout 1500 --output-on-failure)

report="$build/coverage.json"
gcovr -r "$repository" --gcov-ignore-parse-errors --filter "$repository/src/" --filter "$repository/include/" \
  --filter "$repository/examples/" --json -o "$report" "$build" 2>/dev/null
python3 - "$repository" "$report" <<'PYTHON'
import json
import sys

repository, report = sys.argv[1:3]
covered_in_all = lines_in_all = 0
for entry in sorted(json.load(open(report))["files"], key=lambda entry: entry["file"]):
    lines = [line for line in entry["lines"] if not line.get("gcovr/noncode")]
    missed = [line["line_number"] for line in lines if line["count"] == 0]
    covered_in_all += len(lines) - len(missed)
    lines_in_all += len(lines)
    print(f"{entry['file']:60s} {len(lines) - len(missed):5d} / {len(lines):5d} lines run")
    source = open(f"{repository}/{entry['file']}", encoding="utf-8").read().split("\n")
    for number in missed:
        print(f"    never run {number:5d}: {source[number - 1].strip()[:100]}")
print(f"all: {covered_in_all} of {lines_in_all} lines run ({100.0 * covered_in_all / max(lines_in_all, 1):.1f} %)")
PYTHON
