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
"""An independent check of the guarantees on the meshes the command-line program writes: radius-edge ratio, dihedral
angles, the planar angles of the boundary and interface triangles, and that every tissue's boundary and the union's
are closed 2-manifolds (issue #14), recomputed with NumPy from the .vtu file as meshio reads it. None of the library's own metric code (DelaunayRefinementMeshQuality, the quality report) is used,
so a mistake there cannot hide a mesh that breaks a guarantee (issue #17).

Usage: DelaunayImageToMeshCommandLineIndependentQuality.py PROGRAM IMAGE_DIRECTORY OUTPUT_DIRECTORY [EXAMPLES_DATA]

With EXAMPLES_DATA (the directory of ITK's example images), the real segmentations are meshed instead, over δ, σ
and ρ (REAL_CASES)."""

import collections
import os
import sys

import meshio
import numpy

from DelaunayImageToMeshCommandLineTesting import check, mesh_and_report

# The meshes: the command-line tests' images with the options they use, and the bounds each promises. rho is the
# radius-edge bound (every ratio < rho); sigma the R4' dihedral bound in degrees (every dihedral angle >= sigma; 0:
# off, the paper's method). Every boundary and interface triangle has all planar angles > 30 degrees: proven with
# sigma = 0 (Theorem 2), measured with sigma > 0 (docs/algorithm.md, "Guarantees, and how the tests see them"), checked
# either way.
DEFAULT_SIGMA = 10.0  # the command-line program's --min-dihedral when not given (its --help says so)
CASES = [
    ("labels", "labels.nii.gz", [], 2.0, DEFAULT_SIGMA),
    ("labels-delta-1.5", "labels.nii.gz", ["--delta", "1.5"], 2.0, DEFAULT_SIGMA),
    ("labels-sigma-0", "labels.nii.gz", ["--delta", "1.5", "--min-dihedral", "0"], 2.0, 0.0),
    ("labels-rho-1.2", "labels.nii.gz", ["--delta", "1.5", "--radius-edge", "1.2"], 1.2, DEFAULT_SIGMA),
    ("labels-merged", "labels.nii.gz", ["--delta", "1.5", "--merge-labels"], 2.0, DEFAULT_SIGMA),
    ("labels-sigma-15", "labels.nii.gz", ["--delta", "1.5", "--min-dihedral", "15"], 2.0, 15.0),
    ("speck", "speck.nii.gz", ["--delta", "1.5"], 2.0, DEFAULT_SIGMA),
    ("gray-iso", "gray.mha", ["--delta", "1.5", "--iso", "92"], 2.0, DEFAULT_SIGMA),
]

# ITK's real segmentations over δ, σ and ρ, each bound asked for by the options: the brain mask (every non-zero voxel,
# one object) and the k-means tissues (labels 2-6; label 1 is the background class), both of 2 x 3 x 2 mm voxels. δ
# is an odd multiple of the largest spacing (1.07, 1.53, 2.37, 3.71, 5.9 x 3 mm) so that no run sits on the voxel
# lattice. Where is_manifold_promised says so the boundaries must be closed manifolds; elsewhere a place that is not
# must be admitted by the report. Measured at b4168a7: every row here is a manifold.
BRAIN_MASK = ("KmeansTest_T1RawSkullStrip.nii.gz", ["--merge-labels"])
KMEANS_TISSUES = ("KmeansTest_T1KmeansPrelimSegmentation.nii.gz", ["--labels", "2,3,4,5,6"])
REAL_IMAGES_LARGEST_SPACING = 3.0
REAL_CASES = [
    ("brain-mask-delta-3.21-sigma-0", BRAIN_MASK, 3.21, 0.0, 2.0),
    ("brain-mask-delta-4.59-sigma-20-rho-1.3", BRAIN_MASK, 4.59, 20.0, 1.3),
    ("brain-mask-delta-7.11-sigma-15", BRAIN_MASK, 7.11, 15.0, 2.0),
    ("brain-mask-delta-11.13-rho-1.3", BRAIN_MASK, 11.13, DEFAULT_SIGMA, 1.3),
    ("kmeans-tissues-delta-4.59-sigma-0", KMEANS_TISSUES, 4.59, 0.0, 2.0),
    ("kmeans-tissues-delta-7.11", KMEANS_TISSUES, 7.11, DEFAULT_SIGMA, 2.0),
    ("kmeans-tissues-delta-11.13-sigma-20-rho-1.3", KMEANS_TISSUES, 11.13, 20.0, 1.3),
    ("kmeans-tissues-delta-17.7-sigma-15-rho-1.3", KMEANS_TISSUES, 17.7, 15.0, 1.3),
]

def is_manifold_promised(delta, largest_spacing, sigma, rho):
    """Whether every boundary must be a closed manifold with the topology defaults (issue #14's bar, the randomized
    suite's IsPromisedManifold): rho = 2, sigma 0 or the default, and delta at least the largest voxel spacing."""
    return rho == 2.0 and sigma in (0.0, DEFAULT_SIGMA) and delta >= largest_spacing


# Issue #15's bar: no tetrahedron is flat to rounding, its volume from the coordinates as written to the file at most
# this times its shortest edge cubed.
FLAT_VOLUME_RATIO = 1e-6


def read_tetrahedra(path):
    mesh = meshio.read(path)
    points = numpy.asarray(mesh.points, dtype=numpy.float64)
    blocks = [(block.data, labels) for block, labels in zip(mesh.cells, mesh.cell_data["label"])
              if block.type == "tetra"]
    check(blocks, f"{path}: no tetrahedra")
    tetrahedra = numpy.concatenate([data for data, _ in blocks]).astype(numpy.int64)
    labels = numpy.concatenate([numpy.asarray(values).ravel() for _, values in blocks]).astype(numpy.int64)
    return points, tetrahedra, labels


def circumradii(corners):
    """Circumradius of each tetrahedron: |c - p0| with c solving 2 (pi - p0) . c' = |pi - p0|^2."""
    a = corners[:, 1] - corners[:, 0]
    b = corners[:, 2] - corners[:, 0]
    c = corners[:, 3] - corners[:, 0]
    denominator = 2.0 * numpy.einsum("ij,ij->i", a, numpy.cross(b, c))
    numerator = (numpy.einsum("ij,ij->i", a, a)[:, None] * numpy.cross(b, c)
                 + numpy.einsum("ij,ij->i", b, b)[:, None] * numpy.cross(c, a)
                 + numpy.einsum("ij,ij->i", c, c)[:, None] * numpy.cross(a, b))
    return numpy.linalg.norm(numerator / denominator[:, None], axis=1), denominator / 12.0


def shortest_edges(corners):
    pairs = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)]
    lengths = numpy.stack([numpy.linalg.norm(corners[:, i] - corners[:, j], axis=1) for i, j in pairs], axis=1)
    return lengths.min(axis=1)


def dihedral_angle_ranges(corners):
    """Smallest and largest of the six dihedral angles of each tetrahedron, in degrees, from the face normals: the
    angle at the edge shared by faces i and j is pi minus the angle between their outward normals."""
    faces = [(1, 2, 3), (0, 3, 2), (0, 1, 3), (0, 2, 1)]
    normals = []
    for i, j, k in faces:
        normal = numpy.cross(corners[:, j] - corners[:, i], corners[:, k] - corners[:, i])
        normals.append(normal / numpy.linalg.norm(normal, axis=1)[:, None])
    smallest = numpy.full(len(corners), 180.0)
    largest = numpy.zeros(len(corners))
    for first in range(4):
        for second in range(first + 1, 4):
            cosine = numpy.clip(-numpy.einsum("ij,ij->i", normals[first], normals[second]), -1.0, 1.0)
            angle = numpy.degrees(numpy.arccos(cosine))
            smallest = numpy.minimum(smallest, angle)
            largest = numpy.maximum(largest, angle)
    return smallest, largest


def smallest_dihedral_angles(corners):
    return dihedral_angle_ranges(corners)[0]


def boundary_triangles(tetrahedra, labels):
    """Facets whose two sides carry different labels (a facet of one tetrahedron has the background beyond it)."""
    sides = collections.defaultdict(list)
    for tetrahedron, label in zip(tetrahedra, labels):
        for skipped in range(4):
            facet = tuple(sorted(int(v) for position, v in enumerate(tetrahedron) if position != skipped))
            sides[facet].append(int(label))
    triangles = []
    for facet, facet_labels in sides.items():
        check(len(facet_labels) <= 2, f"facet {facet} is shared by {len(facet_labels)} tetrahedra")
        if len(facet_labels) == 1 or facet_labels[0] != facet_labels[1]:
            triangles.append(facet)
    return numpy.asarray(triangles, dtype=numpy.int64)


def label_boundaries(tetrahedra, labels):
    """Each label's boundary (the facets of its tetrahedra that only one of them has: the other side is another label
    or nothing) and the union's (the same over all tetrahedra), by name."""
    facets = numpy.sort(numpy.concatenate([tetrahedra[:, [1, 2, 3]], tetrahedra[:, [0, 2, 3]],
                                           tetrahedra[:, [0, 1, 3]], tetrahedra[:, [0, 1, 2]]]), axis=1)
    facet_labels = numpy.tile(labels, 4)
    groups = {f"label {int(label)}": facet_labels == label for label in numpy.unique(labels)}
    groups["union"] = numpy.ones(len(facets), dtype=bool)
    boundaries = {}
    for name, selected in groups.items():
        unique, counts = numpy.unique(facets[selected], axis=0, return_counts=True)
        boundaries[name] = unique[counts == 1]
    return boundaries


def surface_defects(triangles):
    """Edges of the triangles not in exactly two of them, and vertices whose link (the edges opposite the vertex in
    its triangles) is not one cycle: a closed 2-manifold has neither."""
    edges = numpy.sort(numpy.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [0, 2]]]), axis=1)
    _, edge_counts = numpy.unique(edges, axis=0, return_counts=True)
    bad_edges = int(numpy.count_nonzero(edge_counts != 2))
    links = collections.defaultdict(list)
    for a, b, c in triangles.tolist():
        links[a].append((b, c))
        links[b].append((a, c))
        links[c].append((a, b))
    bad_vertices = 0
    for link in links.values():
        neighbours = collections.defaultdict(list)
        for a, b in link:
            neighbours[a].append(b)
            neighbours[b].append(a)
        if any(len(around) != 2 for around in neighbours.values()):
            bad_vertices += 1
            continue
        start = next(iter(neighbours))
        reached = {start}
        stack = [start]
        while stack:
            for other in neighbours[stack.pop()]:
                if other not in reached:
                    reached.add(other)
                    stack.append(other)
        bad_vertices += len(reached) != len(neighbours)
    return bad_edges, bad_vertices


def smallest_planar_angles(points, triangles):
    corners = points[triangles]
    smallest = numpy.full(len(triangles), 180.0)
    for apex in range(3):
        u = corners[:, (apex + 1) % 3] - corners[:, apex]
        v = corners[:, (apex + 2) % 3] - corners[:, apex]
        cosine = numpy.einsum("ij,ij->i", u, v) / (numpy.linalg.norm(u, axis=1) * numpy.linalg.norm(v, axis=1))
        smallest = numpy.minimum(smallest, numpy.degrees(numpy.arccos(numpy.clip(cosine, -1.0, 1.0))))
    return smallest


# How far the report's angles (degrees) and ratios may differ from this script's, computed from the same double
# precision coordinates by other formulas.
REPORT_ANGLE_TOLERANCE = 1e-6
REPORT_RATIO_TOLERANCE = 1e-9


def check_report(path, report, ratios, dihedral, planar):
    """The quality report says what this script finds in the mesh: the extreme dihedral angles, radius-edge ratio and
    boundary planar angle, and the count of tetrahedra below 5, 10 and 15 degrees (a report that skipped an edge or a
    tetrahedron would flatter the mesh)."""
    quality = report["quality"]
    smallest, largest = dihedral
    for key, value in (("min_dihedral_angle_deg", smallest.min()), ("max_dihedral_angle_deg", largest.max()),
                       ("min_boundary_planar_angle_deg", planar.min())):
        check(abs(quality[key] - value) <= REPORT_ANGLE_TOLERANCE,
              f"{path}: the report's {key} is {quality[key]}, the mesh's {value}")
    check(abs(quality["max_radius_edge_ratio"] - ratios.max()) <= REPORT_RATIO_TOLERANCE * ratios.max(),
          f"{path}: the report's max_radius_edge_ratio is {quality['max_radius_edge_ratio']}, the mesh's "
          f"{ratios.max()}")
    counts = quality["tetrahedra_below_dihedral_deg"]
    check(sorted(float(threshold) for threshold in counts) == [5.0, 10.0, 15.0],
          f"{path}: the report counts tetrahedra below {sorted(counts)} degrees, not below 5, 10 and 15")
    for threshold, count in counts.items():
        below = int(numpy.count_nonzero(smallest < float(threshold)))
        check(count == below, f"{path}: the report counts {count} tetrahedra below {threshold} degrees, the mesh has "
              f"{below}")


def check_mesh(path, report, rho, sigma, manifold_promised=True):
    """Every bound from the file, and the report's figures against it. Where `manifold_promised` is false, a boundary
    that is not a closed manifold passes only when the report says so."""
    points, tetrahedra, labels = read_tetrahedra(path)
    corners = points[tetrahedra]
    radii, volumes = circumradii(corners)
    check(volumes.min() > 0.0, f"{path}: a tetrahedron has volume {volumes.min()} <= 0")
    shortest = shortest_edges(corners)
    flatness = volumes / shortest ** 3
    flattest = int(numpy.argmin(flatness))
    check(flatness[flattest] > FLAT_VOLUME_RATIO, f"{path}: tetrahedron {flattest} is flat to rounding: volume "
          f"{volumes[flattest]} <= {FLAT_VOLUME_RATIO} x its shortest edge cubed, corners {corners[flattest].tolist()}")
    ratios = radii / shortest
    worst = int(numpy.argmax(ratios))
    check(ratios[worst] < rho, f"{path}: radius-edge ratio {ratios[worst]} >= {rho} at tetrahedron {worst}, corners "
          f"{corners[worst].tolist()}")
    dihedral_ranges = dihedral_angle_ranges(corners)
    dihedral = dihedral_ranges[0]
    triangles = boundary_triangles(tetrahedra, labels)
    check(len(triangles) > 0, f"{path}: no boundary triangle")
    planar = smallest_planar_angles(points, triangles)
    check_report(path, report, ratios, dihedral_ranges, planar)
    defects = {name: surface_defects(boundary) for name, boundary in label_boundaries(tetrahedra, labels).items()}
    manifold = all(defect == (0, 0) for defect in defects.values())
    check(report["quality"]["manifold"] == manifold, f"{path}: the report says manifold {report['quality']['manifold']}, "
          f"the mesh's boundaries have non-manifold edges and vertices {defects}")
    if manifold_promised:
        for name, (bad_edges, bad_vertices) in defects.items():
            check(bad_edges == 0 and bad_vertices == 0, f"{path}: the boundary of {name} has {bad_edges} non-manifold "
                  f"edges and {bad_vertices} non-manifold vertices")
    if sigma > 0.0:
        check(dihedral.min() >= sigma * (1.0 - 1e-9), f"{path}: dihedral angle {dihedral.min()} < sigma {sigma}")
    check(planar.min() > 30.0, f"{path}: boundary planar angle {planar.min()} <= 30 degrees at triangle "
          f"{triangles[int(numpy.argmin(planar))].tolist()}")
    return (f"{os.path.basename(path)}: {len(tetrahedra)} tetrahedra, {len(triangles)} boundary triangles, "
            f"{'' if manifold else 'admitted non-manifold boundaries, '}smallest volume / shortest edge cubed "
            f"{flatness.min():.3g}, "
            f"max radius-edge {ratios.max():.4f} (< {rho}), min dihedral {dihedral.min():.3f} deg"
            f"{f' (>= {sigma})' if sigma > 0 else ''}, min boundary planar angle {planar.min():.3f} deg (> 30)")


def self_test():
    """The checks must see what they look for: a regular tetrahedron (ratio sqrt(6)/4, dihedral 70.53 degrees,
    planar 60) and a flattened one (a sliver: large ratio, small dihedral)."""
    regular = numpy.array([[[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]]], dtype=numpy.float64)
    radii, _ = circumradii(regular)
    check(abs(radii[0] / shortest_edges(regular)[0] - numpy.sqrt(6) / 4) < 1e-12, "regular tetrahedron's ratio")
    check(abs(smallest_dihedral_angles(regular)[0] - numpy.degrees(numpy.arccos(1 / 3))) < 1e-9, "regular dihedral")
    sliver = numpy.array([[[0, 0, 0], [1, 0, 0.01], [1, 1, 0], [0, 1, 0.01]]], dtype=numpy.float64)
    radii, _ = circumradii(sliver)
    check(radii[0] / shortest_edges(sliver)[0] > 0.7 and smallest_dihedral_angles(sliver)[0] < 5, "sliver")
    triangles = boundary_triangles(numpy.array([[0, 1, 2, 3]]), numpy.array([1]))
    check(len(triangles) == 4, "a lone tetrahedron has four boundary facets")
    check(abs(smallest_planar_angles(regular[0], triangles).min() - 60.0) < 1e-9, "regular planar angles")
    # A lone tetrahedron's boundary is a sphere; two sharing only an edge make it an edge in four triangles (and its
    # two ends non-manifold vertices); two sharing only a vertex, a vertex whose link is two cycles.
    lone = label_boundaries(numpy.array([[0, 1, 2, 3]]), numpy.array([1]))
    check(surface_defects(lone["union"]) == (0, 0) and surface_defects(lone["label 1"]) == (0, 0), "lone tetrahedron")
    along_an_edge = label_boundaries(numpy.array([[0, 1, 2, 3], [0, 1, 4, 5]]), numpy.array([1, 1]))
    check(surface_defects(along_an_edge["union"]) == (1, 2), "two tetrahedra sharing an edge only")
    at_a_vertex = label_boundaries(numpy.array([[0, 1, 2, 3], [0, 4, 5, 6]]), numpy.array([1, 2]))
    check(surface_defects(at_a_vertex["union"]) == (0, 1), "two tetrahedra sharing a vertex only")
    check(surface_defects(at_a_vertex["label 2"]) == (0, 0), "one tissue's boundary alone")


def main(program, image_directory, output_directory, examples_data=None):
    self_test()
    if examples_data is None:
        for name, image, options, rho, sigma in CASES:
            mesh_path, report = mesh_and_report(program, os.path.join(image_directory, image), output_directory, name,
                                                options=options)
            print(check_mesh(mesh_path, report, rho, sigma))
        return
    for name, (image, selection), delta, sigma, rho in REAL_CASES:
        options = [*selection, "--delta", repr(delta), "--min-dihedral", repr(sigma), "--radius-edge", repr(rho)]
        mesh_path, report = mesh_and_report(program, os.path.join(examples_data, image), output_directory, name,
                                            options=options)
        promised = is_manifold_promised(delta, REAL_IMAGES_LARGEST_SPACING, sigma, rho)
        print(check_mesh(mesh_path, report, rho, sigma, promised))


if __name__ == "__main__":
    if len(sys.argv) not in (4, 5):
        sys.exit(__doc__)
    main(*sys.argv[1:])
