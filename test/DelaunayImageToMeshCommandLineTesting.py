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
"""What the command-line tests share: running the program, reading its report, checking with messages."""

import json
import math
import os
import subprocess

PROGRAM_NAME = "delaunay-image-to-mesh"

# Analytic volumes of the generated label image (DelaunayImageToMeshCommandLineGenerateImages.cxx): label 2 is a
# ball of radius 5 mm; label 1 a ball of radius 7 mm whose centre is 8 mm away, minus the lens it shares with it.
_LENS = math.pi * (7 + 5 - 8) ** 2 * (8**2 + 2 * 8 * (7 + 5) - 3 * (7 - 5) ** 2) / (12 * 8)
BALL_VOLUMES = {1: 4 / 3 * math.pi * 7**3 - _LENS, 2: 4 / 3 * math.pi * 5**3}
# gray.mha with --iso 92: a ball of radius 8 mm.
ISO_BALL_VOLUME = 4 / 3 * math.pi * 8**3


class CheckFailed(AssertionError):
    pass


def check(condition, message):
    if not condition:
        raise CheckFailed(message)


def run(program, arguments):
    """Runs the program with stdout and stderr captured (so stderr is not a terminal)."""
    return subprocess.run([program] + [str(argument) for argument in arguments], capture_output=True, text=True,
                          timeout=600)


def describe(result):
    return f"exit code {result.returncode}\nstdout:\n{result.stdout}\nstderr:\n{result.stderr}"


def remove_if_present(*paths):
    """Removes each file that exists, so that a check reads what the run being checked wrote."""
    for path in paths:
        if os.path.exists(path):
            os.remove(path)


def mesh_report_and_summary(program, image, directory, name, extension="vtu", options=(), quiet=True):
    """Meshes `image` into directory/name.extension with a JSON report, with --quiet unless `quiet` is False;
    returns (mesh path, report, what the program printed on stdout)."""
    os.makedirs(directory, exist_ok=True)
    mesh_path = os.path.join(directory, f"{name}.{extension}")
    report_path = os.path.join(directory, f"{name}.json")
    # A run in a build tree that already holds the files of an earlier run must write them again to pass.
    remove_if_present(mesh_path, report_path)
    result = run(program, [image, mesh_path, "--report", report_path, *(["--quiet"] if quiet else []), *options])
    check(result.returncode == 0, f"meshing {image} {' '.join(options)} failed: {describe(result)}")
    if quiet:
        check(result.stdout == "" and result.stderr == "", f"--quiet printed something: {describe(result)}")
    with open(report_path, encoding="utf-8") as file:
        return mesh_path, json.load(file), result.stdout


def mesh_and_report(program, image, directory, name, extension="vtu", options=()):
    """Meshes `image` quietly into directory/name.extension with a JSON report; returns (mesh path, report)."""
    mesh_path, report, _ = mesh_report_and_summary(program, image, directory, name, extension, options)
    return mesh_path, report


def tetrahedra_per_label(report):
    return {entry["label"]: entry["tetrahedra"] for entry in report["labels"] if entry["tetrahedra"] > 0}


def relative_difference(value, reference):
    return abs(value - reference) / abs(reference)
