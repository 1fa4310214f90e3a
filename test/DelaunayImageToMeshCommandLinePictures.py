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
"""Runs examples/render_mesh.py and examples/plot_dihedral_histogram.py on a mesh of the generated two-label
image and checks that the pictures show something: the requested size, enough non-white pixels, and (for the
surface) both labels' colours, orange for label 1 and blue for label 2.

Usage: DelaunayImageToMeshCommandLinePictures.py PROGRAM IMAGE EXAMPLES_DIRECTORY OUTPUT_DIRECTORY"""

import os
import shutil
import subprocess
import sys
import tempfile

import numpy
import vtk
from vtk.util.numpy_support import vtk_to_numpy

from DelaunayImageToMeshCommandLineTesting import check, mesh_and_report, remove_if_present

SIZE = (640, 480)


class PrivateXServer:
    """An Xvfb of its own, on a display number it chose itself (-displayfd), and ready when the number arrives: the
    display is then known to be served. xvfb-run failed here about one run in four back to back (VTK: "bad X server
    connection", aborting): it takes the first number without a lock file, and runs the command even when that
    server died at start (a previous server on the number still going away)."""

    def __enter__(self):
        read_end, write_end = os.pipe()
        # Its messages go to a file: a pipe nobody reads could fill and stop the server.
        self.messages = tempfile.TemporaryFile()
        try:
            self.server = subprocess.Popen(["Xvfb", "-displayfd", str(write_end), "-ac", "-nolisten", "tcp", "-screen",
                                            "0", "1280x1024x24"], pass_fds=(write_end,), stdout=subprocess.DEVNULL,
                                           stderr=self.messages)
        finally:
            os.close(write_end)
        with os.fdopen(read_end) as numbers:
            number = numbers.readline().strip()
        if not number.isdigit():
            self.server.kill()
            self.server.wait()
            self.messages.seek(0)
            check(False, f"Xvfb did not start: {self.messages.read().decode(errors='replace')}")
        self.display = ":" + number
        return self

    def __exit__(self, *exception):
        self.server.terminate()
        self.server.wait(timeout=60)
        self.messages.close()


def run_script(command, name):
    """Debian's VTK needs an X display even off-screen: a private Xvfb whenever it is installed, since a DISPLAY
    inherited from the environment can name a server that is not running (CI once had DISPLAY=:99 with no server,
    and VTK aborted)."""
    if "render_mesh" in name and shutil.which("Xvfb") is not None:
        with PrivateXServer() as server:
            result = subprocess.run(command, capture_output=True, text=True, timeout=600,
                                    env=dict(os.environ, DISPLAY=server.display))
    else:
        if "render_mesh" in name:
            check(bool(os.environ.get("DISPLAY")), "no DISPLAY and no Xvfb (package xvfb) to render with")
        result = subprocess.run(command, capture_output=True, text=True, timeout=600)
    check(result.returncode == 0, f"{name} failed with exit code {result.returncode}:\n{result.stderr}")


def read_png(path):
    reader = vtk.vtkPNGReader()
    reader.SetFileName(path)
    reader.Update()
    image = reader.GetOutput()
    width, height, _ = image.GetDimensions()
    pixels = vtk_to_numpy(image.GetPointData().GetScalars()).astype(float) / 255.0
    return (width, height), pixels[:, :3]


def check_picture(path, expected_size, minimum_ink):
    size, pixels = read_png(path)
    check(tuple(size) == tuple(expected_size), f"{path}: size {size}, expected {expected_size}")
    ink = numpy.mean(pixels.min(axis=1) < 0.9)
    check(ink > minimum_ink, f"{path}: only {ink:.1%} of the pixels are not white")
    return pixels


def fraction_where(pixels, condition):
    return numpy.mean(condition(pixels[:, 0], pixels[:, 1], pixels[:, 2]))


def main(program, image, examples, output):
    mesh, _ = mesh_and_report(program, image, output, "pictures", options=["--delta", "2"])
    report = os.path.join(output, "pictures.json")
    surface, cut, histogram = (os.path.join(output, name) for name in ("surface.png", "cut.png", "histogram.png"))
    remove_if_present(surface, cut, histogram)
    # The balls' centres lie on a line along x, so a plane across y cuts both.
    run_script([sys.executable, os.path.join(examples, "render_mesh.py"), mesh, "--surface", surface, "--cut", cut,
                "--cut-axis", "y", "--size", str(SIZE[0]), str(SIZE[1])], "render_mesh.py")
    run_script([sys.executable, os.path.join(examples, "plot_dihedral_histogram.py"), report, histogram],
               "plot_dihedral_histogram.py")

    for picture in (surface, cut):
        pixels = check_picture(picture, SIZE, 0.05)
        orange = fraction_where(pixels, lambda r, g, b: (r > b + 0.25) & (g > b + 0.1))
        blue = fraction_where(pixels, lambda r, g, b: b > r + 0.25)
        check(orange > 0.01 and blue > 0.01,
              f"{picture}: label 1 (orange) covers {orange:.1%}, label 2 (blue) {blue:.1%}; both should show")
    check_picture(histogram, (960, 540), 0.03)
    print(f"pictures written and checked: {surface}, {cut}, {histogram}")


if __name__ == "__main__":
    main(*sys.argv[1:])
