# ==========================================================================
#
#   Copyright NumFOCUS
#
#   Licensed under the Apache License, Version 2.0 (the "License");
#   you may not use this file except in compliance with the License.
#   You may obtain a copy of the License at
#
#          http://www.apache.org/licenses/LICENSE-2.0.txt
#
#   Unless required by applicable law or agreed to in writing, software
#   distributed under the License is distributed on an "AS IS" BASIS,
#   WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
#   See the License for the specific language governing permissions and
#   limitations under the License.
#
# ==========================================================================
"""A tissue the mesh loses reads as lost, in the table and in the JSON report: speck.nii.gz holds two balls and
label 3, two face-adjacent voxels of 1 x 1.25 x 1.5 mm, far thinner than the default delta (6 mm). Its row must
say "lost: 1 component, 3.8 mm^3", and its JSON entry "lost": true with the component and the volume, never the
angle or the genus of its empty boundary. A selected label that no voxel carries is named as such.

Usage: DelaunayImageToMeshCommandLineLostTissue.py PROGRAM IMAGE_DIRECTORY OUTPUT_DIRECTORY"""

import json
import math
import os
import sys

from DelaunayImageToMeshCommandLineTesting import check, describe, remove_if_present, run

SPECK_LABEL = 3
SPECK_VOLUME = 2 * 1.0 * 1.25 * 1.5


def main(program, images, output):
    os.makedirs(output, exist_ok=True)
    report_path = os.path.join(output, "speck.json")
    unregularized_path = os.path.join(output, "speck-unregularized.json")
    selected_path = os.path.join(output, "speck-selected.json")
    # A run in a build tree that already holds an earlier run's reports must write them again to pass.
    remove_if_present(report_path, unregularized_path, selected_path, os.path.join(output, "speck-absent.vtu"))
    result = run(program, [os.path.join(images, "speck.nii.gz"), os.path.join(output, "speck.vtu"), "--report",
                           report_path])
    check(result.returncode == 0, describe(result))
    with open(report_path, encoding="utf-8") as file:
        report_of_all_labels = json.load(file)
    labels = {entry["label"]: entry for entry in report_of_all_labels["labels"]}

    check(sorted(labels) == [1, 2, SPECK_LABEL], f"labels in the report: {sorted(labels)}")
    speck = labels[SPECK_LABEL]
    check(speck["tetrahedra"] == 0, f"the premise failed: label 3 was meshed at the default delta: {speck}")
    check(speck["lost"] is True and speck["lost_components"] == 1, f"label 3 not reported as lost: {speck}")
    check(math.isclose(speck["lost_volume_mm3"], SPECK_VOLUME, rel_tol=1e-9), f"lost volume: {speck}")
    check(speck["min_planar_angle_deg"] is None and speck["boundary_genus"] is None,
          f"an empty boundary was given an angle or a genus: {speck}")
    for label in (1, 2):
        check(labels[label]["lost"] is False and "lost_components" not in labels[label],
              f"meshed label {label} reported as lost: {labels[label]}")
    # What left it is said too: the regularisation at the scale of delta removed its one component (both voxels),
    # so no part of it was left for the mesh to miss.
    regularization = speck["regularization"]
    check(regularization["components_removed"] == 1, f"label 3's component not reported as regularised away: {speck}")
    check(math.isclose(regularization["volume_removed_mm3"], SPECK_VOLUME, rel_tol=1e-9)
          and regularization["volume_added_mm3"] == 0, f"label 3's regularised volume: {speck}")
    check(speck["parts_without_tetrahedra"] == 0, f"a part of label 3 left after the regularisation: {speck}")

    # Without the regularisation label 3's component reaches the mesher, which gives it no tetrahedron (both voxels
    # are far thinner than delta): still lost, and counted as a part the mesh left without a tetrahedron.
    unregularized = run(program, [os.path.join(images, "speck.nii.gz"), os.path.join(output, "speck-unregularized.vtu"),
                                  "--quiet", "--regularization-scale", "0", "--report", unregularized_path])
    check(unregularized.returncode == 0, describe(unregularized))
    with open(unregularized_path, encoding="utf-8") as file:
        unregularized_speck = {entry["label"]: entry for entry in json.load(file)["labels"]}[SPECK_LABEL]
    check(unregularized_speck["tetrahedra"] == 0 and unregularized_speck["lost"] is True and
          unregularized_speck["regularization"]["components_removed"] == 0,
          f"the premise failed: without the regularisation label 3 is {unregularized_speck}")
    check(unregularized_speck["parts_without_tetrahedra"] == 1 and
          math.isclose(unregularized_speck["parts_without_tetrahedra_mm3"], SPECK_VOLUME, rel_tol=1e-9),
          f"label 3's part without a tetrahedron not counted: {unregularized_speck}")

    rows = [line.split() for line in result.stdout.splitlines()]
    speck_rows = [row for row in rows if row[:3] == [str(SPECK_LABEL), "0", "0"]]
    check(len(speck_rows) == 1, f"expected one table row for label 3: {describe(result)}")
    # Columns: label, vertices, tetrahedra, triangles, mesh and voxel volumes, then components, genus,
    # non-manifold edges/vertices and min angle, which an empty boundary does not have.
    check(speck_rows[0][6:10] == ["-"] * 4, f"label 3's boundary columns should be '-': {speck_rows[0]}")
    check(speck_rows[0][10:] == ["lost:", "1", "component,", "3.8", "mm^3"],
          f"label 3's row should end with 'lost: 1 component, 3.8 mm^3': {speck_rows[0]}")
    check("180.00" not in result.stdout, f"an angle of an empty set is printed: {describe(result)}")
    check("LOST tissues                label 3 (1 component, 3.8 mm^3)" in result.stdout,
          f"the summary does not list the lost tissue: {describe(result)}")
    check("regularised at delta        1 component removed;" in result.stdout,
          f"the summary does not say what the regularisation removed: {describe(result)}")

    # A selected label that no voxel carries (label 9: mistyped, say) is not in the segmentation, so it cannot read
    # as lost; the summary and the JSON name it instead. Where none of the selected labels is there, the run fails
    # naming them, before any mesh file is written.
    selected = run(program, [os.path.join(images, "speck.nii.gz"), os.path.join(output, "speck-selected.vtu"),
                             "--labels", "2,9,1", "--report", selected_path])
    check(selected.returncode == 0, describe(selected))
    with open(selected_path, encoding="utf-8") as file:
        selected_report = json.load(file)
    check(selected_report["selected_labels_not_in_image"] == [9],
          f"label 9 not reported as not in the image: {selected_report['selected_labels_not_in_image']}")
    check(sorted(entry["label"] for entry in selected_report["labels"]) == [1, 2],
          f"labels in the report with --labels 2,9,1: {selected_report['labels']}")
    check("selected, NOT in image      label 9 (no voxel carries it)" in selected.stdout,
          f"the summary does not name label 9: {describe(selected)}")
    check(report_of_all_labels["selected_labels_not_in_image"] == [],
          f"labels not in the image reported without a selection: {report_of_all_labels}")
    absent_mesh = os.path.join(output, "speck-absent.vtu")
    absent = run(program, [os.path.join(images, "speck.nii.gz"), absent_mesh, "--labels", "11,9"])
    check(absent.returncode != 0 and "the selected labels not in the image: 9, 11" in absent.stderr,
          f"meshing only absent labels should fail naming them: {describe(absent)}")
    check(not os.path.exists(absent_mesh), "a mesh file was written for labels not in the image")
    print("label 3 (2 voxels) lost at the default delta: 'lost: 1 component, 3.8 mm^3' in the table and JSON, "
          "regularised away; selected label 9, not in the image, named in the summary and the JSON")


if __name__ == "__main__":
    main(*sys.argv[1:])
