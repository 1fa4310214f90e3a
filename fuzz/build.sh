#!/usr/bin/env bash
# Builds the libFuzzer target into build-fuzz/ (or $DELAUNAY_FUZZ_BUILD_DIR) with clang, AddressSanitizer and
# UndefinedBehaviorSanitizer. Installs clang and libFuzzer from Debian when they are missing.
set -euo pipefail

repository=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_directory=${DELAUNAY_FUZZ_BUILD_DIR:-$repository/build-fuzz}

# libFuzzer ships in libclang-rt-14-dev (Debian 12); clang-14 is the compiler that matches it.
if ! command -v clang++-14 >/dev/null || [ ! -f /usr/lib/llvm-14/lib/clang/14.0.6/lib/linux/libclang_rt.fuzzer-x86_64.a ]; then
  sudo_prefix=""
  [ "$(id -u)" -eq 0 ] || sudo_prefix="sudo"
  $sudo_prefix apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_prefix apt-get install -y -qq clang-14 libclang-rt-14-dev >/dev/null
fi

cmake -S "$repository/fuzz" -B "$build_directory" \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_C_COMPILER=clang-14 -DCMAKE_CXX_COMPILER=clang++-14 >/dev/null
cmake --build "$build_directory" -j"${DELAUNAY_FUZZ_JOBS:-2}"
echo "== Built $build_directory/DelaunayImageToMeshFuzzer"
