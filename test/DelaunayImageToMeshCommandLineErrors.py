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
line on stderr, "delaunay-image-to-mesh: error: ...", naming the problem. --help and --version exit with 0.

Usage: DelaunayImageToMeshCommandLineErrors.py PROGRAM IMAGE_DIRECTORY OUTPUT_DIRECTORY"""

import os
import re
import sys

from DelaunayImageToMeshCommandLineTesting import PROGRAM_NAME, check, describe, run

OPTIONS = ["--delta", "--radius-edge", "--min-dihedral", "--labels", "--merge-labels", "--keep-diagonal-voxels", "--iso",
           "--max-vertices", "--report", "--quiet", "--version", "--help"]


def error_cases(image, output):
    """(arguments, what the message must name) for each mistake."""
    mesh = os.path.join(output, "mesh.vtu")
    not_an_image = os.path.join(output, "not-an-image.nii")
    empty_directory = os.path.join(output, "empty-directory")
    with open(not_an_image, "w", encoding="utf-8") as file:
        file.write("this is text, not an image\n")
    os.makedirs(empty_directory, exist_ok=True)
    return [
        ([image, mesh, "--frobnicate"], "unknown option '--frobnicate'"),
        ([image, mesh, "--delta"], "option --delta needs a value"),
        ([image, mesh, "--delta", "-1"], "--delta must be a distance > 0 in mm, got '-1'"),
        ([image, mesh, "--delta", "two"], "--delta needs a number, got 'two'"),
        ([image, mesh, "--radius-edge", "0.5"], "--radius-edge must be >= 1, got '0.5'"),
        ([image, mesh, "--min-dihedral", "45"], "--min-dihedral must be in [0, 30] degrees, got '45'"),
        ([image, mesh, "--labels", "1,x"], "--labels needs 'all' or comma-separated integer labels"),
        ([image, mesh, "--labels", "0,1"], "--labels cannot select label 0"),
        ([image, mesh, "--max-vertices", "-5"], "--max-vertices must be a whole number >= 8, got '-5'"),
        ([image, mesh, "--iso", "1", "--labels", "1"], "--iso cannot be combined with --labels or --merge-labels"),
        ([image, mesh, "--iso", "1", "--merge-labels"], "--iso cannot be combined with --labels or --merge-labels"),
        ([image, mesh, "--quiet=yes"], "option --quiet takes no value"),
        ([image], "missing OUTPUT"),
        ([image, mesh, "surplus"], "unexpected argument 'surplus'"),
        ([os.path.join(output, "missing.nii.gz"), mesh], "cannot read input '" + os.path.join(output, "missing.nii.gz")
         + "': No such file or directory"),
        ([not_an_image, mesh], "cannot read input '" + not_an_image + "': not an image format ITK can read"),
        ([empty_directory, mesh], "the directory holds no DICOM series"),
        ([image, os.path.join(output, "mesh.stl")], "unsupported output extension '.stl'"),
        ([image, os.path.join(output, "no-such-directory", "mesh.vtu")], "directory '" +
         os.path.join(output, "no-such-directory") + "' does not exist"),
        ([image, mesh, "--report", os.path.join(output, "no-such-directory", "r.json")], "cannot write the report"),
        ([image, mesh, "--labels", "99"], "meshing failed: No voxel of the input is part of the object"),
        ([image, mesh, "--delta", "1", "--max-vertices", "20"], "meshing failed"),
    ]


def check_error(program, arguments, expected, mesh):
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
    check("4 x the largest voxel spacing" in help_result.stdout, "--help does not give the default --delta")
    version = run(program, ["--version"])
    check(version.returncode == 0 and version.stderr == "", f"--version: {describe(version)}")
    check(re.fullmatch(PROGRAM_NAME + r" \d+\.\d+\.\d+ \(ITK \d+\.\d+\.\d+\)\n", version.stdout),
          f"--version: {describe(version)}")


def main(program, image_directory, output):
    os.makedirs(output, exist_ok=True)
    image = os.path.join(image_directory, "labels.nii.gz")
    mesh = os.path.join(output, "mesh.vtu")
    cases = error_cases(image, output)
    for arguments, expected in cases:
        check_error(program, arguments, expected, mesh)
    check_help_and_version(program)
    print(f"{len(cases)} mistakes rejected with exit code 2 and one line each; --help and --version exit with 0")


if __name__ == "__main__":
    main(*sys.argv[1:])
