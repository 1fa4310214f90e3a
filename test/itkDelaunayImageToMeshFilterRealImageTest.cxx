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

// Regression test on a real segmented image: mesh it, voxelise the tetrahedra back onto the input grid
// (compared with a stored label image by the driver's --compare), and compare the mesh invariants with a
// stored text baseline.
//
// Usage: itkDelaunayImageToMeshFilterRealImageTest input delta labels voxelisedOutput baselineInvariants
//        measuredInvariants [countsOnly]
//   labels: "nonzero" meshes every non-zero voxel as one object (label 1); otherwise a comma-separated list
//   of the labels to mesh, each a tissue. The measured invariants are always written: copying them over the
//   baseline (after looking at them) is how the baseline is regenerated. "countsOnly" compares the counts
//   but not the topology, for segmentations whose speckle makes topology chaotic (see FilterTests.cmake).

#include "itkDelaunayImageToMeshFilter.h"
#include "itkDelaunayImageToMeshFilterTestHelpers.h"
#include "itkImageFileReader.h"
#include "itkImageFileWriter.h"
#include "itkTestingMacros.h"
#include "itkTetrahedralMeshVoxelizer.h"
#include "itksys/SystemTools.hxx"

#include <cmath>
#include <cstdlib>
#include <iostream>

namespace
{

using namespace itk::delaunay_image_to_mesh_test;
using FilterType = itk::DelaunayImageToMeshFilter<LabelImageType, MeshType>;

/** Counts (tetrahedra, boundary triangles, tetrahedra per tissue) may drift by 3 % before the mesh counts as
 * changed: a different compiler or CPU rounding the same predicates' inputs differently moves a few vertices, and
 * the refinement's cascade turns that into a few % of the elements at most. A material change (δ off by 5 %: 4.2 mm
 * for 4 mm) moves them by more (issue #17), which the former 10 % let pass. */
constexpr double CountTolerance = 0.03;

bool
CountMatches(const char * name, std::size_t measured, std::size_t baseline)
{
  const double allowed = CountTolerance * static_cast<double>(baseline);
  const bool   matches = std::abs(static_cast<double>(measured) - static_cast<double>(baseline)) <= allowed;
  std::cout << (matches ? "  ok   " : "  FAIL ") << name << ": " << measured << " (baseline " << baseline << " ± "
            << allowed << ")" << std::endl;
  return matches;
}

/** Topology (components and genus of each tissue's boundary) must not change at all. */
bool
TopologyMatches(const char * name, int measured, int baseline)
{
  const bool matches = measured == baseline;
  std::cout << (matches ? "  ok   " : "  FAIL ") << name << ": " << measured << " (baseline " << baseline << ")"
            << std::endl;
  return matches;
}

bool
InvariantsMatch(const MeshInvariants & measured, const MeshInvariants & baseline, bool compareTopology)
{
  bool matches = CountMatches("tetrahedra", measured.tetrahedra, baseline.tetrahedra);
  matches &= CountMatches("boundary triangles", measured.boundaryTriangles, baseline.boundaryTriangles);
  for (const auto & entry : baseline.tissues)
  {
    const auto found = measured.tissues.find(entry.first);
    if (found == measured.tissues.end())
    {
      std::cout << "  FAIL tissue " << entry.first << " is missing from the mesh" << std::endl;
      matches = false;
      continue;
    }
    std::cout << "tissue " << entry.first << ":" << std::endl;
    matches &= CountMatches("tetrahedra", found->second.tetrahedra, entry.second.tetrahedra);
    if (compareTopology)
    {
      matches &= TopologyMatches("components", found->second.components, entry.second.components);
      matches &= TopologyMatches("genus", found->second.genus, entry.second.genus);
    }
  }
  for (const auto & entry : measured.tissues)
  {
    if (!baseline.tissues.count(entry.first))
    {
      std::cout << "  FAIL tissue " << entry.first << " is not in the baseline" << std::endl;
      matches = false;
    }
  }
  return matches;
}

FilterType::LabelListType
ParseLabels(const std::string & text)
{
  FilterType::LabelListType labels;
  std::istringstream        list(text);
  std::string               label;
  while (std::getline(list, label, ','))
  {
    labels.push_back(std::stoi(label));
  }
  return labels;
}

} // namespace

int
itkDelaunayImageToMeshFilterRealImageTest(int argc, char * argv[])
{
  const bool countsOnly = argc == 8 && std::string(argv[7]) == "countsOnly";
  if (argc != 7 && !countsOnly)
  {
    std::cerr << "Usage: " << itkNameOfTestExecutableMacro(argv)
              << " input delta labels|nonzero voxelisedOutput baselineInvariants measuredInvariants [countsOnly]"
              << std::endl;
    return EXIT_FAILURE;
  }
  const std::string inputFileName = argv[1];
  const double      delta = std::stod(argv[2]);
  const std::string labels = argv[3];

  LabelImageType::Pointer image;
  ITK_TRY_EXPECT_NO_EXCEPTION(image = itk::ReadImage<LabelImageType>(inputFileName));
  auto filter = FilterType::New();
  if (labels == "nonzero")
  {
    image = MapLabels(*image, NonZeroToOne);
  }
  else
  {
    filter->SetLabels(ParseLabels(labels));
  }
  filter->SetInput(image);
  filter->SetSurfaceSamplingDistance(delta);
  ITK_TRY_EXPECT_NO_EXCEPTION(filter->Update());
  std::cout << "meshed in " << filter->GetRefinementStatistics().refinementSeconds << " s of refinement" << std::endl;

  const auto voxelized = itk::VoxelizeTetrahedralMesh<LabelImageType>(*filter->GetOutput(), *image);
  ITK_TRY_EXPECT_NO_EXCEPTION(itk::WriteImage(voxelized, argv[4], true));

  const MeshInvariants measured = InvariantsOf(TetrahedralMeshFromOutputs(*filter));
  const std::string    description = "Mesh invariants of " + itksys::SystemTools::GetFilenameName(inputFileName) +
                                  " at delta = " + argv[2] + " mm, labels " + labels;
  WriteInvariants(measured, description, argv[6]);
  MeshInvariants baseline;
  try
  {
    baseline = ReadInvariants(argv[5]);
  }
  catch (const std::exception & error)
  {
    std::cerr << error.what() << std::endl;
    return EXIT_FAILURE;
  }
  std::cout << "Mesh invariants against " << argv[5] << ":" << std::endl;
  if (!InvariantsMatch(measured, baseline, !countsOnly))
  {
    std::cerr << "The mesh invariants differ from the baseline; the measured ones are in " << argv[6] << std::endl;
    return EXIT_FAILURE;
  }
  std::cout << "Test finished." << std::endl;
  return EXIT_SUCCESS;
}
