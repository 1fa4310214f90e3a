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
"""The short options (-d, -q) and --config files (TOML and INI) reach the filter as the long options do: each
run is compared with the same parameters given as long options on the command line, and the command line wins
over the file.

Usage: DelaunayImageToMeshCommandLineConfig.py PROGRAM IMAGE_DIRECTORY OUTPUT_DIRECTORY"""

import json
import os
import sys

from DelaunayImageToMeshCommandLineTesting import check, describe, mesh_and_report, run, tetrahedra_per_label


def summary(report):
    return (report["parameters"], report["vertices"], report["tetrahedra"], tetrahedra_per_label(report))


def run_quietly(program, arguments, report_path):
    """Runs the program, which must print nothing (its --quiet coming from `arguments` or a config file)."""
    result = run(program, arguments)
    check(result.returncode == 0, f"{arguments}: {describe(result)}")
    check(result.stdout == "" and result.stderr == "", f"{arguments}: printed something although quiet: "
          f"{describe(result)}")
    with open(report_path, encoding="utf-8") as file:
        return json.load(file)


def write(path, text):
    with open(path, "w", encoding="utf-8") as file:
        file.write(text)
    return path


def check_short_forms(program, image, output):
    _, long_form = mesh_and_report(program, image, output, "long", options=["--delta", "2"])
    report_path = os.path.join(output, "short.json")
    short_form = run_quietly(program, [image, os.path.join(output, "short.vtu"), "-d", "2", "-q", "--report",
                                       report_path], report_path)
    check(short_form["parameters"]["delta_mm"] == 2, f"-d 2: {short_form['parameters']}")
    check(summary(short_form) == summary(long_form), f"-d 2 -q: {summary(short_form)}; --delta 2 --quiet: "
          f"{summary(long_form)}")


def check_toml_file(program, image, output):
    report_path = os.path.join(output, "toml.json")
    config = write(os.path.join(output, "parameters.toml"),
                   f'delta = 2\nradius-edge = 3\nlabels = [2]\nquiet = true\nreport = "{report_path}"\n')
    from_file = run_quietly(program, [image, os.path.join(output, "toml.vtu"), "--config", config], report_path)
    _, from_line = mesh_and_report(program, image, output, "toml-line",
                                   options=["--delta", "2", "--radius-edge", "3", "--labels", "2"])
    check(summary(from_file) == summary(from_line), f"TOML file: {summary(from_file)}; command line: "
          f"{summary(from_line)}")
    check(list(tetrahedra_per_label(from_file)) == [2], f"labels = [2]: {from_file['labels']}")

    overridden = run_quietly(program, [image, os.path.join(output, "override.vtu"), "--config", config, "-d", "3",
                                       "--labels", "1"], report_path)
    check(overridden["parameters"]["delta_mm"] == 3 and overridden["parameters"]["radius_edge_bound"] == 3,
          f"-d 3 after a file with delta = 2 and radius-edge = 3: {overridden['parameters']}")
    check(list(tetrahedra_per_label(overridden)) == [1], f"--labels 1 over labels = [2]: {overridden['labels']}")


def check_ini_file(program, image, output):
    config = write(os.path.join(output, "parameters.ini"), "[default]\ndelta=2\nmerge-labels=true\n")
    _, from_file = mesh_and_report(program, image, output, "ini", options=["--config", config])
    _, from_line = mesh_and_report(program, image, output, "ini-line", options=["--delta", "2", "--merge-labels"])
    check(summary(from_file) == summary(from_line), f"INI file: {summary(from_file)}; command line: "
          f"{summary(from_line)}")
    check(list(tetrahedra_per_label(from_file)) == [1], f"merge-labels=true: {from_file['labels']}")
    # The report records the option it ran with, from the file as from the command line.
    check(from_file["parameters"]["merge_labels"] is True and from_line["parameters"]["merge_labels"] is True,
          f"merge-labels=true: the reports record {from_file['parameters']} and {from_line['parameters']}")


def main(program, images, output):
    os.makedirs(output, exist_ok=True)
    image = os.path.join(images, "labels.nii.gz")
    check_short_forms(program, image, output)
    check_toml_file(program, image, output)
    check_ini_file(program, image, output)
    print("-d and -q, TOML and INI --config files: the same meshes as the long options; the command line wins")


if __name__ == "__main__":
    main(*sys.argv[1:])
