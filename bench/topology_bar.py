"""Issue #14's bar: the filter's defaults against the method alone, image by image and delta by delta.

    delaunay-bench --images brain-mask,atlas-phantom --ours-only --runs 1 --write-images IMAGES
    /usr/bin/python3 bench/topology_bar.py PROGRAM IMAGES brain-mask:3 atlas-phantom:1 ... [--rounds N]
        [--cgal CGAL_PROGRAM]

PROGRAM is delaunay-image-to-mesh; each IMAGE:SPACING names IMAGES/IMAGE.nrrd and its largest voxel spacing (mm);
IMAGE:SPACING:FIRST starts at FIRST times the spacing instead of 1 (a mesh too large for the machine at 1 ×), and
IMAGE:SPACING:FIRST:LAST stops at LAST times (such a large mesh measured alone).
For delta = 1 to 6 times the spacing the script meshes the image with the defaults (with --distance) and with the
method alone (no regularisation, no pinch removal, no relabelling, no topology rounds, no thick-part refinement),
then times N paired rounds
of both (the mesh phase of the report: the whole filter). It checks every default mesh's topology itself, from the
.vtu file, with the command-line tests' independent checker (no library code): every tissue's boundary and the
union's must be closed 2-manifolds. Tetrahedra are also counted at 1.25, 1.5 and 2.5 times the spacing, so that the
series delta, 1.25 delta, 1.5 delta, 2 delta, 3 delta can be read from delta = 1 and 2 times the spacing.

With --cgal (delaunay-bench-cgal-mesh) each row also gets CGAL Mesh_3 on the same image and delta, as the bench runs
it (no optimisers, facet_size = delta, facet_distance searched so that neither our mean nor our p95 distance is worse
than CGAL's by more than 10 %): its tetrahedra, the same independent count of non-manifold edges and vertices on its
mesh, and its time (image conversion and make_mesh_3) in the same paired rounds, against our whole filter.

Prints Markdown: one row per image and delta, then the delta series and the per-tissue volume changes.
"""
import json
import os
import statistics
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "test"))
# The independent checker of the command-line tests: read_tetrahedra, label_boundaries, surface_defects.
import DelaunayImageToMeshCommandLineIndependentQuality as independent  # noqa: E402

ALONE = ["--regularization-scale", "0", "--topology-rounds", "0", "--no-topology-relabelling",
         "--keep-diagonal-voxels", "--no-thick-part-refinement"]
TIMED_MULTIPLES = [1, 2, 3, 4, 5, 6]
SERIES_ONLY_MULTIPLES = [1.25, 1.5, 2.5]


def mesh(program, image, delta, options, keep_mesh=None, distance=False):
    """The report of one run, and the mesh written to keep_mesh when given."""
    with tempfile.TemporaryDirectory() as directory:
        output = keep_mesh or os.path.join(directory, "mesh.vtu")
        report = os.path.join(directory, "report.json")
        command = [program, image, output, "-d", repr(delta), "-q", "--report", report] + options
        if distance:
            command.append("--distance")
        subprocess.run(command, check=True, capture_output=True)
        with open(report, encoding="utf-8") as file:
            return json.load(file)


def independent_defects(path):
    """Non-manifold edges and vertices over every tissue's boundary and the union's, found from the file."""
    _, tetrahedra, labels = independent.read_tetrahedra(path)
    edges = vertices = 0
    for boundary in independent.label_boundaries(tetrahedra, labels).values():
        bad_edges, bad_vertices = independent.surface_defects(boundary)
        edges += bad_edges
        vertices += bad_vertices
    return edges, vertices


def cgal_mesh(cgal_program, image, delta, matching, keep_mesh=None):
    """What delaunay-bench-cgal-mesh printed (its JSON line), with `matching` its facet-distance options."""
    with tempfile.TemporaryDirectory() as directory:
        output = keep_mesh or os.path.join(directory, "cgal.vtu")
        result = subprocess.run([cgal_program, image, output, "-d", repr(delta)] + matching, check=True,
                                capture_output=True, text=True)
        return json.loads(result.stdout.splitlines()[0])


def measure(program, image, delta, rounds, cgal_program=None):
    with tempfile.TemporaryDirectory() as directory:
        path = os.path.join(directory, "defaults.vtu")
        defaults = mesh(program, image, delta, [], keep_mesh=path, distance=True)
        row = {"delta": delta, "defaults": defaults, "independent": independent_defects(path)}
        if cgal_program:
            distance = defaults["distance_to_marching_cubes"]
            cgal_path = os.path.join(directory, "cgal.vtu")
            row["cgal"] = cgal_mesh(cgal_program, image, delta,
                                    ["--match-mean-distance", repr(distance["mean_mm"]),
                                     "--match-p95-distance", repr(distance["percentile95_mm"])], keep_mesh=cgal_path)
            row["cgal_independent"] = independent_defects(cgal_path)
    row["alone"] = mesh(program, image, delta, ALONE)
    alone_seconds, default_seconds, cgal_seconds = [], [], []
    for _ in range(rounds):
        alone_seconds.append(mesh(program, image, delta, ALONE)["time_seconds"]["mesh"])
        default_seconds.append(mesh(program, image, delta, [])["time_seconds"]["mesh"])
        if cgal_program:
            matched = ["--facet-distance", repr(row["cgal"]["facet_distance_mm"])] \
                if row["cgal"]["facet_distance_mm"] > 0 else []
            cgal_seconds.append(cgal_mesh(cgal_program, image, delta, matched)["seconds"])
    ratios = [b / a for a, b in zip(alone_seconds, default_seconds)]
    row.update(alone_s=statistics.median(alone_seconds), default_s=statistics.median(default_seconds),
               ratio=statistics.median(ratios), ratio_range=(min(ratios), max(ratios)))
    if cgal_program:
        cgal_ratios = [ours / cgal for ours, cgal in zip(default_seconds, cgal_seconds)]
        row.update(cgal_s=statistics.median(cgal_seconds), cgal_ratio=statistics.median(cgal_ratios),
                   cgal_ratio_range=(min(cgal_ratios), max(cgal_ratios)))
    return row


def table_row(name, multiple, row):
    defaults, alone = row["defaults"], row["alone"]
    quality, distance, delta = defaults["quality"], defaults["distance_to_marching_cubes"], row["delta"]
    low, high = row["ratio_range"]
    return (f"| {name}, {delta:g} mm ({multiple:g} ×) | {defaults['tetrahedra']:,} / {alone['tetrahedra']:,} "
            f"({defaults['tetrahedra'] / alone['tetrahedra']:.2f}) | {row['default_s']:.3f} / {row['alone_s']:.3f}, "
            f"**{row['ratio']:.2f}** ({low:.2f}-{high:.2f}) | {quality['non_manifold_edges']} / "
            f"{quality['non_manifold_vertices']}, {row['independent'][0]} / {row['independent'][1]} | "
            f"{distance['mean_mm'] / delta:.3f} / {distance['percentile95_mm'] / delta:.3f} | "
            f"{quality['min_dihedral_angle_deg']:.2f}° / {quality['max_radius_edge_ratio']:.3f} / "
            f"{quality['min_boundary_planar_angle_deg']:.2f}° |" + cgal_cells(row))


def cgal_cells(row):
    """The CGAL columns of a row (none without --cgal)."""
    if "cgal" not in row:
        return ""
    cgal, defaults = row["cgal"], row["defaults"]
    low, high = row["cgal_ratio_range"]
    matched = "" if cgal["matched"] else ", not matched"
    return (f" {cgal['tetrahedra']:,} ({defaults['tetrahedra'] / cgal['tetrahedra']:.2f}) | "
            f"{row['cgal_s']:.3f}, **{row['cgal_ratio']:.2f}** ({low:.2f}-{high:.2f}) | "
            f"{row['cgal_independent'][0]} / {row['cgal_independent'][1]} | "
            f"{cgal['facet_distance_mm']:g}: {cgal['matched_mean_distance_mm'] / row['delta']:.3f} / "
            f"{cgal['matched_percentile95_distance_mm'] / row['delta']:.3f}{matched} |")


def main(program, image_directory, cases, rounds, cgal_program=None):
    header = ("| image, δ (× voxel) | tetrahedra: defaults / alone (ratio) | time s: defaults / alone, paired ratio "
              "(range) | non-manifold edges / vertices: report, independent | distance mean / p95 (× δ) | "
              "min dihedral / max radius-edge / min boundary angle |")
    columns = 6
    if cgal_program:
        header += (" CGAL tetrahedra (ours / CGAL) | CGAL time s, ours / CGAL paired (range) | CGAL non-manifold "
                   "edges / vertices, independent | CGAL facet_distance mm: distance mean / p95 (× δ) |")
        columns += 4
    print(header)
    print("|" + "---|" * columns)
    series, volumes = {}, {}
    for case in cases:
        name, spacing, *multiples = case.split(":")
        first_multiple = float(multiples[0]) if multiples else 1.0
        last_multiple = float(multiples[1]) if len(multiples) > 1 else max(TIMED_MULTIPLES)
        image = os.path.join(image_directory, name + ".nrrd")
        counts = {}
        for multiple in sorted(m for m in TIMED_MULTIPLES + SERIES_ONLY_MULTIPLES
                               if first_multiple <= m <= last_multiple):
            delta = multiple * float(spacing)
            if multiple in SERIES_ONLY_MULTIPLES:
                counts[multiple] = mesh(program, image, delta, [])["tetrahedra"]
                continue
            row = measure(program, image, delta, rounds, cgal_program)
            counts[multiple] = row["defaults"]["tetrahedra"]
            print(table_row(name, multiple, row), flush=True)
            changes = [100.0 * (label["mesh_volume_mm3"] - label["segmented_volume_mm3"]) / label["segmented_volume_mm3"]
                       for label in row["defaults"]["labels"] if label["segmented_volume_mm3"] > 0]
            lost = sum(1 for label in row["defaults"]["labels"] if label["lost"])
            if changes:
                volumes[(name, multiple)] = (len(row["defaults"]["labels"]), min(changes),
                                             statistics.median(changes), max(changes), lost)
        series[name] = counts
    print("\nTetrahedra with the defaults over delta (× the voxel):\n")
    for name, counts in series.items():
        ordered = [counts[multiple] for multiple in sorted(counts)]
        decreasing = all(later < earlier for earlier, later in zip(ordered, ordered[1:]))
        print(f"- {name}: " + ", ".join(f"{multiple:g} ×: {counts[multiple]:,}" for multiple in sorted(counts))
              + f"; strictly decreasing: {'yes' if decreasing else 'NO'}")
    print("\nPer-tissue volume change, mesh against segmentation (%): labels, smallest / median / largest, "
          "labels lost whole:\n")
    for (name, multiple), (labels, smallest, median, largest, lost) in volumes.items():
        print(f"- {name} at {multiple:g} ×: {labels} labels, {smallest:+.1f} / {median:+.1f} / {largest:+.1f}, "
              f"{lost} lost")


if __name__ == "__main__":
    arguments = sys.argv[1:]
    rounds = 5
    if "--rounds" in arguments:
        position = arguments.index("--rounds")
        rounds = int(arguments[position + 1])
        del arguments[position:position + 2]
    cgal_program = None
    if "--cgal" in arguments:
        position = arguments.index("--cgal")
        cgal_program = arguments[position + 1]
        del arguments[position:position + 2]
    if len(arguments) < 3:
        sys.exit(__doc__)
    main(arguments[0], arguments[1], arguments[2:], rounds, cgal_program)
