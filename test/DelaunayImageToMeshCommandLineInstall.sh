#!/bin/sh
# Installs the build tree into a scratch prefix and runs the installed program: `cmake --install` must put
# delaunay-image-to-mesh into PREFIX/bin, where it must start.
# Usage: DelaunayImageToMeshCommandLineInstall.sh BUILD_DIRECTORY SCRATCH_PREFIX
set -eu
build_directory=$1
prefix=$2
rm -rf "$prefix"
cmake --install "$build_directory" --prefix "$prefix" >/dev/null
program="$prefix/bin/delaunay-image-to-mesh"
[ -x "$program" ] || { echo "not installed: $program" >&2; exit 1; }
"$program" --version
