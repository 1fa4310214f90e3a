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
"""Every topology option of the command line reaches the filter and does what it says (docs/algorithm.md,
"Topology"), seen in the JSON report, whose parameters the program reads back from the filter and whose "topology"
object says what each step did.

ITK's k-means tissues at delta = 6 mm (twice the largest spacing) need every step: the defaults change voxels at
pinches, remove components thinner than the scale, relabel tetrahedra, make regularisation rounds and refine a thick
part. The test first asserts that they do (else the image no longer tests anything), then turns each step off alone
and asserts that exactly that step did nothing, with the option recorded. The opt-in halving of delta and the vertex
cap are checked as recorded parameters on the k-means tissues, where the rounds leave nothing to halve.

An iso-surface of ITK's raw T1 image (interpolated labels, whose regularised voxels carry their side into the gray
values) must be a closed manifold with the defaults, checked from the file by the independent checker, and the
regularisation must have worked for it; with the voxels as they are and no rounds it keeps non-manifold places (else
it tests nothing), and there the halving itself is checked: it must run and leave fewer.

What the regularisation changed is also said in the summary the program prints without --quiet: the voxels changed at
pinches, the tetrahedra relabelled, the rounds of halving and the places left, each line checked against the report.

Usage: DelaunayImageToMeshCommandLineTopologyOptions.py PROGRAM OUTPUT_DIRECTORY EXAMPLES_DATA"""

import os
import re
import sys

from DelaunayImageToMeshCommandLineIndependentQuality import KMEANS_TISSUES as KMEANS_TISSUES_AND_SELECTION
from DelaunayImageToMeshCommandLineIndependentQuality import check_mesh
from DelaunayImageToMeshCommandLineTesting import check, mesh_and_report, mesh_report_and_summary

# The real-image cases' k-means file and tissue selection, written once there.
KMEANS_TISSUES, TISSUES = KMEANS_TISSUES_AND_SELECTION
DELTA = ["--delta", "6"]
# A gray image, meshed where its linearly interpolated value is >= 60. Before its voxels were regularised, 23
# non-manifold vertices were left at 4.5 mm, as many as with the voxels as they are and no rounds now.
RAW_T1 = "KmeansTest_T1UCharRaw.nii.gz"
ISO_SURFACE = ["--iso", "60", "--delta", "4.5"]
VOXELS_AS_THEY_ARE = ["--regularization-scale", "0", "--keep-diagonal-voxels", "--topology-rounds", "0"]

# The filter's defaults, as the report must record them when no option is given.
DEFAULT_PARAMETERS = {
    "labels": [2, 3, 4, 5, 6],
    "merge_labels": False,
    "iso_value": None,
    "max_vertices": 10_000_000,
    "regularization_scale": 0.4,
    "join_diagonal_voxels": True,
    "relabel_non_manifold_places": True,
    "topology_rounds": 20,
    "refine_thick_parts": True,
    "manifold_refinement_levels": 0,
}


def components_removed(report):
    return sum(label["regularization"]["components_removed"] for label in report["labels"])


def volume_regularised(report):
    return sum(label["regularization"]["volume_removed_mm3"] + label["regularization"]["volume_added_mm3"]
               for label in report["labels"])


# What each step did, read from a report: (name, work).
STEPS = {
    "regularisation at the scale of delta": lambda report: components_removed(report) + volume_regularised(report),
    "voxel pinches": lambda report: report["topology"]["voxels_changed_at_pinches"],
    "relabelling at non-manifold places": lambda report: report["topology"]["relabelled_tetrahedra"],
    "regularisation rounds": lambda report: (report["topology"]["regularization_rounds"] +
                                            report["topology"]["locally_regularized_voxels"]),
    "thick-part refinement": lambda report: report["topology"]["thick_parts_refined"],
}

# Each option that turns one step off: (options, the step, the parameters it must record).
OPTIONS_OFF = [
    (["--regularization-scale", "0"], "regularisation at the scale of delta", {"regularization_scale": 0.0}),
    (["--keep-diagonal-voxels"], "voxel pinches", {"join_diagonal_voxels": False}),
    (["--no-topology-relabelling"], "relabelling at non-manifold places", {"relabel_non_manifold_places": False}),
    (["--topology-rounds", "0"], "regularisation rounds", {"topology_rounds": 0}),
    (["--no-thick-part-refinement"], "thick-part refinement", {"refine_thick_parts": False}),
]


def check_summary_line(summary, pattern, expected, what):
    """The summary the program prints must hold a line matching `pattern` whose first number is `expected`: what the
    regularisation changed is said on the console too, not only in the JSON report."""
    found = re.search(pattern, summary)
    check(found is not None, f"{what}: no line matching '{pattern}' in what the program printed:\n{summary}")
    check(int(found.group(1)) == expected, f"{what}: the program printed '{found.group(0)}', the report says {expected}")


def check_parameters(report, expected, what):
    parameters = report["parameters"]
    for key, value in expected.items():
        check(key in parameters and parameters[key] == value,
              f"{what}: the report's parameter {key} is {parameters.get(key, 'missing')!r}, expected {value!r}")


def main(program, output, examples_data):
    image = os.path.join(examples_data, KMEANS_TISSUES)
    _, default, summary = mesh_report_and_summary(program, image, output, "defaults", options=TISSUES + DELTA,
                                                  quiet=False)
    check_parameters(default, DEFAULT_PARAMETERS, "the defaults")
    check_summary_line(summary, r"removed voxel pinches \([^)]*\): (\d+) voxels changed label",
                       default["topology"]["voxels_changed_at_pinches"], "the defaults")
    check_summary_line(summary, r"relabelled at non-manifold places: (\d+) tetrahedra took a neighbour's label",
                       default["topology"]["relabelled_tetrahedra"], "the defaults")
    for step, work in STEPS.items():
        check(work(default) > 0, f"with the defaults the {step} did nothing on {KMEANS_TISSUES} at 6 mm: the image "
              f"no longer tests the option that turns it off ({default['topology']})")
    print("defaults:", default["topology"])

    for options, step_off, recorded in OPTIONS_OFF:
        what = " ".join(options)
        _, report = mesh_and_report(program, image, output, options[0].lstrip("-"), options=TISSUES + DELTA + options)
        check_parameters(report, {**DEFAULT_PARAMETERS, **recorded}, what)
        check(STEPS[step_off](report) == 0, f"{what}: the {step_off} still worked ({report['topology']}, "
              f"{components_removed(report)} components removed)")
        print(f"{what}: the {step_off} did nothing; {report['tetrahedra']} tetrahedra against "
              f"{default['tetrahedra']}")

    opt_in = ["--manifold-levels", "2", "--max-vertices", "900000", "--labels", "2,3"]
    _, report = mesh_and_report(program, image, output, "opt-in", options=DELTA + opt_in)
    check_parameters(report, {**DEFAULT_PARAMETERS, "labels": [2, 3], "manifold_refinement_levels": 2,
                              "max_vertices": 900_000}, " ".join(opt_in))
    check(sorted(label["label"] for label in report["labels"]) == [2, 3],
          f"--labels 2,3: the report's labels are {[label['label'] for label in report['labels']]}")

    # An iso-surface: the regularisation reaches it through the values, and the defaults give a closed manifold.
    raw_t1 = os.path.join(examples_data, RAW_T1)
    iso_mesh, iso = mesh_and_report(program, raw_t1, output, "iso", options=ISO_SURFACE)
    print(check_mesh(iso_mesh, iso, 2.0, 10.0, manifold_promised=True))
    check(iso["topology"]["voxels_changed_at_pinches"] > 0 and components_removed(iso) > 0,
          f"{RAW_T1} {' '.join(ISO_SURFACE)}: the pinch removal or the opening did nothing ({iso['topology']}, "
          f"{components_removed(iso)} components removed): the iso-surface was not regularised")

    # The halving where the rounds cannot mend a place: with the voxels as they are and no rounds.
    plain_options = ISO_SURFACE + VOXELS_AS_THEY_ARE
    _, plain, plain_summary = mesh_report_and_summary(program, raw_t1, output, "iso-plain", options=plain_options,
                                                      quiet=False)
    check(plain["quality"]["non_manifold_vertices"] > 0, f"{RAW_T1} {' '.join(plain_options)} is a closed manifold "
          "without the halving: it no longer tests it")
    check(plain["topology"]["manifold_refinement_rounds"] == 0 and plain["topology"]["regularization_rounds"] == 0,
          f"{RAW_T1} {' '.join(plain_options)}: without --manifold-levels {plain['topology']}")
    # The places left are said, with the option that refines around them.
    check("; --manifold-levels 2 refines around them" in plain_summary and
          re.search(r"non-manifold places left \(a vertex and a label each\): [1-9]", plain_summary) is not None,
          f"{RAW_T1} {' '.join(plain_options)}: the places left are not said:\n{plain_summary}")
    halving = ["--manifold-levels", "2"]
    _, halved, halved_summary = mesh_report_and_summary(program, raw_t1, output, "iso-halved",
                                                        options=plain_options + halving, quiet=False)
    check_summary_line(halved_summary, r"halved delta around non-manifold places: (\d+) rounds",
                       halved["topology"]["manifold_refinement_rounds"], " ".join(plain_options + halving))
    check_parameters(halved, {"iso_value": 60.0, "manifold_refinement_levels": 2}, " ".join(plain_options + halving))
    check(halved["topology"]["manifold_refinement_rounds"] > 0,
          f"{' '.join(plain_options + halving)}: delta was never halved ({halved['topology']})")
    check(halved["quality"]["non_manifold_vertices"] < plain["quality"]["non_manifold_vertices"],
          f"{' '.join(plain_options + halving)}: {halved['quality']['non_manifold_vertices']} non-manifold vertices, "
          f"{plain['quality']['non_manifold_vertices']} without the halving")
    print(f"iso-surface: closed manifold with the defaults ({iso['tetrahedra']} tetrahedra); with the voxels as they "
          f"are {plain['quality']['non_manifold_vertices']} non-manifold vertices, "
          f"{halved['quality']['non_manifold_vertices']} after {halved['topology']['manifold_refinement_rounds']} "
          f"rounds of halving; {halved['tetrahedra']} tetrahedra against {plain['tetrahedra']}")

if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    main(*sys.argv[1:])
