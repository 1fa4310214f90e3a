#!/usr/bin/env python3
"""From a segmentation to a linear-elastic finite-element solve with DOLFINx: a starting point for FEM users.

    /usr/bin/python3 examples/elasticity_dolfinx.py build/bin/delaunay-image-to-mesh OUTPUT_DIRECTORY [IMAGE]

1. IMAGE, a 3-D label image (label 1 = soft tissue, label 2 = stiff inclusion), or without it a generated one: a
   40 x 40 x 20 mm block of soft tissue holding a ball of radius 6 mm. Other labels need a Young's modulus in
   main()'s young_by_label.
2. delaunay-image-to-mesh meshes it (tetrahedra with their label as cell data, .vtu).
3. meshio reads the .vtu; dolfinx.mesh.create_mesh() builds the mesh from the NumPy arrays.
4. Each tetrahedron's label becomes its Young's modulus (a piecewise-constant "DG0" function).
5. Linear elasticity, P1 elements: the boundary facets in the lowest plane (the block's bottom face) are clamped,
   those in the highest plane (its top face) pushed down by 1 mm.
   PETSc's conjugate gradients with a Jacobi preconditioner solve it.
6. OUTPUT_DIRECTORY/displacement.xdmf holds the displacement and the von Mises stress (ParaView opens it); the
   mean strain of each tissue is printed (the labels tag the cells for integration too).

Debian packages: python3-dolfinx (DOLFINx 0.5.2; its API changes between releases), python3-meshio. Run it with
Debian's /usr/bin/python3. The functions below are what a program of one's own needs; test/ uses them too.
"""
import logging
import os
import subprocess
import sys

import meshio
import numpy as np
import ufl
from dolfinx import fem, io, mesh
from dolfinx.fem.petsc import apply_lifting, assemble_matrix, assemble_vector, set_bc
from mpi4py import MPI
from petsc4py import PETSc

# DOLFINx compiles each form to C the first time it meets it (cached in ~/.cache/fenics); keep its log quiet.
logging.getLogger().setLevel(logging.WARNING)


def write_metaimage(path, labels, spacing, origin):
    """Writes a uint8 NumPy array indexed [z, y, x] as a MetaImage (.mha) with the given spacing and origin (x, y, z,
    mm). ITK, and therefore delaunay-image-to-mesh, reads it; any other ITK-readable image (NIfTI, NRRD) works too."""
    header = (
        "ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\n"
        f"DimSize = {labels.shape[2]} {labels.shape[1]} {labels.shape[0]}\n"
        "ElementSpacing = " + " ".join(repr(float(value)) for value in spacing) + "\n"
        "Offset = " + " ".join(repr(float(value)) for value in origin) + "\n"
        "ElementType = MET_UCHAR\nElementDataFile = LOCAL\n"
    )
    with open(path, "wb") as stream:
        stream.write(header.encode("ascii"))
        stream.write(np.ascontiguousarray(labels, dtype=np.uint8).tobytes())


def mesh_image(program, image, output, delta, *options):
    """Runs delaunay-image-to-mesh on `image` with surface sampling distance `delta` (mm) and writes `output`."""
    subprocess.run([program, image, output, "--delta", str(delta), "--quiet", *options], check=True)


def read_tetrahedra(path):
    """The points (n x 3), tetrahedra (m x 4, point indices) and tetrahedron labels (m) of a mesh file."""
    data = meshio.read(path)
    tetrahedra = np.vstack([block.data for block in data.cells if block.type == "tetra"])
    labels = np.concatenate(
        [values for block, values in zip(data.cells, data.cell_data["label"]) if block.type == "tetra"]
    )
    return data.points.astype(np.float64), tetrahedra.astype(np.int64), labels.astype(np.int32)


def minimum_dihedral_angle(points, tetrahedra):
    """The smallest dihedral angle of the tetrahedra, degrees: near 0, a flat "sliver" whose gradients (strains,
    stresses) are unreliable and which can slow the solver down."""
    corners = points[tetrahedra]
    smallest = 180.0
    for i, j in ((0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)):
        k, m = [c for c in range(4) if c not in (i, j)]
        edge = corners[:, j] - corners[:, i]
        edge /= np.linalg.norm(edge, axis=1)[:, None]
        # The dihedral angle at edge ij: the angle between the other two corners' offsets, projected off the edge.
        first = corners[:, k] - corners[:, i]
        second = corners[:, m] - corners[:, i]
        first -= np.sum(first * edge, axis=1)[:, None] * edge
        second -= np.sum(second * edge, axis=1)[:, None] * edge
        cosine = np.sum(first * second, axis=1) / (np.linalg.norm(first, axis=1) * np.linalg.norm(second, axis=1))
        smallest = min(smallest, float(np.degrees(np.arccos(np.clip(cosine, -1.0, 1.0))).min()))
    return smallest


def create_dolfinx_mesh(points, tetrahedra, labels):
    """A DOLFINx mesh of P1 tetrahedra, and the labels in DOLFINx's cell order (create_mesh reorders the cells)."""
    domain = ufl.Mesh(ufl.VectorElement("Lagrange", ufl.tetrahedron, 1))
    msh = mesh.create_mesh(MPI.COMM_WORLD, tetrahedra, points, domain)
    return msh, labels[msh.topology.original_cell_index]


def cellwise_constant(msh, values_per_cell):
    """A piecewise-constant (DG0) function with one value per cell, e.g. a material parameter per tissue."""
    function = fem.Function(fem.FunctionSpace(msh, ("DG", 0)))
    function.x.array[:] = values_per_cell
    return function


def stress(u, young, poisson):
    """Linear isotropic elasticity: sigma = 2 mu eps(u) + lambda tr(eps(u)) I, with Lame's mu and lambda."""
    mu = young / (2.0 * (1.0 + poisson))
    lmbda = young * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson))
    strain = ufl.sym(ufl.grad(u))
    return 2.0 * mu * strain + lmbda * ufl.tr(strain) * ufl.Identity(len(u))


def solve_elasticity(msh, young, poisson, dirichlet, loads, rtol=1e-10):
    """Solves linear elasticity, -div sigma(u) = f, with P1 elements.

    dirichlet: (facets, value) pairs, value a constant 3-vector or a function of the points (a 3 x n array)
    that returns their displacements (3 x n);
    loads: (measure, vector) pairs, a traction on part of the boundary, e.g. (ds(1), -p n), or a body force f,
    e.g. (dx, rho g). Returns the displacement, the number of conjugate-gradient iterations (Jacobi
    preconditioner) and PETSc's estimate of the preconditioned operator's condition number (extreme singular
    values from the Lanczos process of CG)."""
    V = fem.VectorFunctionSpace(msh, ("Lagrange", 1))
    u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
    bilinear = fem.form(ufl.inner(stress(u, young, poisson), ufl.sym(ufl.grad(v))) * ufl.dx)
    zero = fem.Constant(msh, PETSc.ScalarType((0.0, 0.0, 0.0)))
    linear = fem.form(sum((ufl.dot(load, v) * measure for measure, load in loads), ufl.dot(zero, v) * ufl.dx))

    bcs = []
    for facets, value in dirichlet:
        dofs = fem.locate_dofs_topological(V, msh.topology.dim - 1, facets)
        if callable(value):
            prescribed = fem.Function(V)
            prescribed.interpolate(value)
            bcs.append(fem.dirichletbc(prescribed, dofs))
        else:
            bcs.append(fem.dirichletbc(np.asarray(value, dtype=PETSc.ScalarType), dofs, V))

    return solve_with_cg(V, bilinear, linear, bcs, rtol)


def solve_with_cg(V, bilinear, linear, bcs, rtol):
    """Assembles and solves a symmetric positive definite problem on V with CG and a Jacobi preconditioner.
    Returns the solution, the number of iterations and PETSc's estimate of the preconditioned operator's
    condition number (extreme singular values from the Lanczos process of CG)."""
    A = assemble_matrix(bilinear, bcs=bcs)
    A.assemble()
    b = assemble_vector(linear)
    apply_lifting(b, [bilinear], bcs=[bcs])
    b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
    set_bc(b, bcs)

    solver = PETSc.KSP().create(V.mesh.comm)
    solver.setOperators(A)
    solver.setType("cg")
    solver.getPC().setType("jacobi")
    solver.setTolerances(rtol=rtol, atol=0.0, max_it=100000)
    solver.setComputeSingularValues(True)
    solution = fem.Function(V)
    solver.solve(b, solution.vector)
    solution.x.scatter_forward()
    if solver.getConvergedReason() <= 0:
        raise RuntimeError(f"CG did not converge: reason {solver.getConvergedReason()}")
    largest, smallest = solver.computeExtremeSingularValues()
    return solution, solver.getIterationNumber(), largest / smallest


def make_block_with_inclusion(spacing=0.5):
    """The default image: label 1 fills a 40 x 40 x 20 mm block, label 2 a ball of radius 6 mm at its centre."""
    counts = (np.array([48.0, 48.0, 28.0]) / spacing).astype(int)  # x, y, z: the block and 4 mm of background
    x, y, z = ((np.arange(n) - (n - 1) / 2.0) * spacing for n in counts)  # voxel centres, centred on 0
    labels = np.zeros(counts[::-1], dtype=np.uint8)  # indexed [z, y, x]
    zz, yy, xx = np.meshgrid(z, y, x, indexing="ij")
    labels[(np.abs(xx) < 20) & (np.abs(yy) < 20) & (np.abs(zz) < 10)] = 1
    labels[xx**2 + yy**2 + zz**2 < 6.0**2] = 2
    origin = [x[0], y[0], z[0]]
    return labels, [spacing] * 3, origin


def main(program, output_directory, image=None):
    os.makedirs(output_directory, exist_ok=True)
    if image is None:
        image = os.path.join(output_directory, "block-with-inclusion.mha")
        write_metaimage(image, *make_block_with_inclusion())
    mesh_file = os.path.join(output_directory, "mesh.vtu")
    mesh_image(program, image, mesh_file, 2.0)

    points, tetrahedra, labels = read_tetrahedra(mesh_file)
    msh, labels = create_dolfinx_mesh(points, tetrahedra, labels)
    young_by_label = {1: 3.0, 2: 30.0}  # kPa: soft tissue, and an inclusion ten times stiffer
    young = cellwise_constant(msh, np.array([young_by_label[label] for label in labels]))
    poisson = 0.3

    # The block's bottom and top faces, found by their height (the segmentation's faces are planes of voxel faces).
    z = msh.geometry.x[:, 2]
    bottom = mesh.locate_entities_boundary(msh, 2, lambda x: np.isclose(x[2], z.min()))
    top = mesh.locate_entities_boundary(msh, 2, lambda x: np.isclose(x[2], z.max()))
    u, iterations, condition = solve_elasticity(
        msh, young, poisson, dirichlet=[(bottom, (0.0, 0.0, 0.0)), (top, (0.0, 0.0, -1.0))], loads=[]
    )

    # Von Mises stress per tetrahedron, for the picture.
    s = stress(u, young, poisson)
    deviator = s - ufl.tr(s) / 3.0 * ufl.Identity(3)
    von_mises = fem.Function(fem.FunctionSpace(msh, ("DG", 0)), name="von_Mises_stress")
    von_mises.interpolate(fem.Expression(ufl.sqrt(1.5 * ufl.inner(deviator, deviator)),
                                         von_mises.function_space.element.interpolation_points()))
    u.name = "displacement"
    with io.XDMFFile(msh.comm, os.path.join(output_directory, "displacement.xdmf"), "w") as xdmf:
        xdmf.write_mesh(msh)
        xdmf.write_function(u)
        xdmf.write_function(von_mises)

    # The labels also tag the cells for integration: dx(label) is one tissue. Mean strain magnitude per tissue.
    cell_tags = mesh.meshtags(msh, 3, np.arange(len(labels), dtype=np.int32), labels)
    dx = ufl.Measure("dx", domain=msh, subdomain_data=cell_tags)
    strain = ufl.sym(ufl.grad(u))
    one = fem.Constant(msh, 1.0)
    mean_strain = {label: fem.assemble_scalar(fem.form(ufl.sqrt(ufl.inner(strain, strain)) * dx(label)))
                   / fem.assemble_scalar(fem.form(one * dx(label))) for label in young_by_label}

    print(f"{len(points)} points, {len(tetrahedra)} tetrahedra (smallest dihedral angle "
          f"{minimum_dihedral_angle(points, tetrahedra):.2f} deg); CG + Jacobi: {iterations} iterations, condition "
          f"estimate {condition:.0f}; mean strain magnitude per label: "
          + ", ".join(f"{label}: {value:.4f}" for label, value in mean_strain.items())
          + f"; results in {output_directory}")
    return {"mesh": msh, "labels": labels, "displacement": u, "mean_strain": mean_strain, "cg_iterations": iterations}


if __name__ == "__main__":
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__)
    main(*sys.argv[1:])
