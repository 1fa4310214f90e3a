#!/usr/bin/env bash
# Installs the Debian packages the module needs (when missing), then configures and builds into build/.
# Safe to re-run: installed packages are skipped and the build is incremental (ccache when present).
set -euo pipefail

repository=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_directory=${DELAUNAY_BUILD_DIR:-$repository/build}

packages=(
  cmake g++ make ccache pkg-config
  libinsighttoolkit5-dev    # ITK 5.2.1
  libcgal-dev               # CGAL 5.5, header-only (pulls GMP and MPFR)
  libvtk9-dev               # VTK 9.1: .vtu/.vtk files, flying edges, rendering
  libgtest-dev              # GoogleTest
  libtbb-dev libeigen3-dev
  libcli11-dev              # CLI11 2.1, header-only: the command line's options, --help and --config files
  nlohmann-json3-dev        # nlohmann-json 3.11, header-only: the quality report's JSON, written and re-read
  insighttoolkit5-examples  # real segmented brain images for the tests and the sample run
  python3 python3-numpy python3-meshio python3-vtk9 python3-matplotlib xvfb  # tests re-read meshes (meshio, VTK); pictures
)
# DOLFINx 0.5.2 (FEniCSx, with PETSc 3.18) for the finite-element example and tests (issue #19). Installed without
# the recommended packages (Sphinx, Numba: none is needed): about 110 packages, 57 MB to download, 250 MB
# installed, a minute and a quarter here. Its forms are compiled at run time with gcc and Python's headers.
fem_packages=(python3-dolfinx)

missing_packages() {
  for package in "$@"; do
    dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" || echo "$package"
  done
}
mapfile -t missing < <(missing_packages "${packages[@]}")
mapfile -t missing_fem < <(missing_packages "${fem_packages[@]}")
if [ ${#missing[@]} -gt 0 ] || [ ${#missing_fem[@]} -gt 0 ]; then
  echo "== Installing Debian packages: ${missing[*]} ${missing_fem[*]}"
  sudo_prefix=""
  [ "$(id -u)" -eq 0 ] || sudo_prefix="sudo"
  $sudo_prefix apt-get update -qq
  if [ ${#missing[@]} -gt 0 ]; then
    DEBIAN_FRONTEND=noninteractive $sudo_prefix apt-get install -y -qq "${missing[@]}" >/dev/null
  fi
  if [ ${#missing_fem[@]} -gt 0 ]; then
    DEBIAN_FRONTEND=noninteractive $sudo_prefix apt-get install -y -qq --no-install-recommends "${missing_fem[@]}" \
      >/dev/null
  fi
fi

echo "== Configuring and building in $build_directory"
cmake -S "$repository" -B "$build_directory" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build_directory" -j"$(nproc)"
