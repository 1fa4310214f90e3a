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

// Bit-exact mesh fingerprints: every bit of a few meshes (coordinates, vertex kinds, tetrahedra, labels, boundary
// triangles) hashed and compared with test/Baseline/MeshFingerprints.txt. The other tests compare with
// tolerances, so they cannot prove that a change meant to move code (not to change meshes) changed nothing; this
// one can. A change that is meant to alter meshes updates the baseline on purpose (see that file's header):
// set DELAUNAY_WRITE_FINGERPRINTS to a path and the test writes the fingerprints it computed there.

#include "DelaunayRefinementAnalyticOracles.h"
#include "DelaunayRefinementMesher.h"
#include "itkDelaunayImageToMeshFilter.h"
#include "itkDelaunayImageToMeshFilterTestHelpers.h"

#include "itkImageFileReader.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

namespace
{

namespace dr = delaunay_refinement;

/** FNV-1a over the bytes of every field, in the mesh's own order: any change of a bit, an index or an order shows. */
class MeshHash
{
public:
  template <typename T>
  void
  Add(const T & value)
  {
    static_assert(std::is_trivially_copyable<T>::value, "hash plain values only");
    unsigned char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    for (const unsigned char byte : bytes)
    {
      m_Hash = (m_Hash ^ byte) * Prime;
    }
  }

  template <typename T>
  void
  AddAll(const std::vector<T> & values)
  {
    Add(values.size());
    for (const T & value : values)
    {
      Add(value);
    }
  }

  uint64_t
  Value() const
  {
    return m_Hash;
  }

private:
  static constexpr uint64_t Prime = 1099511628211ULL;
  uint64_t                  m_Hash{ 14695981039346656037ULL };
};

std::string
FingerprintOf(const dr::TetrahedralMesh & mesh)
{
  MeshHash hash;
  hash.AddAll(mesh.points);
  hash.AddAll(mesh.pointKinds);
  hash.AddAll(mesh.tetrahedra);
  hash.AddAll(mesh.tetrahedronLabels);
  hash.AddAll(mesh.boundaryTriangles);
  hash.AddAll(mesh.boundaryTriangleLabels);
  std::ostringstream text;
  text << mesh.points.size() << " points, " << mesh.tetrahedra.size() << " tetrahedra, "
       << mesh.boundaryTriangles.size() << " triangles, hash " << std::hex << hash.Value();
  return text.str();
}

/** name -> fingerprint, from the baseline file: one "name: fingerprint" line each; '#' starts a comment line. */
std::map<std::string, std::string>
ReadBaseline()
{
  std::ifstream                      file(DelaunayImageToMesh_FINGERPRINT_BASELINE);
  std::map<std::string, std::string> fingerprints;
  std::string                        line;
  while (std::getline(file, line))
  {
    const std::size_t colon = line.find(": ");
    if (line.empty() || line[0] == '#' || colon == std::string::npos)
    {
      continue;
    }
    fingerprints[line.substr(0, colon)] = line.substr(colon + 2);
  }
  return fingerprints;
}

void
ExpectFingerprint(const std::string & name, const dr::TetrahedralMesh & mesh)
{
  static const std::map<std::string, std::string> baseline = ReadBaseline();
  const std::string                               fingerprint = FingerprintOf(mesh);
  if (const char * output = std::getenv("DELAUNAY_WRITE_FINGERPRINTS"))
  {
    std::ofstream(output, std::ios::app) << name << ": " << fingerprint << '\n';
  }
  const auto expected = baseline.find(name);
  ASSERT_NE(expected, baseline.end()) << "no fingerprint for " << name
                                      << " in " DelaunayImageToMesh_FINGERPRINT_BASELINE;
  EXPECT_EQ(fingerprint, expected->second) << name << ": the mesh changed";
}

dr::RefinementParameters
ParametersWithDelta(double delta)
{
  dr::RefinementParameters parameters;
  parameters.surfaceSamplingDistance = delta;
  return parameters;
}

TEST(MeshFingerprint, AnalyticShapes)
{
  const dr::SphereOracle        sphere({ { 1.5, -2.25, 0.75 } }, 10.0);
  const dr::TorusOracle         torus({ { 0.5, 0.25, -0.5 } }, 10.0, 4.0);
  const dr::Genus2Oracle        genus2({ { 0.25, -0.5, 0.5 } }, 8.0, 7.0, 4.0, 2.0);
  const dr::NestedSpheresOracle nestedSpheres({ { -0.5, 1.0, 0.25 } }, 5.0, 10.0);
  ExpectFingerprint("sphere delta 2", dr::RefineMesh(sphere, ParametersWithDelta(2.0)));
  ExpectFingerprint("torus delta 1.5", dr::RefineMesh(torus, ParametersWithDelta(1.5)));
  ExpectFingerprint("genus2 delta 1", dr::RefineMesh(genus2, ParametersWithDelta(1.0)));
  ExpectFingerprint("nested spheres delta 1.5", dr::RefineMesh(nestedSpheres, ParametersWithDelta(1.5)));
  // The defaults remove slivers (σ = 10°); the paper's method, without it, keeps a fingerprint of its own.
  dr::RefinementParameters withoutSliverRemoval = ParametersWithDelta(2.0);
  withoutSliverRemoval.minimumDihedralAngle = 0.0;
  ExpectFingerprint("sphere delta 2 sigma 0", dr::RefineMesh(sphere, withoutSliverRemoval));
}

using LabelImageType = itk::Image<uint8_t, 3>;
using FilterType = itk::DelaunayImageToMeshFilter<LabelImageType, itk::delaunay_image_to_mesh_test::MeshType>;

const dr::TetrahedralMesh &
MeshOfExampleImage(const std::string & fileName, double delta, const std::vector<int32_t> & labels, bool merge)
{
  auto filter = FilterType::New();
  filter->SetInput(
    itk::ReadImage<LabelImageType>(itk::delaunay_image_to_mesh_test::ExamplesDataDirectory() + fileName));
  filter->SetSurfaceSamplingDistance(delta);
  filter->SetLabels(labels);
  filter->SetMergeLabels(merge);
  filter->Update();
  static std::map<std::string, dr::TetrahedralMesh> keep;
  return keep[fileName + std::to_string(delta)] = filter->GetRefinedMesh();
}

TEST(MeshFingerprint, BrainMask)
{
  for (const double delta : { 4.0, 6.0 })
  {
    ExpectFingerprint("brain mask delta " + std::to_string(static_cast<int>(delta)),
                      MeshOfExampleImage("KmeansTest_T1RawSkullStrip.nii.gz", delta, {}, true));
  }
}

TEST(MeshFingerprint, KmeansTissues)
{
  ExpectFingerprint("kmeans tissues delta 4",
                    MeshOfExampleImage("KmeansTest_T1KmeansPrelimSegmentation.nii.gz", 4.0, { 2, 3, 4, 5, 6 }, false));
}

} // namespace
