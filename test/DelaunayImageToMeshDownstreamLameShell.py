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
"""The whole chain against an analytic solution (issue #19): label image -> delaunay-image-to-mesh -> DOLFINx linear
elasticity, on a thick spherical shell under internal pressure, whose displacement Lame gave in closed form.

    DelaunayImageToMeshDownstreamLameShell.py PROGRAM CGAL_PROGRAM|- EXAMPLES_DIRECTORY OUTPUT_DIRECTORY

The shell (radii a = 6 mm, b = 12 mm, one label) is voxelised at 0.2 mm and meshed at several surface sampling
distances delta. Boundary conditions: the exact displacement on the outer surface (Dirichlet, which also removes
the rigid-body modes) and the pressure p on the inner surface (Neumann, the traction -p n on the mesh's own inner
boundary). The exact radial displacement is u_r = A r + B / r^2 with
A = p a^3 / ((3 lambda + 2 mu)(b^3 - a^3)) and B = p a^3 b^3 / (4 mu (b^3 - a^3)).

Checked:
- the relative L2 error of the P1 displacement falls with the mesh as P1 elements make it fall: the least-squares
  slope of log(error) against log(h), h = (mesh volume / tetrahedra)^(1/3) the mean element size, is at least 1.7
  (2 in theory). Against delta the slope is smaller, because the mesh's interior size is not proportional to delta
  (the refinement bounds no volume size, only radius-edge ratios, and grades away from the surface): it must still
  be at least 1.2 and is reported;
- the voxels do not spoil it: the same solve with the traction of the exact stress, sigma(u) n, on the mesh's own
  inner boundary (for which the exact field solves the meshed problem whatever the boundary's shape) differs from
  the pressure solve by less than a third of the error measured (the rest is the discretisation's);
- with CGAL_PROGRAM (bench/delaunay-bench-cgal-mesh), CGAL Mesh_3's mesh of the same image at matched fidelity
  (facet_size = delta and the benchmark's facet_distance search): at each delta our L2 error is no worse than on
  CGAL's mesh, and no worse either once normalised by the mesh size (error x tetrahedra^(2/3)).

Reported beside it, for every mesh: conjugate-gradient iterations (Jacobi preconditioner, relative tolerance 1e-10),
PETSc's condition estimate of the preconditioned operator, the smallest dihedral angle, the relative H1 error, and
the same for our mesher without sliver removal (--min-dihedral 0, the paper's method; the defaults remove slivers,
sigma = 10 degrees), on which nothing is asserted. The H1 error is not asserted because of what it showed before
sliver removal became the default: the surface points lie on voxel-face centres, a lattice with exactly coplanar,
cocircular quadruples, and the paper's method at delta = 0.7 made one flat tetrahedron of four such outer-boundary points
(volume 6e-17 mm^3). Its vertices carry Dirichlet data here, so the solve and the L2 error do not see it, but the
gradient of the interpolated exact field there makes the H1 error 8e2. On a Neumann boundary such a tetrahedron
wrecks the solver instead (a 0.25 mm grid at delta = 0.5 gave one of 6e-8 mm^3 on the inner surface: condition
estimate 6e5 and 1111 CG iterations, against about 300 and 150).

Without DOLFINx (Debian package python3-dolfinx, installed by scripts/setup.sh) the test says so and exits with
code 77, which CTest counts as skipped.
"""

import json
import math
import os
import subprocess
import sys
import time

SKIP = 77
try:
    from dolfinx import fem, mesh
    import numpy as np
    import ufl
except ModuleNotFoundError as error:
    # Skipped only where DOLFINx is not installed at all: an installed one that fails to import (a missing library,
    # an ABI mismatch) or a missing NumPy is a failure, not a skip.
    if error.name != "dolfinx":
        raise
    print(f"SKIPPED: DOLFINx is not available ({error}); install Debian's python3-dolfinx (scripts/setup.sh does)")
    sys.exit(SKIP)

INNER_RADIUS, OUTER_RADIUS = 6.0, 12.0  # mm
VOXEL = 0.2  # mm
DELTAS = [1.4, 1.0, 0.7, 0.5]  # mm
YOUNG, POISSON, PRESSURE = 1.0, 0.3, 0.1  # kPa, -, kPa: the displacement scales with p / E

MINIMUM_RATE_AGAINST_SIZE = 1.7
MINIMUM_RATE_AGAINST_DELTA = 1.2
MAXIMUM_GEOMETRY_SHARE = 1.0 / 3.0


def check(condition, message):
    if not condition:
        raise AssertionError(message)


def shell_image(path):
    """The shell as labels (1 inside, 0 elsewhere) on a grid of VOXEL mm centred on the origin."""
    count = int(math.ceil(2.0 * (OUTER_RADIUS + 1.0) / VOXEL))
    centres = (np.arange(count) - (count - 1) / 2.0) * VOXEL
    z, y, x = np.meshgrid(centres, centres, centres, indexing="ij")
    radius = np.sqrt(x * x + y * y + z * z)
    labels = ((radius > INNER_RADIUS) & (radius < OUTER_RADIUS)).astype(np.uint8)
    example.write_metaimage(path, labels, [VOXEL] * 3, [centres[0]] * 3)


def lame_coefficients():
    mu = YOUNG / (2.0 * (1.0 + POISSON))
    lmbda = YOUNG * POISSON / ((1.0 + POISSON) * (1.0 - 2.0 * POISSON))
    volume_ratio = OUTER_RADIUS**3 - INNER_RADIUS**3
    a = PRESSURE * INNER_RADIUS**3 / ((3.0 * lmbda + 2.0 * mu) * volume_ratio)
    b = PRESSURE * INNER_RADIUS**3 * OUTER_RADIUS**3 / (4.0 * mu * volume_ratio)
    return a, b


def solve_shell(mesh_path):
    """The FEM solve on one mesh: errors, solver figures and the size of the mesh."""
    points, tetrahedra, labels = example.read_tetrahedra(mesh_path)
    msh, _ = example.create_dolfinx_mesh(points, tetrahedra, labels)
    a, b = lame_coefficients()
    x = ufl.SpatialCoordinate(msh)
    exact = (a + b / ufl.sqrt(ufl.dot(x, x)) ** 3) * x

    # Inner and outer boundary facets, told apart by their midpoints' radii.
    msh.topology.create_connectivity(2, 3)
    boundary = mesh.exterior_facet_indices(msh.topology)
    midpoint_radii = np.linalg.norm(mesh.compute_midpoints(msh, 2, boundary), axis=1)
    inner = boundary[midpoint_radii < 0.5 * (INNER_RADIUS + OUTER_RADIUS)]
    outer = np.setdiff1d(boundary, inner)
    inner_tags = mesh.meshtags(msh, 2, inner, np.ones(len(inner), np.int32))
    ds = ufl.Measure("ds", domain=msh, subdomain_data=inner_tags, metadata={"quadrature_degree": 4})
    normal = ufl.FacetNormal(msh)

    def exact_displacement(p):
        return (a + b / np.linalg.norm(p, axis=0) ** 3) * p

    young = fem.Constant(msh, YOUNG)
    solve = lambda traction: example.solve_elasticity(  # noqa: E731
        msh, young, POISSON, dirichlet=[(outer, exact_displacement)], loads=[(ds(1), traction)]
    )
    start = time.time()
    u, iterations, condition = solve(-PRESSURE * normal)
    seconds = time.time() - start
    u_consistent, _, _ = solve(ufl.dot(example.stress(exact, young, POISSON), normal))

    def norm(expression, degree):
        return math.sqrt(fem.assemble_scalar(fem.form(expression * ufl.dx(metadata={"quadrature_degree": degree}))))

    exact_l2 = norm(ufl.dot(exact, exact), 6)
    exact_h1 = norm(ufl.inner(ufl.grad(exact), ufl.grad(exact)), 4)
    volume = fem.assemble_scalar(fem.form(fem.Constant(msh, 1.0) * ufl.dx))
    return {
        "tetrahedra": len(tetrahedra),
        "vertices": len(points),
        "h_mm": (volume / len(tetrahedra)) ** (1.0 / 3.0),
        "min_dihedral_deg": example.minimum_dihedral_angle(points, tetrahedra),
        "l2_error": norm(ufl.dot(u - exact, u - exact), 6) / exact_l2,
        "h1_error": norm(ufl.inner(ufl.grad(u - exact), ufl.grad(u - exact)), 4) / exact_h1,
        "geometry_l2": norm(ufl.dot(u - u_consistent, u - u_consistent), 2) / exact_l2,
        "cg_iterations": iterations,
        "condition_estimate": condition,
        "solve_seconds": seconds,
    }


def slope(x, y):
    """Least-squares slope of log y against log x."""
    return float(np.polyfit(np.log(x), np.log(y), 1)[0])


def run(command):
    result = subprocess.run(command, capture_output=True, text=True, timeout=600)
    check(result.returncode == 0,
          f"{' '.join(command)} failed ({result.returncode}):\n{result.stdout}\n{result.stderr}")
    return result.stdout


def size_normalised(row):
    """The L2 error times tetrahedra^(2/3): P1's error constant at a given mesh size, to compare meshes of
    different sizes."""
    return row["l2_error"] * row["tetrahedra"] ** (2.0 / 3.0)


def mesh_ours(program, image, delta, directory, name, options=()):
    path = os.path.join(directory, f"{name}-{delta}.vtu")
    report_path = os.path.join(directory, f"{name}-{delta}.json")
    # The output directory outlives the run: the files read below must be this run's.
    for stale in (path, report_path):
        if os.path.exists(stale):
            os.remove(stale)
    run([program, image, path, "--delta", str(delta), "--quiet", "--distance", "--report", report_path,
         *options])
    with open(report_path) as stream:
        distance = json.load(stream)["distance_to_marching_cubes"]
        return path, {"mean_distance_mm": distance["mean_mm"], "p95_distance_mm": distance["percentile95_mm"]}


def mesh_cgal(cgal_program, image, delta, directory, ours):
    """CGAL Mesh_3 with facet_size = delta and the benchmark's facet_distance matching to `ours` (its mean and 95th
    percentile distances): the tightest bound at which neither of ours is worse than CGAL's by more than 10 %."""
    path = os.path.join(directory, f"cgal-{delta}.vtu")
    match = json.loads(run([cgal_program, image, path, "--delta", str(delta), "--match-mean-distance",
                            str(ours["mean_distance_mm"]), "--match-p95-distance", str(ours["p95_distance_mm"])]))
    return path, {"mean_distance_mm": match["matched_mean_distance_mm"],
                  "facet_distance_mm": match["facet_distance_mm"]}


def print_table(rows):
    print("| delta mm | mesher | tetrahedra | h mm | mean distance mm | min dihedral deg | L2 error | "
          "L2 error x tets^(2/3) | H1 error | geometry share of L2 | CG iterations | condition estimate | seconds |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for row in rows:
        mesher = row["mesher"]
        if "facet_distance_mm" in row:
            facet_distance = row["facet_distance_mm"]
            mesher += f" (facet_distance {facet_distance:.3f})" if facet_distance > 0 else " (facet_distance off)"
        print(f"| {row['delta']} | {mesher} | {row['tetrahedra']} | {row['h_mm']:.3f} | "
              f"{row['mean_distance_mm']:.4f} | {row['min_dihedral_deg']:.2f} | {row['l2_error']:.3e} | "
              f"{size_normalised(row):.1f} | {row['h1_error']:.3e} | {row['geometry_l2'] / row['l2_error']:.2f} | "
              f"{row['cg_iterations']} | {row['condition_estimate']:.0f} | {row['seconds']:.1f} |")
    for mesher in dict.fromkeys(row["mesher"] for row in rows):
        mine = [row for row in rows if row["mesher"] == mesher]
        sizes, deltas = [row["h_mm"] for row in mine], [row["delta"] for row in mine]
        l2, h1 = [row["l2_error"] for row in mine], [row["h1_error"] for row in mine]
        print(f"{mesher}: L2 error ~ h^{slope(sizes, l2):.2f} ~ delta^{slope(deltas, l2):.2f}; "
              f"H1 error ~ h^{slope(sizes, h1):.2f} ~ delta^{slope(deltas, h1):.2f}")


def main(program, cgal_program, examples_directory, output_directory):
    global example
    sys.path.insert(0, examples_directory)
    import elasticity_dolfinx as example  # noqa: E402: the example's functions are what the test exercises

    os.makedirs(output_directory, exist_ok=True)
    image = os.path.join(output_directory, "shell.mha")
    shell_image(image)
    rows = []
    for delta in DELTAS:
        meshings = [("ours", lambda: mesh_ours(program, image, delta, output_directory, "ours")),
                    # The paper's method, without sliver removal, reported only.
                    ("ours, min dihedral 0", lambda: mesh_ours(program, image, delta, output_directory,
                                                               "ours-sigma0", ["--min-dihedral", "0"]))]
        if cgal_program != "-":
            meshings.append(("CGAL Mesh_3", lambda: mesh_cgal(cgal_program, image, delta, output_directory,
                                                              rows[-2])))
        for mesher, meshing in meshings:
            start = time.time()
            path, row = meshing()
            row.update(solve_shell(path), mesher=mesher, delta=delta, seconds=time.time() - start)
            rows.append(row)
    print_table(rows)

    ours = [row for row in rows if row["mesher"] == "ours"]
    rate_h = slope([row["h_mm"] for row in ours], [row["l2_error"] for row in ours])
    rate_delta = slope(DELTAS, [row["l2_error"] for row in ours])
    check(rate_h >= MINIMUM_RATE_AGAINST_SIZE,
          f"the L2 error falls as h^{rate_h:.2f} on our meshes, slower than h^{MINIMUM_RATE_AGAINST_SIZE}")
    check(rate_delta >= MINIMUM_RATE_AGAINST_DELTA,
          f"the L2 error falls as delta^{rate_delta:.2f} on our meshes, slower than delta^{MINIMUM_RATE_AGAINST_DELTA}")
    for row in rows:
        check(row["geometry_l2"] <= MAXIMUM_GEOMETRY_SHARE * row["l2_error"],
              f"{row['mesher']}, delta {row['delta']}: the boundary's shape accounts for "
              f"{row['geometry_l2'] / row['l2_error']:.2f} of the L2 error, more than {MAXIMUM_GEOMETRY_SHARE:.2f}")
    for theirs in (row for row in rows if row["mesher"] == "CGAL Mesh_3"):
        mine = next(row for row in ours if row["delta"] == theirs["delta"])
        check(mine["l2_error"] <= theirs["l2_error"],
              f"delta {mine['delta']}: L2 error {mine['l2_error']:.3e} on our mesh, worse than "
              f"{theirs['l2_error']:.3e} on CGAL's")
        check(size_normalised(mine) <= size_normalised(theirs),
              f"delta {mine['delta']}: L2 error x tetrahedra^(2/3) {size_normalised(mine):.1f} on our mesh, worse than "
              f"{size_normalised(theirs):.1f} on CGAL's")
    print("PASSED")


if __name__ == "__main__":
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    main(*sys.argv[1:])
