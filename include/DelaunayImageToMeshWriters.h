/*=========================================================================
 *
 *  Copyright NumFOCUS
 *
 *  Licensed under the Apache License, Version 2.0 (the "License");
 *  you may not use this file except in compliance with the License.
 *  You may obtain a copy of the License at
 *
 *         http://www.apache.org/licenses/LICENSE-2.0.txt
 *
 *  Unless required by applicable law or agreed to in writing, software
 *  distributed under the License is distributed on an "AS IS" BASIS,
 *  WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
 *  See the License for the specific language governing permissions and
 *  limitations under the License.
 *
 *=========================================================================*/
#ifndef DelaunayImageToMeshWriters_h
#define DelaunayImageToMeshWriters_h

#include "DelaunayRefinementTypes.h"

#include <string>
#include <vector>

namespace delaunay_refinement
{

/** Writes a labelled tetrahedral mesh to a file whose format is chosen by the file name's extension
 * (case-insensitive):
 * - `.vtu`: VTK XML unstructured grid, binary data mode. Cells are the tetrahedra (VTK_TETRA), with an Int32
 *   cell-data array "label" holding the tetrahedron labels.
 * - `.vtk`: VTK legacy unstructured grid (file version 4.2, binary), with the same content as `.vtu`.
 * - `.msh`: Gmsh 4.1 ASCII. Every tetrahedron label L is a volume entity carrying the physical group L named
 *   "label_L"; every distinct pair (a, b) of boundary-triangle labels is a surface entity carrying a physical
 *   group named "interface_a_b", whose tag is the largest positive tetrahedron label (0 if none) plus the rank of
 *   the pair in lexicographic order (1 for the first), so that it never equals a tissue label. Element tags are 1 + the
 * tetrahedron index for tetrahedra and 1 + (number of tetrahedra) + the triangle index for boundary triangles.
 * - `.mesh`: Medit ASCII (MeshVersionFormatted 2, double precision): vertices with reference 0, tetrahedra with
 *   their label as reference, boundary triangles with the interface tag of their label pair (as in `.msh`) as
 *   reference; comment lines list which label pair each triangle reference stands for.
 *
 * Coordinates are written with enough digits to be read back exactly. The point kinds are not written.
 *
 * \param mesh  The mesh to write. Its arrays must be consistent: one label per tetrahedron, one label pair per
 *              boundary triangle, every point index less than the number of points.
 * \param fileName  Path of the file to create or overwrite; its extension must be one of
 *                  SupportedMeshFileExtensions().
 * \throws std::invalid_argument  if the extension is not supported, if the mesh arrays are inconsistent, or (for
 *                                `.msh`, whose physical tags must be positive) if a tetrahedron label is not
 *                                positive. Nothing is written then.
 * \throws std::runtime_error  if the file cannot be created or fully written; the incomplete file is removed. */
void
WriteTetrahedralMesh(const TetrahedralMesh & mesh, const std::string & fileName);

/** The file name extensions accepted by WriteTetrahedralMesh(), in lower case with the leading dot:
 * {".vtu", ".vtk", ".msh", ".mesh"}. */
std::vector<std::string>
SupportedMeshFileExtensions();

} // namespace delaunay_refinement

#endif
