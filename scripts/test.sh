#!/usr/bin/env bash
# Sets up (packages, build) and runs every test. This is the README's test command and what CI runs.
set -euo pipefail

repository=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_directory=${DELAUNAY_BUILD_DIR:-$repository/build}

bash "$repository/scripts/setup.sh"
echo "== Running the tests"
ctest --test-dir "$build_directory" --output-on-failure -j"$(nproc)" --timeout 1800
