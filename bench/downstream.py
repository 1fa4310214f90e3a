#!/usr/bin/env python3
"""The benchmark's meshes downstream (issue #19): how a finite-element solver does on ours and on CGAL's.

    delaunay-bench --images brain-mask --deltas 2,4 --runs 1 --write-meshes DIRECTORY
    /usr/bin/python3 bench/downstream.py DIRECTORY

For every DIRECTORY/IMAGE_DELTA_MESHER.vtu that delaunay-bench wrote: P1 finite elements in DOLFINx (Debian
python3-dolfinx) on two problems, each solved with PETSc's conjugate gradients and a Jacobi preconditioner to a
relative residual of 1e-8:
- Poisson: -laplace(u) = 1 in the mesh (every tissue), u = 0 on its boundary;
- linear elasticity: E = 1, nu = 0.3, a unit body force along z, the boundary clamped.
Prints a Markdown table: tetrahedra, smallest dihedral angle, CG iterations and PETSc's condition estimate of the
preconditioned operator (from the Lanczos process of CG) for each problem.
"""
import glob
import os
import sys

import ufl
from dolfinx import fem, mesh
from petsc4py import PETSc

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples"))
import elasticity_dolfinx as example  # noqa: E402: the example's mesh reading and elasticity solve

RTOL = 1e-8


def solve_poisson(msh, boundary_facets):
    """-laplace(u) = 1, u = 0 on the boundary: CG iterations and the condition estimate."""
    V = fem.FunctionSpace(msh, ("Lagrange", 1))
    u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
    bilinear = fem.form(ufl.inner(ufl.grad(u), ufl.grad(v)) * ufl.dx)
    linear = fem.form(fem.Constant(msh, PETSc.ScalarType(1.0)) * v * ufl.dx)
    bcs = [fem.dirichletbc(PETSc.ScalarType(0.0), fem.locate_dofs_topological(V, 2, boundary_facets), V)]
    _, iterations, condition = example.solve_with_cg(V, bilinear, linear, bcs, RTOL)
    return iterations, condition


def solve_clamped_elasticity(msh, boundary_facets):
    """Linear elasticity under a unit body force, the boundary clamped: CG iterations and the condition estimate."""
    young = fem.Constant(msh, 1.0)
    body_force = fem.Constant(msh, PETSc.ScalarType((0.0, 0.0, -1.0)))
    _, iterations, condition = example.solve_elasticity(
        msh, young, 0.3, dirichlet=[(boundary_facets, (0.0, 0.0, 0.0))], loads=[(ufl.dx, body_force)], rtol=RTOL
    )
    return iterations, condition


def main(directory):
    meshers = ["ours", "ours-sliver-removal", "cgal", "cgal-optimized"]

    def order(path):
        image, delta, mesher = os.path.basename(path)[: -len(".vtu")].rsplit("_", 2)
        return image, float(delta), meshers.index(mesher) if mesher in meshers else len(meshers), mesher

    paths = sorted(glob.glob(os.path.join(directory, "*_*_*.vtu")), key=order)
    if not paths:
        sys.exit(f"no IMAGE_DELTA_MESHER.vtu in {directory}: run delaunay-bench --write-meshes {directory} first")
    print("| image | δ mm | mesher | tetrahedra | min dihedral ° | Poisson: CG iterations | Poisson: condition "
          "estimate | elasticity: CG iterations | elasticity: condition estimate |")
    print("|---|---|---|---|---|---|---|---|---|")
    for path in paths:
        image, delta, mesher = os.path.basename(path)[: -len(".vtu")].rsplit("_", 2)
        points, tetrahedra, labels = example.read_tetrahedra(path)
        msh, _ = example.create_dolfinx_mesh(points, tetrahedra, labels)
        msh.topology.create_connectivity(2, 3)
        boundary = mesh.exterior_facet_indices(msh.topology)
        poisson = solve_poisson(msh, boundary)
        elasticity = solve_clamped_elasticity(msh, boundary)
        print(f"| {image} | {delta} | {mesher} | {len(tetrahedra)} | "
              f"{example.minimum_dihedral_angle(points, tetrahedra):.2f} | {poisson[0]} | {poisson[1]:.0f} | "
              f"{elasticity[0]} | {elasticity[1]:.0f} |", flush=True)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
