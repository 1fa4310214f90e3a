#!/usr/bin/env bash
# The README's main job: sets up (Debian packages, build), then meshes the real brain mask shipped with
# insighttoolkit5-examples at delta = 4 mm into brain.vtu, prints the quality report and writes it as
# brain-report.json.
# Usage: scripts/run-sample.sh [OUTPUT_DIRECTORY]   (default: the repository root)
set -euo pipefail

repository=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_directory=${DELAUNAY_BUILD_DIR:-$repository/build}
output_directory=${1:-$repository}
brain_mask=/usr/share/doc/insighttoolkit5-examples/examples/Data/KmeansTest_T1RawSkullStrip.nii.gz

bash "$repository/scripts/setup.sh"

mkdir -p "$output_directory"
output_directory=$(cd "$output_directory" && pwd)
mesh="$output_directory/brain.vtu"
report="$output_directory/brain-report.json"

echo "== Meshing $brain_mask"
echo "   (128 x 128 x 62 voxels of 2 x 2 x 3 mm; labels 4, 5 and 6 are brain, meshed as one object; delta = 4 mm)"
"$build_directory/bin/delaunay-image-to-mesh" "$brain_mask" "$mesh" --delta 4 --merge-labels --distance --report "$report"

echo
echo "== Done"
echo "   mesh:   $mesh"
echo "           tetrahedra with their label as the cell array 'label' (ParaView, meshio, VTK)"
echo "   report: $report"
echo "   pictures of the mesh (needs python3-vtk9, python3-matplotlib and, without a display, xvfb):"
echo "     xvfb-run -a /usr/bin/python3 $repository/examples/render_mesh.py $mesh --surface brain-surface.png --cut brain-cut.png"
echo "     /usr/bin/python3 $repository/examples/plot_dihedral_histogram.py $report brain-min-dihedral-histogram.png"
