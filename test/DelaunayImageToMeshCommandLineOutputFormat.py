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
"""Meshes a generated label image into one output format and re-reads the file with meshio (and with VTK for
.vtu and .vtk), checking points, tetrahedra, labels, boundary triangles and volume against the --report JSON.

Usage: DelaunayImageToMeshCommandLineOutputFormat.py PROGRAM IMAGE OUTPUT_DIRECTORY EXTENSION"""

import collections
import sys

import meshio
import numpy
import vtk

from DelaunayImageToMeshCommandLineTesting import check, mesh_and_report, relative_difference, tetrahedra_per_label

# Where each format keeps the tetrahedron labels, as meshio names them.
MESHIO_LABEL_ARRAYS = {"vtu": "label", "vtk": "label", "msh": "gmsh:physical", "mesh": "medit:ref"}
VTK_READERS = {"vtu": vtk.vtkXMLUnstructuredGridReader, "vtk": vtk.vtkUnstructuredGridReader}


def signed_volumes(points, tetrahedra):
    corners = points[tetrahedra]
    edges = corners[:, 1:, :] - corners[:, :1, :]
    return numpy.einsum("ij,ij->i", edges[:, 0], numpy.cross(edges[:, 1], edges[:, 2])) / 6.0


def check_with_meshio(path, extension, report):
    mesh = meshio.read(path)
    check(len(mesh.points) == report["vertices"], f"meshio: {len(mesh.points)} points, report: {report['vertices']}")
    label_blocks = mesh.cell_data[MESHIO_LABEL_ARRAYS[extension]]
    tetrahedra = [block.data for block in mesh.cells if block.type == "tetra"]
    labels = [labels for block, labels in zip(mesh.cells, label_blocks) if block.type == "tetra"]
    tetrahedra = numpy.concatenate(tetrahedra)
    labels = numpy.concatenate(labels)
    check(len(tetrahedra) == report["tetrahedra"],
          f"meshio: {len(tetrahedra)} tetrahedra, report: {report['tetrahedra']}")
    counts = dict(collections.Counter(int(label) for label in labels))
    check(counts == tetrahedra_per_label(report), f"meshio: tetrahedra per label {counts}, report: "
          f"{tetrahedra_per_label(report)}")
    volumes = signed_volumes(numpy.asarray(mesh.points, dtype=float), tetrahedra)
    check(volumes.min() > 0, f"meshio: a tetrahedron has volume {volumes.min()} <= 0 (orientation lost)")
    check(relative_difference(volumes.sum(), report["mesh_volume_mm3"]) < 1e-9,
          f"meshio: mesh volume {volumes.sum()}, report: {report['mesh_volume_mm3']}")
    if extension in ("msh", "mesh"):
        triangles = sum(len(block.data) for block in mesh.cells if block.type == "triangle")
        check(triangles == report["boundary_triangles"],
              f"meshio: {triangles} triangles, report: {report['boundary_triangles']} boundary triangles")


def check_with_vtk(path, extension, report):
    reader = VTK_READERS[extension]()
    reader.SetFileName(path)
    reader.Update()
    grid = reader.GetOutput()
    check(grid.GetNumberOfPoints() == report["vertices"],
          f"VTK: {grid.GetNumberOfPoints()} points, report: {report['vertices']}")
    check(grid.GetNumberOfCells() == report["tetrahedra"],
          f"VTK: {grid.GetNumberOfCells()} cells, report: {report['tetrahedra']} tetrahedra")
    cell_types = {grid.GetCellType(i) for i in range(grid.GetNumberOfCells())}
    check(cell_types == {vtk.VTK_TETRA}, f"VTK: cell types {cell_types}, expected only VTK_TETRA")
    labels = grid.GetCellData().GetArray("label")
    check(labels is not None, "VTK: no cell array 'label'")
    counts = dict(collections.Counter(int(labels.GetValue(i)) for i in range(labels.GetNumberOfValues())))
    check(counts == tetrahedra_per_label(report), f"VTK: tetrahedra per label {counts}, report: "
          f"{tetrahedra_per_label(report)}")


def main(program, image, directory, extension):
    path, report = mesh_and_report(program, image, directory, "mesh", extension, ["--delta", "2"])
    check(sorted(tetrahedra_per_label(report)) == [1, 2], f"expected labels 1 and 2, report: {report['labels']}")
    check_with_meshio(path, extension, report)
    if extension in VTK_READERS:
        check_with_vtk(path, extension, report)
    print(f"{extension}: {report['vertices']} points, {report['tetrahedra']} tetrahedra "
          f"{tetrahedra_per_label(report)}, {report['boundary_triangles']} boundary triangles: all re-read")


if __name__ == "__main__":
    main(*sys.argv[1:])
