"""Every guarantee over delta, sigma and rho on whole images, checked from the files the command-line program writes.

    delaunay-bench --images brain-mask,atlas-phantom --ours-only --runs 1 --write-images IMAGES
    /usr/bin/python3 bench/guarantee_sweep.py PROGRAM IMAGES brain-mask:3 atlas-phantom:1 ...
        [--multiples 1.07,1.53,2.37,3.71,5.9] [--sigmas 0,10,15,20] [--rhos 2,1.3]

PROGRAM is delaunay-image-to-mesh; each IMAGE:SPACING names IMAGES/IMAGE.nrrd and its largest voxel spacing (mm).
Every delta is a multiple of that spacing (odd multiples by default, so that no run sits on the voxel lattice), and
every combination of delta, sigma and rho is meshed once with the topology defaults on one thread. Each mesh is checked
by the command-line tests' independent checker (no library code; check_mesh): no tetrahedron flat to rounding,
radius-edge ratio < rho, smallest dihedral angle >= sigma, boundary planar angles > 30 degrees, the report's figures
against the file's, and closed 2-manifold boundaries wherever they are promised (rho = 2, sigma = 0 or the default,
delta at least the spacing: the randomized suite's IsPromisedManifold); elsewhere a boundary that is not one must be
admitted by the report. A mesh that fails is kept next to its report in a temporary directory, named in the output.

Prints one line per run, then the number of runs and of failures; exits 1 when a run fails.
"""
import itertools
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "test"))
# The independent checker of the command-line tests.
import DelaunayImageToMeshCommandLineIndependentQuality as independent  # noqa: E402
from DelaunayImageToMeshCommandLineTesting import CheckFailed, mesh_and_report  # noqa: E402


def values(text):
    return [float(value) for value in text.split(",")]


def main(arguments):
    options = {"--multiples": "1.07,1.53,2.37,3.71,5.9", "--sigmas": "0,10,15,20", "--rhos": "2,1.3"}
    positional = []
    while arguments:
        argument = arguments.pop(0)
        if argument in options:
            options[argument] = arguments.pop(0)
        else:
            positional.append(argument)
    if len(positional) < 3:
        sys.exit(__doc__)
    program, image_directory, cases = positional[0], positional[1], positional[2:]
    # One thread: the runs are checks, not timings, and the machine may be running others.
    os.environ["ITK_GLOBAL_DEFAULT_NUMBER_OF_THREADS"] = "1"
    kept = tempfile.mkdtemp(prefix="guarantee-sweep-")
    runs = failures = 0
    for case in cases:
        image, spacing = case.split(":")
        for multiple, sigma, rho in itertools.product(values(options["--multiples"]), values(options["--sigmas"]),
                                                      values(options["--rhos"])):
            delta = multiple * float(spacing)
            name = f"{image}-delta-{delta:.4f}-sigma-{sigma:g}-rho-{rho:g}"
            promised = independent.is_manifold_promised(delta, float(spacing), sigma, rho)
            runs += 1
            try:
                mesh_path, report = mesh_and_report(
                    program, os.path.join(image_directory, f"{image}.nrrd"), kept, name,
                    options=["--delta", repr(delta), "--min-dihedral", repr(sigma), "--radius-edge", repr(rho)])
                print(independent.check_mesh(mesh_path, report, rho, sigma, promised), flush=True)
            except (CheckFailed, subprocess.TimeoutExpired) as failure:
                failures += 1
                print(f"{name}: FAILED: {failure}", flush=True)
                continue
            os.remove(mesh_path)
            os.remove(mesh_path[:-len(".vtu")] + ".json")
    print(f"{runs} runs, {failures} failed" + (f"; their meshes are in {kept}" if failures else ""))
    if not failures:
        os.rmdir(kept)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
