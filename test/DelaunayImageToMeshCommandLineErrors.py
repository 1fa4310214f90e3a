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
"""Every way to call the program wrongly must end with exit code 2, nothing on stdout, no output file, and one
line on stderr, "delaunay-image-to-mesh: error: ...", naming the problem (and the option), also when the mistake is
in a --config file. --help and -h, --version and -V exit with 0.

Usage: DelaunayImageToMeshCommandLineErrors.py PROGRAM IMAGE_DIRECTORY OUTPUT_DIRECTORY"""

import os
import re
import sys

from DelaunayImageToMeshCommandLineTesting import PROGRAM_NAME, check, describe, run

OPTIONS = ["--delta", "--radius-edge", "--min-dihedral", "--labels", "--merge-labels", "--keep-diagonal-voxels", "--iso",
           "--max-vertices", "--regularization-scale", "--topology-rounds", "--no-topology-relabelling",
           "--no-thick-part-refinement", "--manifold-levels", "--distance", "--report", "--quiet", "--version", "--help",
           "--config", "-d,", "-q,", "-V,", "-h,"]
GROUPS = ["Meshing:", "Tissues:", "Output:"]


def error_cases(image, output):
    """(arguments, what the message must name) for each mistake."""
    mesh = os.path.join(output, "mesh.vtu")

    def beside(name):
        return os.path.join(os.path.dirname(image), name)

    not_an_image = os.path.join(output, "not-an-image.nii")
    empty_directory = os.path.join(output, "empty-directory")
    with open(not_an_image, "w", encoding="utf-8") as file:
        file.write("this is text, not an image\n")
    os.makedirs(empty_directory, exist_ok=True)
    sheared = write_sheared_image(output)
    # A 2-D image read as 3-D would be meshed as a slab one voxel thick, and a 4-D image of two time points as its
    # first volume alone: both are refused (a 4-D file of one time point is a 3-D image: the Inputs test).
    flat = write_cube_image(output, "flat.mha", [10, 10])
    two_time_points = write_cube_image(output, "two-time-points.mha", [10, 10, 10, 2])
    bad_delta = write_config(output, "bad-delta.toml", "delta = -1\n")
    misspelt = write_config(output, "misspelt.toml", "delt = 2\n")
    # The ranges are the refinement core's (ValidateParameters): its message follows the option's name.
    return [
        ([image, mesh, "--frobnicate"], "The following argument was not expected: --frobnicate"),
        ([image, mesh, "--delta"], "--delta: 1 required MM missing"),
        ([image, mesh, "--delta", "-1"], "--delta: Invalid parameter surfaceSamplingDistance (delta) = -1: the valid "
         "range is (0, "),
        ([image, mesh, "-d", "0"], "--delta: Invalid parameter surfaceSamplingDistance (delta) = 0: the valid range "
         "is (0, "),
        ([image, mesh, "--delta", "two"], "Could not convert: --delta = two"),
        ([image, mesh, "--radius-edge", "0.5"], "--radius-edge: Invalid parameter radiusEdgeBound (rho) = 0.5: the "
         "valid range is [1, +inf)"),
        ([image, mesh, "--min-dihedral", "45"], "--min-dihedral: Invalid parameter minimumDihedralAngle (sigma, "
         "degrees) = 45: the valid range is [0, 20]"),
        ([image, mesh, "--min-dihedral", "20.5"], "--min-dihedral: Invalid parameter minimumDihedralAngle (sigma, "
         "degrees) = 20.5: the valid range is [0, 20]"),
        ([image, mesh, "--labels", "1,x"], "--labels: needs 'all' or comma-separated integer labels such as 1,2 (0, "
         "the background, cannot be selected), got 'x'"),
        ([image, mesh, "--labels", "0,1"], "--labels: needs 'all' or comma-separated integer labels such as 1,2 (0, "
         "the background, cannot be selected), got '0'"),
        ([image, mesh, "--max-vertices", "-5"], "--max-vertices: needs a whole number, got '-5'"),
        ([image, mesh, "--max-vertices", "5"], "--max-vertices: Invalid parameter maximumNumberOfVertices = 5: the "
         "valid range is [8, "),
        ([image, mesh, "--regularization-scale", "0.7"], "--regularization-scale: a number in [0, 0.5], got '0.7'"),
        ([image, mesh, "--topology-rounds", "21"], "--topology-rounds: Invalid parameter topologyRegularizationRounds "
         "= 21: the valid range is [0, 20]"),
        ([image, mesh, "--manifold-levels", "11"], "--manifold-levels: Invalid parameter manifoldRefinementLevels = 11: "
         "the valid range is [0, 10]"),
        ([image, mesh, "--iso", "nan"], "--iso: needs a finite number, got 'nan'"),
        ([image, mesh, "--iso", "1", "--labels", "1"], "--labels excludes --iso"),
        ([image, mesh, "--iso", "1", "--merge-labels"], "--merge-labels excludes --iso"),
        ([image, mesh, "--quiet=yes"], "quiet was given a disallowed flag override"),
        ([image], "OUTPUT is required"),
        ([image, mesh, "surplus"], "The following argument was not expected: surplus"),
        ([image, mesh, "--config", bad_delta], "--delta: Invalid parameter surfaceSamplingDistance (delta) = -1"),
        ([image, mesh, "--config", misspelt], "INI was not able to parse delt"),
        ([image, mesh, "--config", os.path.join(output, "missing.toml")], os.path.join(output, "missing.toml") +
         " was not readable"),
        ([os.path.join(output, "missing.nii.gz"), mesh], "cannot read input '" + os.path.join(output, "missing.nii.gz")
         + "': No such file or directory"),
        ([not_an_image, mesh], "cannot read input '" + not_an_image + "': not an image format ITK can read"),
        ([empty_directory, mesh], "the directory holds no DICOM series"),
        ([image, os.path.join(output, "mesh.stl")], "OUTPUT: unsupported output extension '.stl'"),
        ([image, os.path.join(output, "no-such-directory", "mesh.vtu")], "OUTPUT: directory '" +
         os.path.join(output, "no-such-directory") + "' does not exist"),
        ([image, mesh, "--report", os.path.join(output, "no-such-directory", "r.json")], "--report: directory '" +
         os.path.join(output, "no-such-directory") + "' does not exist"),
        ([image, mesh, "--labels", "99"], "meshing failed: No voxel of the input is part of the object"),
        # Values no label can hold are refused, not wrapped or clamped into another tissue; colours are not labels.
        ([beside("labels-uint32-beyond.nrrd"), mesh], "The input image holds the value 4000000000 at index"),
        ([beside("labels-uint32-beyond.nrrd"), mesh], "labels are the integers in [-2147483647, 2147483647]"),
        ([beside("labels-int64-beyond.nrrd"), mesh], "The input image holds the value 8589934593 at index"),
        ([beside("labels-vector.nrrd"), mesh], "cannot mesh input '" + beside("labels-vector.nrrd") +
         "': its voxels have 3 components"),
        ([flat, mesh], "cannot mesh input '" + flat + "': it is a 2-D image, a 3-D image is needed"),
        ([two_time_points, mesh], "cannot mesh input '" + two_time_points + "': it is a 4-D image, a 3-D image is "
         "needed"),
        # Distances are measured along the voxel axes: a sheared grid is refused, not meshed wrongly.
        ([sheared, mesh], "meshing failed: The input image's direction (rows) [[1, 0.5, 0], [0, 1, 0], [0, 0, 1]] is "
         "not orthonormal"),
        ([image, mesh, "--delta", "1", "--max-vertices", "20"],
         "meshing failed: Delaunay refinement reached maximumNumberOfVertices = 20 vertices"),
    ]


def write_sheared_image(directory):
    """A MetaImage of a 6-voxel cube of label 1 in a 10^3 grid whose second axis leans on the first: direction
    columns (1, 0, 0) and (0.5, 1, 0), as a CT gantry tilt gives."""
    return write_cube_image(directory, "sheared.mha", [10, 10, 10],
                            "ElementSpacing = 1 1 1\nOffset = 0 0 0\nTransformMatrix = 1 0 0 0.5 1 0 0 0 1\n")


def write_cube_image(directory, name, sizes, geometry=""):
    """A MetaImage of the given sizes (2 to 4 axes), label 1 on voxels 2 to 7 of the first three axes, else 0;
    `geometry` holds header lines such as the spacing and the direction."""
    path = os.path.join(directory, name)
    header = (f"ObjectType = Image\nNDims = {len(sizes)}\nBinaryData = True\nBinaryDataByteOrderMSB = False\n"
              f"DimSize = {' '.join(str(size) for size in sizes)}\n{geometry}ElementType = MET_UCHAR\n"
              "ElementDataFile = LOCAL\n")
    count = 1
    for size in sizes:
        count *= size
    voxels = bytearray(count)
    for index in range(count):
        coordinates = []
        rest = index
        for size in sizes:
            coordinates.append(rest % size)
            rest //= size
        voxels[index] = 1 if all(2 <= c < 8 for c in coordinates[:3]) else 0
    with open(path, "wb") as file:
        file.write(header.encode("ascii") + bytes(voxels))
    return path


def write_config(directory, name, text):
    path = os.path.join(directory, name)
    with open(path, "w", encoding="utf-8") as file:
        file.write(text)
    return path


def check_error(program, arguments, expected, mesh):
    # A mesh left by an earlier run (one that met a deliberate bug, say) would fail every call below, and a mesh one
    # call wrote would be blamed on the next: each call is checked against an empty place.
    if os.path.exists(mesh):
        os.remove(mesh)
    result = run(program, arguments)
    call = " ".join(str(argument) for argument in arguments)
    check(result.returncode == 2, f"'{call}': expected exit code 2; {describe(result)}")
    check(result.stdout == "", f"'{call}': printed on stdout; {describe(result)}")
    # Progress lines may come first when the failure happens while meshing.
    lines = [line for line in result.stderr.splitlines() if not re.fullmatch(r"progress: \d{1,3}%", line)]
    check(len(lines) == 1, f"'{call}': expected one line on stderr besides progress; {describe(result)}")
    check(lines[0].startswith(f"{PROGRAM_NAME}: error: "), f"'{call}': not an error line; {describe(result)}")
    check(expected in lines[0], f"'{call}': the message should say \"{expected}\"; {describe(result)}")
    check(not os.path.exists(mesh), f"'{call}': wrote {mesh} despite the error")


def check_help_and_version(program):
    help_result = run(program, ["--help"])
    check(help_result.returncode == 0 and help_result.stderr == "", f"--help: {describe(help_result)}")
    for option in OPTIONS:
        check(option in help_result.stdout, f"--help does not mention {option}: {describe(help_result)}")
    for group in GROUPS:
        check(f"\n{group}\n" in help_result.stdout, f"--help has no option group {group}: {describe(help_result)}")
    check("4 x the largest voxel spacing" in help_result.stdout, "--help does not give the default --delta")
    short_help = run(program, ["-h"])
    check(short_help.returncode == 0 and short_help.stdout == help_result.stdout, f"-h: {describe(short_help)}")
    version = run(program, ["--version"])
    check(version.returncode == 0 and version.stderr == "", f"--version: {describe(version)}")
    check(re.fullmatch(PROGRAM_NAME + r" \d+\.\d+\.\d+ \(ITK \d+\.\d+\.\d+\)\n", version.stdout),
          f"--version: {describe(version)}")
    short_version = run(program, ["-V"])
    check(short_version.returncode == 0 and short_version.stdout == version.stdout, f"-V: {describe(short_version)}")


def main(program, image_directory, output):
    os.makedirs(output, exist_ok=True)
    image = os.path.join(image_directory, "labels.nii.gz")
    mesh = os.path.join(output, "mesh.vtu")
    cases = error_cases(image, output)
    for arguments, expected in cases:
        check_error(program, arguments, expected, mesh)
    check_help_and_version(program)
    print(f"{len(cases)} mistakes rejected with exit code 2 and one line each; -h, --help, -V and --version exit with 0")


if __name__ == "__main__":
    main(*sys.argv[1:])
