"""Issue #15's bar: sliver removal at sigma against the same run without it, image by image and delta by delta.

    delaunay-bench --images sphere-64,brain-mask --ours-only --runs 1 --deltas 4 --write-images IMAGES
    /usr/bin/python3 bench/sliver_bar.py PROGRAM IMAGES IMAGE:DELTA ... [--sigma S] [--rounds N]

PROGRAM is delaunay-image-to-mesh; each IMAGE:DELTA names IMAGES/IMAGE.nrrd and a delta in mm. For each, the script
meshes the image with the defaults and --min-dihedral S (15 unless told) and with --min-dihedral 0, in N paired rounds
(5 unless told) whose order alternates, and takes the whole filter's time from the report (time_seconds.mesh). It
checks the mesh with sliver removal itself, from the .vtu, with the command-line tests' independent checker (no
library code): its smallest dihedral angle, largest radius-edge ratio, smallest boundary planar angle, and the
non-manifold edges and vertices of every tissue's boundary and the union's. Topology and fidelity against the run
without sliver removal come from the two reports (one more run of each, with --distance): every tissue's boundary
components and genus, and the two-sided distance to the marching-cubes surface. Where the topology differs, the
runs without sliver removal at δ ± 1 % say how far a perturbation that is not sliver removal moves it.

Prints Markdown: one row per image and delta.
"""
import os
import statistics
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "test"))
# The independent checker of the command-line tests.
import DelaunayImageToMeshCommandLineIndependentQuality as independent  # noqa: E402
# Issue #14's bar script: its runs of the command-line program and its count of non-manifold places.
from topology_bar import independent_defects, mesh  # noqa: E402


def sigma_option(sigma):
    return ["--min-dihedral", repr(sigma)]


def independent_quality(path):
    """Smallest dihedral angle, largest radius-edge ratio, smallest boundary planar angle, and the non-manifold
    edges and vertices over every tissue's boundary and the union's, computed from the file."""
    points, tetrahedra, labels = independent.read_tetrahedra(path)
    corners = points[tetrahedra]
    radii, _ = independent.circumradii(corners)
    ratios = radii / independent.shortest_edges(corners)
    planar = independent.smallest_planar_angles(points, independent.boundary_triangles(tetrahedra, labels))
    edges, vertices = independent_defects(path)
    return {"min_dihedral": float(independent.smallest_dihedral_angles(corners).min()),
            "max_ratio": float(ratios.max()), "min_planar": float(planar.min()), "edges": edges, "vertices": vertices}


def topology(report):
    """Every tissue's boundary components and genus, by label."""
    return {label["label"]: (label["boundary_components"], label["boundary_genus"]) for label in report["labels"]}


def largest_topology_change(a, b):
    """The largest change of a tissue's boundary components, and of its genus, from `a` to `b` (topology())."""
    components = max((abs(a[label][0] - b.get(label, (0, 0))[0]) for label in a), default=0)
    genus = max((abs(a[label][1] - b.get(label, (0, 0))[1]) for label in a), default=0)
    return components, genus


def topology_without_removal_nearby(program, image, delta):
    """The topology of the runs without sliver removal at δ ± 1 %: how much a perturbation that is not sliver
    removal moves it. Where tissues are speckle at the scale of δ (the k-means tissues), any change to the
    refinement's cascade moves components and genus; this says by how much."""
    return [topology(mesh(program, image, factor * delta, sigma_option(0.0))) for factor in (0.99, 1.01)]


def measure(program, image, delta, sigma, rounds):
    with tempfile.TemporaryDirectory() as directory:
        path = os.path.join(directory, "sigma.vtu")
        with_removal = mesh(program, image, delta, sigma_option(sigma), keep_mesh=path, distance=True)
        row = {"with": with_removal, "independent": independent_quality(path)}
    row["without"] = mesh(program, image, delta, sigma_option(0.0), distance=True)
    if topology(row["with"]) != topology(row["without"]):
        row["nearby"] = topology_without_removal_nearby(program, image, delta)
    seconds = {sigma: [], 0.0: []}
    for round_index in range(rounds):
        for run_sigma in ((sigma, 0.0) if round_index % 2 == 0 else (0.0, sigma)):
            seconds[run_sigma].append(mesh(program, image, delta, sigma_option(run_sigma))["time_seconds"]["mesh"])
    ratios = [a / b for a, b in zip(seconds[sigma], seconds[0.0])]
    row.update(with_s=statistics.median(seconds[sigma]), without_s=statistics.median(seconds[0.0]),
               ratio=statistics.median(ratios), ratio_range=(min(ratios), max(ratios)))
    return row


def table_row(name, delta, row):
    with_removal, without = row["with"], row["without"]
    checked = row["independent"]
    low, high = row["ratio_range"]
    same_topology = "same"
    if "nearby" in row:
        components, genus = largest_topology_change(topology(without), topology(with_removal))
        nearby = [largest_topology_change(topology(without), other) for other in row["nearby"]]
        same_topology = (f"**differs** (a tissue's components by up to {components}, genus by {genus}; σ = 0 at "
                         f"δ ± 1 %: by {max(n[0] for n in nearby)} and {max(n[1] for n in nearby)})")
    distance, distance_without = with_removal["distance_to_marching_cubes"], without["distance_to_marching_cubes"]
    return (f"| {name}, {delta:g} mm | {with_removal['tetrahedra']:,} / {without['tetrahedra']:,} "
            f"({with_removal['tetrahedra'] / without['tetrahedra']:.3f}) | {row['with_s']:.3f} / {row['without_s']:.3f}, "
            f"**{row['ratio']:.2f}** ({low:.2f}-{high:.2f}) | {checked['min_dihedral']:.2f}° / {checked['max_ratio']:.4f} / "
            f"{checked['min_planar']:.2f}° | {checked['edges']} / {checked['vertices']} | {same_topology} | "
            f"{distance['mean_mm']:.3f} / {distance['percentile95_mm']:.3f} against "
            f"{distance_without['mean_mm']:.3f} / {distance_without['percentile95_mm']:.3f} |")


def main(program, image_directory, cases, sigma, rounds):
    print(f"| image, δ | tetrahedra σ = {sigma:g}° / σ = 0 (ratio) | time s σ = {sigma:g}° / σ = 0, paired ratio (range) | "
          "min dihedral / max radius-edge / min boundary angle (independent) | non-manifold edges / vertices "
          "(independent) | tissues' components and genus against σ = 0 | distance mean / p95 mm against σ = 0 |")
    print("|" + "---|" * 7)
    for case in cases:
        name, delta = case.split(":")
        row = measure(program, os.path.join(image_directory, name + ".nrrd"), float(delta), sigma, rounds)
        print(table_row(name, float(delta), row), flush=True)


if __name__ == "__main__":
    arguments = sys.argv[1:]
    options = {"--rounds": 5.0, "--sigma": 15.0}
    for option in options:
        if option in arguments:
            position = arguments.index(option)
            options[option] = float(arguments[position + 1])
            del arguments[position:position + 2]
    if len(arguments) < 3:
        sys.exit(__doc__)
    main(arguments[0], arguments[1], arguments[2:], options["--sigma"], int(options["--rounds"]))
