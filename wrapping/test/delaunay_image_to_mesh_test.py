#!/usr/bin/env python3
"""Meshes a NumPy-made image through ITK's Python wrapping and checks the mesh in Python.

Run by CTest in an ITK build with Python wrapping, or directly with that build's Python path set
(scripts/build-itk-python.sh does both).
"""
import math
import sys

import itk
import numpy as np

SPACING = (0.8, 0.9, 1.2)  # x, y, z in mm
ORIGIN = (-12.0, 5.0, 30.0)
RADIUS = 8.0


def make_sphere_image(pixel_type):
    """A ball of label 3, radius 8 mm, in an anisotropic grid with a non-zero origin."""
    size = (28, 24, 18)  # x, y, z
    z, y, x = np.meshgrid(*(np.arange(n) for n in reversed(size)), indexing="ij")
    center_index = [(n - 1) / 2.0 for n in size]
    squared = sum(((c - m) * s) ** 2 for c, m, s in zip((x, y, z), center_index, SPACING))
    array = np.where(squared < RADIUS**2, 3, 0).astype(pixel_type)
    image = itk.image_from_array(array)
    image.SetSpacing(SPACING)
    image.SetOrigin(ORIGIN)
    return image, [o + m * s for o, m, s in zip(ORIGIN, center_index, SPACING)]


def physical_bounds(image):
    size = image.GetLargestPossibleRegion().GetSize()
    lower = [image.GetOrigin()[a] - 0.5 * image.GetSpacing()[a] for a in range(3)]
    upper = [image.GetOrigin()[a] + (size[a] - 0.5) * image.GetSpacing()[a] for a in range(3)]
    return lower, upper


def check_mesh(mesh, image, center, delta):
    cells = mesh.GetNumberOfCells()
    assert cells > 100, f"expected a real mesh, got {cells} cells"
    lower, upper = physical_bounds(image)
    for point_id in range(mesh.GetNumberOfPoints()):
        point = mesh.GetPoint(point_id)
        for axis in range(3):
            assert lower[axis] - 1e-9 <= point[axis] <= upper[axis] + 1e-9, f"point {point_id} {point} outside the image"
        # Every vertex lies inside the ball or on its (voxelised) surface.
        assert math.dist(point, center) <= RADIUS + max(SPACING), f"point {point_id} is off the object"
    for cell_id in range(cells):
        cell = mesh.GetCells().GetElement(cell_id)
        assert cell.GetNumberOfPoints() == 4, f"cell {cell_id} is not a tetrahedron"
        assert mesh.GetCellData().GetElement(cell_id) == 3, f"cell {cell_id} carries label {mesh.GetCellData().GetElement(cell_id)}"
    return cells


def check_diagonal_voxels():
    """Two boxes of label 1 touching along an edge of 5 voxels: joined by default (one voxel per voxel edge), kept
    apart with join_diagonal_voxels=False."""
    array = np.zeros((12, 16, 16), np.uint8)  # z, y, x
    array[3:8, 3:7, 3:7] = 1
    array[3:8, 7:11, 7:11] = 1
    image = itk.image_from_array(array)
    image.SetSpacing(SPACING)
    joined = itk.DelaunayImageToMeshFilter.New(image, SurfaceSamplingDistance=1.5)
    assert joined.GetJoinDiagonalVoxels(), "joining is the default"
    joined.Update()
    assert joined.GetNumberOfJoiningVoxels() == 5, f"{joined.GetNumberOfJoiningVoxels()} joining voxels"
    apart = itk.DelaunayImageToMeshFilter.New(image, SurfaceSamplingDistance=1.5, JoinDiagonalVoxels=False)
    apart.Update()
    assert apart.GetNumberOfJoiningVoxels() == 0, f"{apart.GetNumberOfJoiningVoxels()} joining voxels when off"
    print("diagonal voxels: 5 joined by default, none when off")


def check_topology_options():
    """Issue #14's options reach Python with the C++ defaults, and the relabelling count is there to read: none
    relabelled when the relabelling is off."""
    image, _ = make_sphere_image(np.uint8)
    filter_ = itk.DelaunayImageToMeshFilter.New(image, SurfaceSamplingDistance=2.0)
    assert filter_.GetRegularizationScale() == 0.4, f"RegularizationScale {filter_.GetRegularizationScale()}"
    assert filter_.GetTopologyRegularizationRounds() == 20, f"rounds {filter_.GetTopologyRegularizationRounds()}"
    assert filter_.GetRelabelNonManifoldPlaces(), "relabelling non-manifold places is the default"
    assert filter_.GetManifoldRefinementLevels() == 0, "the old delta halving is opt-in"
    assert filter_.GetRefineThickParts(), "every part a delta across gets tetrahedra by default"
    filter_.SetRelabelNonManifoldPlaces(False)
    filter_.Update()
    assert not filter_.GetRelabelNonManifoldPlaces()
    assert filter_.GetNumberOfTopologyRelabelledTetrahedra() == 0, "tetrahedra relabelled with the relabelling off"
    print("topology options: defaults 0.4 / 20 rounds / relabelling on / no delta halving; off relabels nothing")


def main():
    delta = 2.0
    for pixel_type in (np.uint8, np.float32):
        image, center = make_sphere_image(pixel_type)

        filter_ = itk.DelaunayImageToMeshFilter.New(image)
        filter_.SetSurfaceSamplingDistance(delta)
        filter_.SetInterpolator(itk.NearestNeighborInterpolateImageFunction.New(image))
        filter_.Update()
        cells_from_object = check_mesh(filter_.GetOutput(), image, center, delta)

        # Two outputs, so ITK's functional form returns both: the tetrahedra and the interface triangles.
        mesh, interface = itk.delaunay_image_to_mesh_filter(image, delta=delta, radius_edge_bound=2.0)
        cells_from_function = check_mesh(mesh, image, center, delta)
        assert cells_from_function == cells_from_object, "the functional form must give the same mesh"
        assert interface.GetNumberOfCells() > 50, f"{interface.GetNumberOfCells()} interface triangles"
        assert all(interface.GetCells().GetElement(i).GetNumberOfPoints() == 3 for i in range(interface.GetNumberOfCells()))
        by_long_name, _ = itk.delaunay_image_to_mesh_filter(image, surface_sampling_distance=delta)
        assert by_long_name.GetNumberOfCells() == cells_from_object, "delta= and surface_sampling_distance= differ"
        print(f"{pixel_type.__name__}: {cells_from_object} tetrahedra, labels and bounds checked")
    check_diagonal_voxels()
    check_topology_options()
    return 0


if __name__ == "__main__":
    sys.exit(main())
