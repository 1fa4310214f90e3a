#!/usr/bin/env bash
# Builds ITK 5.2.1 with Python wrapping from Debian's own source package, with this module enabled as a
# remote module inside that ITK tree, then runs the module's Python tests against it, and the registration test
# (test/Registration: ITK's PhysicsBasedNonRigidRegistrationMethod on the filter's mesh, issue #19) against a second,
# unwrapped tree of the same source with ITK's FEM modules, which Debian's ITK does not ship.
#
# Debian ships no wrapped ITK and no Python registry is reachable here, so this is the only way to prove the
# wrapping. The build is cached outside the repository (DELAUNAY_ITK_PYTHON_CACHE, default
# ~/.cache/delaunay-image-to-mesh/itk-python): a second run only rebuilds what changed. About an hour on
# 2 cores the first time (3-D only; unsigned char, short and float; the few modules the filter needs).
set -euo pipefail

repository=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cache=${DELAUNAY_ITK_PYTHON_CACHE:-$HOME/.cache/delaunay-image-to-mesh/itk-python}
build=$cache/build
fem_build=$cache/build-fem
python=/usr/bin/python3   # Debian's Python: it has Debian's NumPy

install_build_packages() {
  local packages=(dpkg-dev swig castxml python3-dev python3-numpy libcgal-dev libvtk9-dev libcli11-dev nlohmann-json3-dev cmake g++ make ccache)
  local missing=()
  for package in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" || missing+=("$package")
  done
  if [ ${#missing[@]} -gt 0 ]; then
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}" >/dev/null
  fi
}

enable_source_packages() {
  if ! grep -rqsE '^(Types:.*deb-src|deb-src )' /etc/apt/sources.list /etc/apt/sources.list.d/; then
    if [ -f /etc/apt/sources.list.d/debian.sources ]; then
      sed -i 's/^Types: deb$/Types: deb deb-src/' /etc/apt/sources.list.d/debian.sources
    else
      sed -n 's/^deb /deb-src /p' /etc/apt/sources.list >/etc/apt/sources.list.d/deb-src.list
    fi
    apt-get update -qq
  fi
}

fetch_itk_source() {
  if [ ! -d "$cache/source" ]; then
    enable_source_packages
    mkdir -p "$cache/download"
    (cd "$cache/download" && apt-get source -qq insighttoolkit5 >/dev/null)
    mv "$cache/download"/insighttoolkit5-*/ "$cache/source"
  fi
  # The module is built from this checkout, as a remote module of that ITK tree.
  ln -sfn "$repository" "$cache/source/Modules/Remote/DelaunayImageToMesh"
}

# What both trees share: a release build of only the modules asked for, shared libraries, no tests or examples.
itk_tree_options=(
  -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER_LAUNCHER=ccache
  -DBUILD_TESTING=OFF -DBUILD_EXAMPLES=OFF -DBUILD_SHARED_LIBS=ON -DITK_BUILD_DEFAULT_MODULES=OFF
  -DModule_DelaunayImageToMesh=ON
)

# Configures and builds one tree of the source: directory, log name, then its own options.
configure_and_build_tree() {
  local tree=$1 log=$2
  shift 2
  cmake -S "$cache/source" -B "$tree" "${itk_tree_options[@]}" "$@" >"$cache/$log-configure.log"
  cmake --build "$tree" -j"$(nproc)" >"$cache/$log-build.log" 2>&1 || { tail -40 "$cache/$log-build.log"; exit 1; }
}

# The wrapped tree. ITK 5.2's own wrapping (itkImageDuplicator.wrap) fails to configure when no vector pixel type is
# wrapped, so the default vector types stay on.
configure_and_build() {
  configure_and_build_tree "$build" python \
    -DModule_ITKMesh=ON -DModule_ITKImageFunction=ON \
    -DModule_ITKIONIFTI=ON -DModule_ITKBridgeNumPy=ON -DModule_ITKFEMRegistration=OFF \
    -DITK_WRAP_PYTHON=ON -DITK_WRAP_IMAGE_DIMS=3 \
    -DITK_WRAP_unsigned_char=ON -DITK_WRAP_signed_short=ON -DITK_WRAP_float=ON \
    -DITK_WRAP_unsigned_short=OFF -DITK_WRAP_double=OFF \
    -DITK_WRAP_vector_float=ON -DITK_WRAP_covariant_vector_float=ON \
    -DITK_USE_SYSTEM_SWIG=ON -DITK_USE_SYSTEM_CASTXML=ON \
    -DPython3_EXECUTABLE="$python"
}

# The registration test's tree: ITK's FEM registration and this module, unwrapped. Not the wrapped tree: the FEM
# modules pull in ITKImageGradient, whose wrapping fails to generate with the few pixel types wrapped here (an empty
# output type for GradientRecursiveGaussianImageFilter), and an unwrapped tree of these modules builds in minutes.
configure_and_build_fem() {
  configure_and_build_tree "$fem_build" fem \
    -DModule_ITKFEMRegistration=ON -DModule_ITKImageGrid=ON \
    -DModule_ITKIONIFTI=ON -DModule_ITKIONRRD=ON -DModule_ITKIOMeta=ON \
    -DITK_WRAP_PYTHON=OFF
}

# ITK 5.2.1's Python still says numpy.bool, which NumPy 1.24 (Debian 12) removed.
# On a rerun the files are patched already and grep finds nothing, which must not stop the script (pipefail).
restore_numpy_bool() {
  { grep -rlE 'np\.bool\b|numpy\.bool\b' "$build/Wrapping/Generators/Python/itk" 2>/dev/null || true; } |
    xargs -r sed -i -E 's/\b(np|numpy)\.bool\b([^_])/\1.bool_\2/g'
}

run_python_tests() {
  export PYTHONPATH="$build/Wrapping/Generators/Python:$build/lib${PYTHONPATH:+:$PYTHONPATH}"
  export LD_LIBRARY_PATH="$build/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
  "$python" -c "import itk; filter = itk.DelaunayImageToMeshFilter.New(); print('import itk: ok')"
  "$python" "$repository/wrapping/test/delaunay_image_to_mesh_test.py"
}

# Issue #19: ITK's physics-based non-rigid registration fed with the filter's mesh, built from test/Registration
# against the FEM tree (Debian's ITK has no FEM modules) and run on the ITK example brain.
run_registration_test() {
  local registration_build=$cache/registration-build
  cmake -S "$repository/test/Registration" -B "$registration_build" -DITK_DIR="$fem_build" \
    -DCMAKE_CXX_COMPILER_LAUNCHER=ccache >"$cache/registration-configure.log"
  cmake --build "$registration_build" -j"$(nproc)" >"$cache/registration-build.log" 2>&1 ||
    { tail -40 "$cache/registration-build.log"; exit 1; }
  local data=/usr/share/doc/insighttoolkit5-examples/examples/Data
  mkdir -p "$registration_build/output"
  LD_LIBRARY_PATH="$fem_build/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" \
    "$registration_build/DelaunayImageToMeshPhysicsBasedRegistration" \
    "$data/KmeansTest_T1UCharRaw.nii.gz" "$data/KmeansTest_T1RawSkullStrip.nii.gz" 6 "$registration_build/output"
}

start=$(date +%s)
install_build_packages
fetch_itk_source
configure_and_build
configure_and_build_fem
restore_numpy_bool
# Marks a finished build: the test command only uses a cache that has one (a build in progress has the
# Python package directories already).
touch "$cache/build-complete"
run_python_tests
echo "== ITK's physics-based registration on the filter's mesh (issue #19)"
run_registration_test
echo "== ITK Python build and tests done in $(( $(date +%s) - start )) s (cache: $cache)"
