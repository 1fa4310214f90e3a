#!/usr/bin/python3
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
"""Plots the histogram of each tetrahedron's smallest dihedral angle from a delaunay-image-to-mesh --report
JSON file (its "min_dihedral_angle_histogram") into a PNG. Runs with Debian's python3-matplotlib
(/usr/bin/python3); needs no display."""

import argparse
import json
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (the backend must be chosen first)

# The smallest dihedral angle of a tetrahedron is at most that of the regular one, arccos(1/3).
REGULAR_TETRAHEDRON_DIHEDRAL_ANGLE = 70.5288


def parse_arguments():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("report", help="the JSON report written by delaunay-image-to-mesh --report")
    parser.add_argument("png", help="the picture to write")
    parser.add_argument("--title", help="title of the plot (default: the report's input file name)")
    return parser.parse_args()


def plot(report, title, path):
    histogram = report["min_dihedral_angle_histogram"]
    width = histogram["bin_width_deg"]
    counts = histogram["counts"]
    lower_edges = [width * i for i in range(len(counts))]
    quality = report["quality"]
    sigma = report["parameters"]["min_dihedral_angle_deg"]

    figure, axes = plt.subplots(figsize=(8, 4.5), dpi=120)
    axes.bar(lower_edges, counts, width=width, align="edge", color="#0072B2", edgecolor="white", linewidth=0.5)
    axes.axvline(REGULAR_TETRAHEDRON_DIHEDRAL_ANGLE, color="0.4", linestyle=":", label="regular tetrahedron (70.5°)")
    axes.axvline(quality["min_dihedral_angle_deg"], color="#D55E00", linestyle="--",
                 label=f"smallest: {quality['min_dihedral_angle_deg']:.3g}°")
    if sigma > 0:
        axes.axvline(sigma, color="#009E73", linestyle="-", label=f"--min-dihedral {sigma:g}°")
    axes.set_xlim(0, 80)
    axes.set_xlabel(f"smallest dihedral angle of the tetrahedron (degrees, {width:g}° bins)")
    axes.set_ylabel("tetrahedra")
    parameters = report["parameters"]
    axes.set_title(f"{title}\n{report['tetrahedra']} tetrahedra, δ = {parameters['delta_mm']:g} mm, "
                   f"ρ = {parameters['radius_edge_bound']:g}", fontsize=11)
    axes.legend(frameon=False, loc="upper left")
    figure.tight_layout()
    figure.savefig(path)


def main():
    arguments = parse_arguments()
    with open(arguments.report, encoding="utf-8") as file:
        report = json.load(file)
    title = arguments.title or f"Smallest dihedral angles: {os.path.basename(report['input'])}"
    plot(report, title, arguments.png)


if __name__ == "__main__":
    main()
