#!/usr/bin/env bash
# Fuzzes itk::DelaunayImageToMeshFilter for SECONDS seconds (default 60): fuzz/run.sh [SECONDS] [libFuzzer flags]
# Builds the target first (fuzz/build.sh). The seed corpus fuzz/corpus/ is read, never written: what the run
# learns goes to build-fuzz/corpus/, crashes and timeouts to build-fuzz/artifacts/. Rerun one of them with
#   build-fuzz/DelaunayImageToMeshFuzzer build-fuzz/artifacts/crash-...
set -euo pipefail

repository=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_directory=${DELAUNAY_FUZZ_BUILD_DIR:-$repository/build-fuzz}
seconds=${1:-60}
shift || true

bash "$repository/fuzz/build.sh"
mkdir -p "$build_directory/corpus" "$build_directory/artifacts"

# detect_leaks: leaks are findings too. The limits: the header and a 16^3 image fit in 4120 bytes; a run of the
# filter on such an image takes well under a second, so 60 s is a hang; 4 GB of memory is a leak or a blow-up.
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:symbolize=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
exec "$build_directory/DelaunayImageToMeshFuzzer" \
  -max_total_time="$seconds" -max_len=4120 -timeout=60 -rss_limit_mb=4096 -print_final_stats=1 \
  -artifact_prefix="$build_directory/artifacts/" \
  "$@" "$build_directory/corpus" "$repository/fuzz/corpus"
