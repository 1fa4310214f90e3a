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

// The regularisation of a label image at the scale of δ (docs/algorithm.md, "Topology"). Distances are exact
// Euclidean distances between voxel centres, by the separable lower-envelope transform of Felzenszwalb and
// Huttenlocher (Distance transforms of sampled functions, Theory of Computing 8, 2012), one axis at a time, with
// the nearest site carried along where the label of the nearest survivor is needed.

#include "DelaunayRefinementLabelRegularization.h"
#include "DelaunayRefinementMesher.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <numeric>

namespace delaunay_refinement
{
namespace
{

constexpr double      Infinity = std::numeric_limits<double>::infinity();
constexpr std::size_t NoSite = std::numeric_limits<std::size_t>::max();

/** A box of voxels, possibly reaching outside the grid (where everything is background). */
struct VoxelBox
{
  std::array<long, 3> lower{};
  std::array<long, 3> size{};

  std::size_t
  NumberOfVoxels() const
  {
    return static_cast<std::size_t>(size[0] * size[1] * size[2]);
  }
};

/** Squared distances from every voxel of a box to the nearest site, and that site, by three passes of the 1-D
 * transform: after the pass along an axis, each voxel holds the nearest site among the voxels that differ from it
 * along that axis and the earlier ones only. */
class NearestSiteTransform
{
public:
  NearestSiteTransform(const VoxelBox & box, const Vector3 & spacing)
    : m_Box(box)
    , m_Spacing(spacing)
    , m_SquaredDistance(box.NumberOfVoxels(), Infinity)
    , m_Site(box.NumberOfVoxels(), NoSite)
  {}

  /** Marks a site by its index in the box; `id` is what Site() returns for the voxels nearest to it. */
  void
  AddSite(std::size_t index, std::size_t id)
  {
    m_SquaredDistance[index] = 0.0;
    m_Site[index] = id;
  }

  /** `checkpoint` is called before each pass. */
  template <typename TCheckpoint>
  void
  Compute(TCheckpoint && checkpoint)
  {
    const std::array<std::size_t, 3> strides{
      { 1, static_cast<std::size_t>(m_Box.size[0]), static_cast<std::size_t>(m_Box.size[0] * m_Box.size[1]) }
    };
    for (int axis = 0; axis < 3; ++axis)
    {
      checkpoint();
      const int         first = (axis + 1) % 3;
      const int         second = (axis + 2) % 3;
      const std::size_t length = static_cast<std::size_t>(m_Box.size[axis]);
      m_Line.resize(length);
      m_LineSite.resize(length);
      for (long b = 0; b < m_Box.size[second]; ++b)
      {
        for (long a = 0; a < m_Box.size[first]; ++a)
        {
          const std::size_t start =
            static_cast<std::size_t>(a) * strides[first] + static_cast<std::size_t>(b) * strides[second];
          TransformLine(start, strides[axis], length, m_Spacing[axis]);
        }
      }
    }
  }

  double
  SquaredDistance(std::size_t index) const
  {
    return m_SquaredDistance[index];
  }

  std::size_t
  Site(std::size_t index) const
  {
    return m_Site[index];
  }

private:
  /** The lower envelope of the parabolas (x - q h)² + f(q) over the line's finite values f(q). */
  void
  TransformLine(std::size_t start, std::size_t stride, std::size_t length, double spacing)
  {
    for (std::size_t q = 0; q < length; ++q)
    {
      m_Line[q] = m_SquaredDistance[start + q * stride];
      m_LineSite[q] = m_Site[start + q * stride];
    }
    m_Vertices.clear();
    m_Boundaries.clear();
    const auto height = [&](std::size_t q) { return m_Line[q] + (q * spacing) * (q * spacing); };
    for (std::size_t q = 0; q < length; ++q)
    {
      if (m_Line[q] == Infinity)
      {
        continue;
      }
      double boundary = -Infinity;
      while (!m_Vertices.empty())
      {
        const std::size_t last = m_Vertices.back();
        boundary = (height(q) - height(last)) / (2.0 * spacing * static_cast<double>(q - last));
        if (boundary > m_Boundaries.back())
        {
          break;
        }
        m_Vertices.pop_back();
        m_Boundaries.pop_back();
        boundary = -Infinity;
      }
      m_Vertices.push_back(q);
      m_Boundaries.push_back(m_Vertices.size() == 1 ? -Infinity : boundary);
    }
    if (m_Vertices.empty())
    {
      return;
    }
    std::size_t parabola = 0;
    for (std::size_t x = 0; x < length; ++x)
    {
      const double position = static_cast<double>(x) * spacing;
      while (parabola + 1 < m_Vertices.size() && m_Boundaries[parabola + 1] < position)
      {
        ++parabola;
      }
      const std::size_t q = m_Vertices[parabola];
      const double      offset = (static_cast<double>(x) - static_cast<double>(q)) * spacing;
      m_SquaredDistance[start + x * stride] = offset * offset + m_Line[q];
      m_Site[start + x * stride] = m_LineSite[q];
    }
  }

  VoxelBox                 m_Box;
  Vector3                  m_Spacing;
  std::vector<double>      m_SquaredDistance;
  std::vector<std::size_t> m_Site;
  std::vector<double>      m_Line;
  std::vector<std::size_t> m_LineSite;
  std::vector<std::size_t> m_Vertices;
  std::vector<double>      m_Boundaries;
};

class LabelRegularizer
{
public:
  LabelRegularizer(Label * labels, const std::array<std::size_t, 3> & size, const Vector3 & spacing, double radius,
                   const std::function<bool()> & keepGoing)
    : m_Labels(labels)
    , m_KeepGoing(keepGoing)
    , m_Size(size)
    , m_Spacing(spacing)
    , m_Radius(radius)
    // Distances are between voxel centres, but a voxel is a cube: a centre whose nearest other label's centre is
    // d away is about d - h/2 from that label's voxels. Half the smallest spacing makes the erosion see that, so
    // that a one-voxel part (d = h) goes at a radius of h/2 already, as the continuous opening would; and the
    // dilation gives back every voxel whose cube reaches a survivor's ball (r + h/2 + h/2), so that a convex part
    // wider than the ball keeps its voxels, corners included.
    , m_Reach(radius > 0.0 ? radius + 0.5 * std::min({ spacing[0], spacing[1], spacing[2] }) : 0.0)
    , m_DilationReach(radius > 0.0 ? radius + std::min({ spacing[0], spacing[1], spacing[2] }) : 0.0)
    , m_NumberOfVoxels(size[0] * size[1] * size[2])
  {}

  LabelRegularizationReport
  Run()
  {
    LabelRegularizationReport report;
    report.radius = m_Radius;
    Checkpoint();
    const std::map<Label, LabelStatistics> before = CountComponents();
    if (m_Radius > 0.0 && m_NumberOfVoxels > 0)
    {
      std::vector<bool> survives(m_NumberOfVoxels, false);
      for (const auto & [label, statistics] : before)
      {
        MarkOpening(label, statistics.bounds, survives);
      }
      report.changedVoxels = GiveRemovedVoxelsTheNearestSurvivorsLabel(survives, report);
    }
    const std::map<Label, LabelStatistics> after = CountComponents();
    for (const auto & [label, statistics] : before)
    {
      LabelRegularizationChange & change = ChangeOf(report, label);
      change.voxelsBefore = statistics.voxels;
      change.componentsBefore = statistics.components;
    }
    for (const auto & [label, statistics] : after)
    {
      LabelRegularizationChange & change = ChangeOf(report, label);
      change.voxelsAfter = statistics.voxels;
      change.componentsAfter = statistics.components;
    }
    return report;
  }

private:
  /** Throws RefinementAborted when asked to stop. The labels change only at the very end, so they are intact. */
  void
  Checkpoint() const
  {
    if (m_KeepGoing && !m_KeepGoing())
    {
      throw RefinementAborted("Label regularisation aborted by the progress observer");
    }
  }

  struct LabelStatistics
  {
    std::size_t voxels{ 0 };
    std::size_t components{ 0 };
    /** The label's voxels' bounding box, in grid coordinates. */
    std::array<long, 3> lowest{
      { std::numeric_limits<long>::max(), std::numeric_limits<long>::max(), std::numeric_limits<long>::max() }
    };
    std::array<long, 3> highest{ { -1, -1, -1 } };
    VoxelBox            bounds;
  };

  static LabelRegularizationChange &
  ChangeOf(LabelRegularizationReport & report, Label label)
  {
    auto found = std::lower_bound(
      report.labels.begin(), report.labels.end(), label, [](const LabelRegularizationChange & change, Label value) {
        return change.label < value;
      });
    if (found == report.labels.end() || found->label != label)
    {
      LabelRegularizationChange change;
      change.label = label;
      found = report.labels.insert(found, change);
    }
    return *found;
  }

  std::array<long, 3>
  CoordinatesOf(std::size_t offset) const
  {
    return { { static_cast<long>(offset % m_Size[0]),
               static_cast<long>((offset / m_Size[0]) % m_Size[1]),
               static_cast<long>(offset / (m_Size[0] * m_Size[1])) } };
  }

  bool
  IsInGrid(const std::array<long, 3> & coordinates) const
  {
    for (int axis = 0; axis < 3; ++axis)
    {
      if (coordinates[axis] < 0 || coordinates[axis] >= static_cast<long>(m_Size[axis]))
      {
        return false;
      }
    }
    return true;
  }

  /** The label at grid coordinates that may lie outside the grid (background there). */
  Label
  LabelAt(const std::array<long, 3> & coordinates) const
  {
    return IsInGrid(coordinates) ? m_Labels[GridOffset(coordinates)] : BackgroundLabel;
  }

  /** Face-connected components, voxel counts and bounding boxes of every label, by union-find. */
  std::map<Label, LabelStatistics>
  CountComponents()
  {
    std::vector<std::size_t> parent(m_NumberOfVoxels);
    std::iota(parent.begin(), parent.end(), std::size_t{ 0 });
    const auto find = [&parent](std::size_t voxel) {
      while (parent[voxel] != voxel)
      {
        parent[voxel] = parent[parent[voxel]];
        voxel = parent[voxel];
      }
      return voxel;
    };
    const std::array<std::size_t, 3> strides{ { 1, m_Size[0], m_Size[0] * m_Size[1] } };
    std::map<Label, LabelStatistics> statistics;
    for (std::size_t offset = 0; offset < m_NumberOfVoxels; ++offset)
    {
      const std::array<long, 3> coordinates = CoordinatesOf(offset);
      LabelStatistics &         entry = statistics[m_Labels[offset]];
      ++entry.voxels;
      for (int axis = 0; axis < 3; ++axis)
      {
        entry.lowest[axis] = std::min(entry.lowest[axis], coordinates[axis]);
        entry.highest[axis] = std::max(entry.highest[axis], coordinates[axis]);
        if (coordinates[axis] > 0 && m_Labels[offset - strides[axis]] == m_Labels[offset])
        {
          const std::size_t a = find(offset);
          const std::size_t b = find(offset - strides[axis]);
          parent[std::max(a, b)] = std::min(a, b);
        }
      }
    }
    for (std::size_t offset = 0; offset < m_NumberOfVoxels; ++offset)
    {
      if (find(offset) == offset)
      {
        ++statistics[m_Labels[offset]].components;
      }
    }
    m_ComponentOf.resize(m_NumberOfVoxels);
    for (std::size_t offset = 0; offset < m_NumberOfVoxels; ++offset)
    {
      m_ComponentOf[offset] = find(offset);
    }
    for (auto & [label, entry] : statistics)
    {
      // A margin of the erosion's reach (and one voxel): beyond it no voxel of another label can matter.
      for (int axis = 0; axis < 3; ++axis)
      {
        const long margin = static_cast<long>(std::ceil(m_DilationReach / m_Spacing[axis])) + 1;
        entry.bounds.lower[axis] = entry.lowest[axis] - margin;
        entry.bounds.size[axis] = entry.highest[axis] - entry.lowest[axis] + 1 + 2 * margin;
      }
    }
    return statistics;
  }

  /** Marks the voxels of `label` that its opening keeps: those within `radius` of a voxel whose nearest voxel of
   * another label is farther than `radius`. */
  void
  MarkOpening(Label label, const VoxelBox & box, std::vector<bool> & survives) const
  {
    const double         squaredRadius = m_Reach * m_Reach;
    NearestSiteTransform others(box, m_Spacing);
    ForEachVoxel(box, [&](std::size_t index, const std::array<long, 3> & coordinates) {
      if (LabelAt(coordinates) != label)
      {
        others.AddSite(index, 0);
      }
    });
    others.Compute([this] { Checkpoint(); });
    NearestSiteTransform eroded(box, m_Spacing);
    bool                 anyEroded = false;
    ForEachVoxel(box, [&](std::size_t index, const std::array<long, 3> & coordinates) {
      if (LabelAt(coordinates) == label && others.SquaredDistance(index) > squaredRadius)
      {
        eroded.AddSite(index, 0);
        anyEroded = true;
      }
    });
    if (!anyEroded)
    {
      return;
    }
    eroded.Compute([this] { Checkpoint(); });
    ForEachVoxel(box, [&](std::size_t index, const std::array<long, 3> & coordinates) {
      if (IsInGrid(coordinates) && LabelAt(coordinates) == label &&
          eroded.SquaredDistance(index) <= m_DilationReach * m_DilationReach)
      {
        survives[GridOffset(coordinates)] = true;
      }
    });
  }

  std::size_t
  GridOffset(const std::array<long, 3> & coordinates) const
  {
    return static_cast<std::size_t>(coordinates[0]) +
           m_Size[0] *
             (static_cast<std::size_t>(coordinates[1]) + m_Size[1] * static_cast<std::size_t>(coordinates[2]));
  }

  /** Calls visit(index in box, grid coordinates) for every voxel of the box, in index order. */
  template <typename TVisit>
  static void
  ForEachVoxel(const VoxelBox & box, TVisit && visit)
  {
    std::size_t index = 0;
    for (long k = 0; k < box.size[2]; ++k)
    {
      for (long j = 0; j < box.size[1]; ++j)
      {
        for (long i = 0; i < box.size[0]; ++i, ++index)
        {
          visit(index, std::array<long, 3>{ { box.lower[0] + i, box.lower[1] + j, box.lower[2] + k } });
        }
      }
    }
  }

  /** Every voxel its opening removed takes the label of the nearest survivor. Returns how many changed. */
  std::size_t
  GiveRemovedVoxelsTheNearestSurvivorsLabel(const std::vector<bool> & survives, LabelRegularizationReport & report)
  {
    VoxelBox grid;
    for (int axis = 0; axis < 3; ++axis)
    {
      grid.size[axis] = static_cast<long>(m_Size[axis]);
    }
    NearestSiteTransform survivors(grid, m_Spacing);
    bool                 anySurvivor = false;
    for (std::size_t offset = 0; offset < m_NumberOfVoxels; ++offset)
    {
      if (survives[offset])
      {
        survivors.AddSite(offset, offset);
        anySurvivor = true;
      }
    }
    if (!anySurvivor)
    {
      return 0;
    }
    survivors.Compute([this] { Checkpoint(); });
    std::vector<Label> result(m_Labels, m_Labels + m_NumberOfVoxels);
    std::size_t        changed = 0;
    // A component of the input removed whole has no voxel that kept its label.
    std::vector<bool> componentKeepsAVoxel(m_NumberOfVoxels, false);
    for (std::size_t offset = 0; offset < m_NumberOfVoxels; ++offset)
    {
      if (!survives[offset])
      {
        result[offset] = m_Labels[survivors.Site(offset)];
      }
      if (result[offset] != m_Labels[offset])
      {
        ++changed;
        ++ChangeOf(report, m_Labels[offset]).voxelsRemoved;
        ++ChangeOf(report, result[offset]).voxelsAdded;
      }
      else
      {
        componentKeepsAVoxel[m_ComponentOf[offset]] = true;
      }
    }
    for (std::size_t offset = 0; offset < m_NumberOfVoxels; ++offset)
    {
      if (m_ComponentOf[offset] == offset && !componentKeepsAVoxel[offset])
      {
        ++ChangeOf(report, m_Labels[offset]).componentsRemoved;
      }
    }
    std::copy(result.begin(), result.end(), m_Labels);
    return changed;
  }

  Label *                       m_Labels;
  const std::function<bool()> & m_KeepGoing;
  std::array<std::size_t, 3>    m_Size;
  Vector3                       m_Spacing;
  double                        m_Radius;
  double                        m_Reach;
  double                        m_DilationReach;
  std::size_t                   m_NumberOfVoxels;
  /** The root voxel of each voxel's face-connected component, from the last CountComponents(). */
  std::vector<std::size_t> m_ComponentOf;
};

} // namespace

LabelRegularizationReport
RegularizeLabels(Label * labels, const std::array<std::size_t, 3> & size, const Vector3 & spacing, double radius,
                 const std::function<bool()> & keepGoing)
{
  return LabelRegularizer(labels, size, spacing, radius, keepGoing).Run();
}

} // namespace delaunay_refinement
