#!/usr/bin/python3
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
"""Renders PNG pictures of a labelled tetrahedral mesh (.vtu or .vtk from delaunay-image-to-mesh).

--surface: the boundary surface coloured by label, with its triangles' edges.
--cut: the tetrahedra on one side of a plane through the mesh (whole cells, not clipped, so the graded
interior tetrahedra show), coloured by label with their edges, and the rest of the boundary faint.

Runs with Debian's python3-vtk9 (/usr/bin/python3). VTK renders off-screen, but Debian's VTK still
needs an X display for its OpenGL context: without one, run under xvfb-run -a.
"""

import argparse
import sys

import vtk

# Well-separated colours (Okabe-Ito), assigned to the labels in increasing order.
LABEL_COLOURS = [
    (0.90, 0.62, 0.00),
    (0.34, 0.71, 0.91),
    (0.00, 0.62, 0.45),
    (0.94, 0.89, 0.26),
    (0.00, 0.45, 0.70),
    (0.84, 0.37, 0.00),
    (0.80, 0.47, 0.65),
]
AXES = {"x": 0, "y": 1, "z": 2}


def read_mesh(path):
    if path.lower().endswith(".vtu"):
        reader = vtk.vtkXMLUnstructuredGridReader()
    elif path.lower().endswith(".vtk"):
        reader = vtk.vtkUnstructuredGridReader()
    else:
        sys.exit(f"render_mesh.py: error: '{path}' is not a .vtu or .vtk file")
    reader.SetFileName(path)
    reader.Update()
    mesh = reader.GetOutput()
    if mesh.GetNumberOfCells() == 0 or mesh.GetCellData().GetArray("label") is None:
        sys.exit(f"render_mesh.py: error: '{path}' holds no cells with a 'label' array")
    mesh.GetCellData().SetActiveScalars("label")
    return mesh


def label_lookup_table(mesh):
    """A categorical lookup table: one colour and one legend entry per label."""
    labels = mesh.GetCellData().GetArray("label")
    values = sorted({int(labels.GetValue(i)) for i in range(labels.GetNumberOfValues())})
    table = vtk.vtkLookupTable()
    table.IndexedLookupOn()
    table.SetNumberOfTableValues(len(values))
    for index, value in enumerate(values):
        table.SetTableValue(index, *LABEL_COLOURS[index % len(LABEL_COLOURS)], 1.0)
        table.SetAnnotation(vtk.vtkVariant(value), f"label {value}")
    return table


def surface_actor(data, table, edges=True, opacity=1.0):
    surface = vtk.vtkDataSetSurfaceFilter()
    surface.SetInputData(data)
    mapper = vtk.vtkPolyDataMapper()
    mapper.SetInputConnection(surface.GetOutputPort())
    mapper.SetScalarModeToUseCellData()
    mapper.SetLookupTable(table)
    mapper.UseLookupTableScalarRangeOn()
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetOpacity(opacity)
    if edges:
        actor.GetProperty().EdgeVisibilityOn()
        actor.GetProperty().SetEdgeColor(0.15, 0.15, 0.15)
        actor.GetProperty().SetLineWidth(0.6)
    return actor


def legend(table, title):
    bar = vtk.vtkScalarBarActor()
    bar.SetLookupTable(table)
    bar.SetTitle(title)
    bar.SetNumberOfLabels(0)
    bar.SetMaximumWidthInPixels(140)
    bar.SetMaximumHeightInPixels(260)
    bar.SetPosition(0.86, 0.05)
    bar.UnconstrainedFontSizeOn()
    bar.GetTitleTextProperty().SetFontSize(20)
    bar.GetAnnotationTextProperty().SetFontSize(16)
    for text in (bar.GetTitleTextProperty(), bar.GetAnnotationTextProperty()):
        text.SetColor(0.1, 0.1, 0.1)
        text.ShadowOff()
        text.ItalicOff()
    return bar


def caption(text):
    actor = vtk.vtkTextActor()
    actor.SetInput(text)
    actor.SetPosition(12, 12)
    actor.GetTextProperty().SetFontSize(18)
    actor.GetTextProperty().SetColor(0.1, 0.1, 0.1)
    return actor


def write_png(actors, camera_setup, path, size):
    renderer = vtk.vtkRenderer()
    renderer.SetBackground(1.0, 1.0, 1.0)
    for actor in actors:
        renderer.AddViewProp(actor)
    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(*size)
    window.AddRenderer(renderer)
    renderer.ResetCamera()
    camera_setup(renderer.GetActiveCamera())
    renderer.ResetCameraClippingRange()
    window.Render()
    image = vtk.vtkWindowToImageFilter()
    image.SetInput(window)
    image.ReadFrontBufferOff()
    writer = vtk.vtkPNGWriter()
    writer.SetFileName(path)
    writer.SetInputConnection(image.GetOutputPort())
    writer.Write()


def view_from(axis, azimuth, elevation):
    """A camera on the +axis side of the mesh looking back at it, z (or y for a z view) up, then turned by
    azimuth degrees about the up direction and raised by elevation degrees."""

    def setup(camera):
        position = list(camera.GetFocalPoint())
        position[axis] += camera.GetDistance()
        camera.SetPosition(position)
        camera.SetViewUp([0.0, 0.0, 1.0] if axis != 2 else [0.0, 1.0, 0.0])
        camera.Azimuth(azimuth)
        camera.Elevation(elevation)
        camera.OrthogonalizeViewUp()
        camera.Zoom(1.2)

    return setup


def render_surface(mesh, path, arguments):
    table = label_lookup_table(mesh)
    actors = [
        surface_actor(mesh, table),
        legend(table, "tissue"),
        caption(f"boundary surface: {mesh.GetNumberOfCells()} tetrahedra, {mesh.GetNumberOfPoints()} vertices"),
    ]
    view = view_from(AXES[arguments.view_axis], arguments.azimuth, arguments.elevation)
    write_png(actors, view, path, arguments.size)


def cut_plane(mesh, axis, fraction):
    bounds = mesh.GetBounds()
    origin = [(bounds[2 * i] + bounds[2 * i + 1]) / 2 for i in range(3)]
    origin[axis] = bounds[2 * axis] + fraction * (bounds[2 * axis + 1] - bounds[2 * axis])
    normal = [0.0, 0.0, 0.0]
    normal[axis] = 1.0
    plane = vtk.vtkPlane()
    plane.SetOrigin(origin)
    plane.SetNormal(normal)
    return plane


def render_cut(mesh, path, arguments):
    axis = AXES[arguments.cut_axis]
    plane = cut_plane(mesh, axis, arguments.cut_position)
    # Whole tetrahedra behind the plane (ExtractBoundaryCells keeps those it crosses): clipping them would
    # hide the mesh's own cells behind slivers of the clip.
    behind = vtk.vtkExtractGeometry()
    behind.SetInputData(mesh)
    behind.SetImplicitFunction(plane)
    behind.ExtractInsideOn()
    behind.ExtractBoundaryCellsOn()
    behind.Update()
    table = label_lookup_table(mesh)
    actors = [
        surface_actor(behind.GetOutput(), table),
        surface_actor(mesh, table, edges=False, opacity=0.12),
        legend(table, "tissue"),
        caption(f"cut at {arguments.cut_axis} = {plane.GetOrigin()[axis]:.1f} mm: whole tetrahedra, coloured by label"),
    ]

    view = view_from(axis, arguments.cut_azimuth, arguments.cut_elevation)
    write_png(actors, view, path, arguments.size)


def parse_arguments():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("mesh", help="a .vtu or .vtk file with a cell array 'label'")
    parser.add_argument("--surface", metavar="PNG", help="write the boundary surface picture here")
    parser.add_argument("--cut", metavar="PNG", help="write the cut picture here")
    parser.add_argument("--cut-axis", choices=sorted(AXES), default="x", help="normal of the cut plane (default: x)")
    parser.add_argument(
        "--cut-position",
        type=float,
        default=0.5,
        help="where the plane crosses the mesh's bounds along the axis, 0 to 1 (default: 0.5)",
    )
    parser.add_argument("--view-axis", choices=sorted(AXES), default="x", help="surface view: from this axis's + side")
    parser.add_argument("--azimuth", type=float, default=-35.0, help="surface view: degrees about the up axis")
    parser.add_argument("--elevation", type=float, default=20.0, help="surface view: degrees above the horizon")
    parser.add_argument("--cut-azimuth", type=float, default=-30.0, help="cut view: degrees off the plane's normal")
    parser.add_argument("--cut-elevation", type=float, default=20.0, help="cut view: degrees above the horizon")
    parser.add_argument("--size", type=int, nargs=2, default=[1200, 900], metavar=("WIDTH", "HEIGHT"))
    arguments = parser.parse_args()
    if not arguments.surface and not arguments.cut:
        parser.error("nothing to do: give --surface PNG and/or --cut PNG")
    return arguments


def main():
    arguments = parse_arguments()
    mesh = read_mesh(arguments.mesh)
    if arguments.surface:
        render_surface(mesh, arguments.surface, arguments)
    if arguments.cut:
        render_cut(mesh, arguments.cut, arguments)


if __name__ == "__main__":
    main()
