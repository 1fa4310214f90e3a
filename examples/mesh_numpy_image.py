#!/usr/bin/env python3
"""Meshes a NumPy-made two-tissue image with ITK's Python wrapping and writes a .vtu with meshio.

Needs an ITK with this module wrapped (scripts/build-itk-python.sh builds one) and meshio:
    PYTHONPATH=<itk-build>/Wrapping/Generators/Python python3 examples/mesh_numpy_image.py shell.vtu
"""
import sys

import itk
import meshio
import numpy as np


def make_two_tissue_image():
    """A ball of label 2 (radius 6 mm) inside a ball of label 1 (radius 12 mm), 1 × 1 × 1.5 mm voxels."""
    spacing = np.array([1.0, 1.0, 1.5])  # x, y, z
    size = np.array([32, 32, 24])
    z, y, x = np.meshgrid(*(np.arange(n) for n in size[::-1]), indexing="ij")
    center = (size - 1) / 2.0 * spacing
    distance = np.sqrt(((x * spacing[0] - center[0]) ** 2 + (y * spacing[1] - center[1]) ** 2 + (z * spacing[2] - center[2]) ** 2))
    labels = np.where(distance < 6.0, 2, np.where(distance < 12.0, 1, 0)).astype(np.uint8)
    image = itk.image_from_array(labels)
    image.SetSpacing(spacing.tolist())
    image.SetOrigin([-center[0], -center[1], -center[2]])
    return image


def to_meshio(mesh):
    points = np.array([list(mesh.GetPoint(i)) for i in range(mesh.GetNumberOfPoints())])
    cells = mesh.GetCells()
    tetrahedra = np.array([list(cells.GetElement(i).GetPointIdsContainer()) for i in range(mesh.GetNumberOfCells())])
    labels = np.array([mesh.GetCellData().GetElement(i) for i in range(mesh.GetNumberOfCells())], dtype=np.int32)
    return meshio.Mesh(points, [("tetra", tetrahedra)], cell_data={"label": [labels]})


def main(output):
    image = make_two_tissue_image()
    mesh, _ = itk.delaunay_image_to_mesh_filter(image, delta=2.0)  # tetrahedra, interface triangles
    meshio.write(output, to_meshio(mesh))
    print(f"{mesh.GetNumberOfPoints()} points, {mesh.GetNumberOfCells()} tetrahedra written to {output}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "two-tissues.vtu")
