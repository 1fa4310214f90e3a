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
// The regularisation of a label image at the scale of δ (docs/algorithm.md, "Topology"). Its cost follows the
// labels' interfaces, not the volume: a voxel can lose its label only within the erosion's reach of a voxel of
// another label, so the erosion and the dilation are balls stamped from the voxels at an interface, row by row
// (the ball's rows along x). Distances are exact Euclidean distances between voxel centres. Only the voxels the
// opening removed look for their nearest survivor, by the separable lower-envelope transform of Felzenszwalb and
// Huttenlocher (Distance transforms of sampled functions, Theory of Computing 8, 2012) over a box around them.

#include "DelaunayRefinementLabelRegularization.h"
#include "DelaunayRefinementLargeBuffers.h"
#include "DelaunayRefinementMesher.h"
#include "DelaunayRefinementParallel.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <thread>

namespace delaunay_refinement
{
namespace
{

constexpr double Infinity = std::numeric_limits<double>::infinity();
/** A flag per voxel of the grid, a bit each. Bytes were read a little faster, but fresh memory costs more than
 * unpacking a bit: about 2 to 3 ms a megabyte on the virtual machines we measure on, a page fault per page
 * (DelaunayRefinementLargeBuffers.h), and the flags of the brain mask resampled to 1 mm were 3.2 MB. */
class VoxelFlags
{
public:
  explicit VoxelFlags(std::size_t numberOfVoxels)
    : m_Words((numberOfVoxels + 63) / 64, 0)
  {}

  bool
  operator[](std::size_t voxel) const
  {
    return (m_Words[voxel >> 6] >> (voxel & 63)) & 1U;
  }

  void
  Set(std::size_t voxel)
  {
    m_Words[voxel >> 6] |= uint64_t{ 1 } << (voxel & 63);
  }

  /** Calls visit(voxel) for every flagged voxel, in increasing order. */
  template <typename TVisit>
  void
  ForEachSet(TVisit && visit) const
  {
    for (std::size_t word = 0; word < m_Words.size(); ++word)
    {
      for (uint64_t bits = m_Words[word]; bits != 0; bits &= bits - 1)
      {
        visit(word * 64 + static_cast<std::size_t>(__builtin_ctzll(bits)));
      }
    }
  }

private:
  LargeVector<uint64_t> m_Words;
};
/** Whether the `count` labels from `labels` are all equal, compared without a branch so that the compiler vectorises
 * it: label images are mostly long runs of one label. */
template <typename TVoxelLabel>
inline bool
AllEqual(const TVoxelLabel * labels, std::size_t count)
{
  uint32_t differs = 0;
  for (std::size_t voxel = 1; voxel < count; ++voxel)
  {
    differs |= static_cast<uint32_t>(labels[voxel] ^ labels[0]);
  }
  return differs == 0;
}

/** The end of the run of equal labels that begins at `begin` in a row of `length` labels: sixteen labels at a time
 * while they all equal the run's (AllEqual). */
template <typename TVoxelLabel>
inline std::size_t
RunEnd(const TVoxelLabel * row, std::size_t begin, std::size_t length)
{
  constexpr std::size_t chunk = 16;
  std::size_t           end = begin + 1;
  while (end + chunk <= length && row[end] == row[begin] && AllEqual(row + end, chunk))
  {
    end += chunk;
  }
  while (end < length && row[end] == row[begin])
  {
    ++end;
  }
  return end;
}

/** Grid offsets of voxels. */
using VoxelOffsets = LargeVector<std::size_t>;
/** Voxels (grid offsets) with their new labels. */
using VoxelChanges = LargeVector<std::pair<std::size_t, Label>>;
/** Below this many voxels per thread, a pass over voxels on more threads costs more than it saves. */
constexpr std::size_t MinimumVoxelsPerThread = 1 << 16;
constexpr std::size_t NoVoxel = std::numeric_limits<std::size_t>::max();

/** A box of voxels: lower corner and size, in the coordinates of the grid it is cut from. */
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

/** Squared distances from voxels of a box to the nearest site, and that site, by three passes of the 1-D transform:
 * after the pass along an axis, each voxel holds the nearest site among the voxels that differ from it along that
 * axis and the earlier ones only. The result is right at the sites and at the voxels asked for (AddQuery): a line
 * whose voxels are all sites, or hold no site yet, is the same after its pass, and the last pass skips the lines
 * without a voxel asked for. A voxel holds its site as the step to it along each axis, `TStep` each: 16 bits
 * where the box allows, six bytes a voxel where a squared distance and a site's name took twelve; the memory is
 * the regularisation's peak (DelaunayRefinementLargeBuffers.h). The distances a pass reads are computed from the
 * steps, with the same arithmetic, in the same order, as when they were stored, so they are the same numbers. */
template <typename TStep>
class NearestSiteTransform
{
public:
  /** The step of a voxel that holds no site yet. */
  static constexpr TStep NoStep = std::numeric_limits<TStep>::min();

  /** Whether every step within the box fits in `TStep` (NoStep apart). */
  static bool
  Fits(const VoxelBox & box)
  {
    return std::max({ box.size[0], box.size[1], box.size[2] }) <= static_cast<long>(std::numeric_limits<TStep>::max());
  }

  /** Every voxel of the box is to be set, as a site or not, before Compute(): the memory is not filled before
   * (the caller's one pass over the box, which can be shared among threads, does it). */
  NearestSiteTransform(const VoxelBox & box, const Vector3 & spacing)
    : m_Box(box)
    , m_Spacing(spacing)
    , m_Steps(box.NumberOfVoxels())
    , m_LastPassLines(static_cast<std::size_t>(box.size[0] * box.size[1]), 0)
  {}

  /** Sets the voxel at `index` in the box as a site. */
  void
  SetSite(std::size_t index)
  {
    m_Steps[index] = { { 0, 0, 0 } };
  }

  /** Sets the voxel at `index` in the box as not a site. */
  void
  SetNotSite(std::size_t index)
  {
    m_Steps[index] = { { NoStep, 0, 0 } };
  }

  /** Asks for the nearest site of the voxels of the line at `line` (x + size x * y) in every slice of the box. */
  void
  AddQueryLine(std::size_t line)
  {
    m_LastPassLines[line] = 1;
  }

  /** `checkpoint` is called before each pass. A pass's lines are independent: they are shared among up to
   * `threads` threads, each line's result the same whichever thread computes it. */
  template <typename TCheckpoint>
  void
  Compute(TCheckpoint && checkpoint, std::size_t threads)
  {
    const std::array<std::size_t, 3> strides{
      { 1, static_cast<std::size_t>(m_Box.size[0]), static_cast<std::size_t>(m_Box.size[0] * m_Box.size[1]) }
    };
    for (int axis = 0; axis < 3; ++axis)
    {
      checkpoint();
      // Lines next to each other along x share their cache lines: x is the inner loop wherever the lines cross it.
      const int         first = axis == 0 ? 1 : 0;
      const int         second = 3 - axis - first;
      const std::size_t length = static_cast<std::size_t>(m_Box.size[axis]);
      const std::size_t voxelsPerRange = static_cast<std::size_t>(m_Box.size[first]) * length;
      detail::ForEachRangeInParallel(static_cast<std::size_t>(m_Box.size[second]),
                                     threads,
                                     (MinimumVoxelsPerThread + voxelsPerRange - 1) / voxelsPerRange,
                                     [&](std::size_t begin, std::size_t end) {
                                       LineScratch scratch(length);
                                       for (std::size_t b = begin; b < end; ++b)
                                       {
                                         for (long a = 0; a < m_Box.size[first]; ++a)
                                         {
                                           const std::size_t start =
                                             static_cast<std::size_t>(a) * strides[first] + b * strides[second];
                                           if (axis == 0)
                                           {
                                             TransformFirstLine(start, length, scratch);
                                           }
                                           else if (axis == 1 || m_LastPassLines[start])
                                           {
                                             TransformLine(axis, start, strides[axis], length, scratch);
                                           }
                                         }
                                       }
                                     });
    }
  }

  /** The squared distance from the voxel at `index` in the box to its nearest site; infinite when it has none. */
  double
  SquaredDistance(std::size_t index) const
  {
    return SquaredDistanceAfterPass(m_Steps[index], 2);
  }

  /** Whether the voxel at `index` in the box has a nearest site. */
  bool
  HasSite(std::size_t index) const
  {
    return m_Steps[index][0] != NoStep;
  }

  /** The step from the voxel at `index` in the box to its nearest site, along each axis (HasSite() first). */
  std::array<long, 3>
  StepToSite(std::size_t index) const
  {
    const Steps & steps = m_Steps[index];
    return { { steps[0], steps[1], steps[2] } };
  }

private:
  using Steps = std::array<TStep, 3>;

  /** The squared distance of `steps` once the passes up to `axis` have run: the sum, over those axes, of the squared
   * step times the spacing, last axis first, as TransformLine() adds them. */
  double
  SquaredDistanceAfterPass(const Steps & steps, int axis) const
  {
    if (steps[0] == NoStep)
    {
      return Infinity;
    }
    double squared = 0.0;
    for (int earlier = 0; earlier <= axis; ++earlier)
    {
      const double offset = static_cast<double>(steps[earlier]) * m_Spacing[earlier];
      squared = offset * offset + squared;
    }
    return squared;
  }

  /** One line's working space, a thread's own. */
  struct LineScratch
  {
    explicit LineScratch(std::size_t length)
      : line(length)
      , lineSteps(length)
      , nextSite(length)
    {}

    std::vector<double>      line;
    std::vector<Steps>       lineSteps;
    std::vector<std::size_t> vertices;
    std::vector<double>      boundaries;
    /** TransformFirstLine()'s: the first site at or after each voxel of the line. */
    std::vector<std::size_t> nextSite;
  };

  /** The pass along x, where every voxel is a site (0) or not yet reached (infinite): each voxel takes the nearer
   * of the sites before and after it on the line, the one before on a tie, which is what the lower envelope of
   * TransformLine() gives there in exact arithmetic, at a fraction of its cost (no parabolas, no divisions). A tie
   * is two survivors at the same distance: either is a nearest one (RegularizeLabels' definition). */
  void
  TransformFirstLine(std::size_t start, std::size_t length, LineScratch & scratch)
  {
    std::vector<std::size_t> & nextSite = scratch.nextSite;
    Steps * const              steps = m_Steps.get() + start;
    constexpr auto             none = std::numeric_limits<std::size_t>::max();
    std::size_t                next = none;
    for (std::size_t x = length; x-- > 0;)
    {
      next = steps[x][0] == 0 ? x : next;
      nextSite[x] = next;
    }
    std::size_t previous = none;
    for (std::size_t x = 0; x < length; ++x)
    {
      if (steps[x][0] == 0)
      {
        previous = x;
        continue;
      }
      const std::size_t after = nextSite[x];
      if (previous == none && after == none)
      {
        return; // no site on the line
      }
      const std::size_t nearest =
        previous == none ? after : (after == none || x - previous <= after - x ? previous : after);
      steps[x] = { { static_cast<TStep>(static_cast<long>(nearest) - static_cast<long>(x)), 0, 0 } };
    }
  }

  /** The lower envelope of the parabolas (x - q h)² + f(q) over the line's finite values f(q), along `axis`. */
  void
  TransformLine(int axis, std::size_t start, std::size_t stride, std::size_t length, LineScratch & scratch)
  {
    std::vector<double> &      line = scratch.line;
    std::vector<Steps> &       lineSteps = scratch.lineSteps;
    std::vector<std::size_t> & vertices = scratch.vertices;
    std::vector<double> &      boundaries = scratch.boundaries;
    const double               spacing = m_Spacing[axis];
    bool                       holdsASite = false;
    bool                       holdsAVoxelAway = false;
    for (std::size_t q = 0; q < length; ++q)
    {
      lineSteps[q] = m_Steps[start + q * stride];
      line[q] = SquaredDistanceAfterPass(lineSteps[q], axis - 1);
      holdsASite = holdsASite || line[q] != Infinity;
      holdsAVoxelAway = holdsAVoxelAway || line[q] != 0.0;
    }
    if (!holdsASite || !holdsAVoxelAway)
    {
      return;
    }
    vertices.clear();
    boundaries.clear();
    const auto height = [&](std::size_t q) { return line[q] + (q * spacing) * (q * spacing); };
    for (std::size_t q = 0; q < length; ++q)
    {
      // A voxel at distance 0 is a site, its own nearest. Inside a run of them, only the run's ends can be nearest
      // to a voxel outside it: the sites strictly inside are left out (most voxels are sites).
      if (line[q] == Infinity ||
          (line[q] == 0.0 && q > 0 && q + 1 < length && line[q - 1] == 0.0 && line[q + 1] == 0.0))
      {
        continue;
      }
      double boundary = -Infinity;
      while (!vertices.empty())
      {
        const std::size_t last = vertices.back();
        boundary = (height(q) - height(last)) / (2.0 * spacing * static_cast<double>(q - last));
        if (boundary > boundaries.back())
        {
          break;
        }
        vertices.pop_back();
        boundaries.pop_back();
        boundary = -Infinity;
      }
      vertices.push_back(q);
      boundaries.push_back(vertices.size() == 1 ? -Infinity : boundary);
    }
    if (vertices.empty())
    {
      return;
    }
    std::size_t parabola = 0;
    for (std::size_t x = 0; x < length; ++x)
    {
      const double position = static_cast<double>(x) * spacing;
      while (parabola + 1 < vertices.size() && boundaries[parabola + 1] < position)
      {
        ++parabola;
      }
      const std::size_t q = vertices[parabola];
      if (line[x] == 0.0)
      {
        continue;
      }
      Steps steps = lineSteps[q];
      steps[axis] = static_cast<TStep>(static_cast<long>(q) - static_cast<long>(x));
      m_Steps[start + x * stride] = steps;
    }
  }

  VoxelBox                       m_Box;
  Vector3                        m_Spacing;
  UninitializedLargeArray<Steps> m_Steps;
  /** The lines of the last pass, by their voxel in the first slice, that hold a voxel asked for. */
  std::vector<uint8_t> m_LastPassLines;
};

/** The voxels within `radius` of a voxel centre (centre to centre, exact), as rows along x: for each (dy, dz), the
 * offsets -halfWidth..halfWidth. */
struct BallRow
{
  long dy{ 0 };
  long dz{ 0 };
  long halfWidth{ 0 };
};

std::vector<BallRow>
BallRows(double radius, const Vector3 & spacing, const std::array<long, 3> & longestOffset)
{
  const double squaredRadius = radius * radius;
  const auto   squaredLength = [&spacing](long dx, long dy, long dz) {
    const double x = static_cast<double>(dx) * spacing[0];
    const double y = static_cast<double>(dy) * spacing[1];
    const double z = static_cast<double>(dz) * spacing[2];
    return x * x + y * y + z * z;
  };
  std::vector<BallRow> rows;
  // Rows that would reach past every box the ball is used in can reach nothing: a radius far larger than the grid
  // (a huge δ, or a spacing a thousand times another) must not cost a ball of its own size.
  const long reachY = std::min(static_cast<long>(std::ceil(radius / spacing[1])), longestOffset[1]);
  const long reachZ = std::min(static_cast<long>(std::ceil(radius / spacing[2])), longestOffset[2]);
  for (long dz = -reachZ; dz <= reachZ; ++dz)
  {
    for (long dy = -reachY; dy <= reachY; ++dy)
    {
      if (squaredLength(0, dy, dz) > squaredRadius)
      {
        continue;
      }
      // The same predicate as every other distance test here, so that the rows hold exactly the ball's voxels.
      long halfWidth = static_cast<long>(std::ceil(radius / spacing[0]));
      while (squaredLength(halfWidth, dy, dz) > squaredRadius)
      {
        --halfWidth;
      }
      rows.push_back({ dy, dz, std::min(halfWidth, longestOffset[0]) });
    }
  }
  return rows;
}

/** One bit per voxel of a box, a row of 64-bit words for each (y, z): the opening works on whole rows, 64 voxels
 * to a word, so that its cost follows the number of rows rather than the number of voxels. Coordinates are the
 * box's own (0 .. size - 1). The words of a large box are on huge pages (LargeVector): a label's opening makes
 * about ten sets of its box, each fresh memory, and with 4 KiB pages their page faults were a third of a whole run
 * on a CT-like volume of 38 M voxels meshed coarsely (docs/algorithm.md, "Implementation"). */
class BoxBits
{
public:
  explicit BoxBits(const VoxelBox & box)
    : m_Box(box)
    , m_WordsPerRow(static_cast<std::size_t>((box.size[0] + 63) / 64))
    , m_Words(m_WordsPerRow * static_cast<std::size_t>(box.size[1] * box.size[2]), 0)
  {}

  const VoxelBox &
  Box() const
  {
    return m_Box;
  }

  std::size_t
  WordsPerRow() const
  {
    return m_WordsPerRow;
  }

  uint64_t *
  Row(long y, long z)
  {
    return m_Words.data() + m_WordsPerRow * static_cast<std::size_t>(y + m_Box.size[1] * z);
  }

  const uint64_t *
  Row(long y, long z) const
  {
    return m_Words.data() + m_WordsPerRow * static_cast<std::size_t>(y + m_Box.size[1] * z);
  }

  bool
  Test(long x, long y, long z) const
  {
    return (Row(y, z)[x >> 6] >> (x & 63)) & 1U;
  }

  void
  Set(long x, long y, long z)
  {
    Row(y, z)[x >> 6] |= uint64_t{ 1 } << (x & 63);
  }

  /** Sets the voxels [first, end) of row (y, z), a word at a time. */
  void
  SetRange(long y, long z, long first, long end)
  {
    uint64_t * words = Row(y, z);
    for (long x = first; x < end;)
    {
      const long     endOfWord = std::min(end, (x | 63) + 1);
      const uint64_t ones = ~uint64_t{ 0 } >> (63 - ((endOfWord - 1) & 63)) & ~uint64_t{ 0 } << (x & 63);
      words[x >> 6] |= ones;
      x = endOfWord;
    }
  }

  /** this = this & other, or this & ~other. */
  void
  Keep(const BoxBits & other, bool complement)
  {
    for (std::size_t word = 0; word < m_Words.size(); ++word)
    {
      m_Words[word] &= complement ? ~other.m_Words[word] : other.m_Words[word];
    }
  }

  /** this = this | other. */
  void
  Add(const BoxBits & other)
  {
    for (std::size_t word = 0; word < m_Words.size(); ++word)
    {
      m_Words[word] |= other.m_Words[word];
    }
  }

  /** Every voxel of the box not set, and only those. */
  void
  Invert()
  {
    for (std::size_t row = 0; row < m_Words.size(); row += m_WordsPerRow)
    {
      for (std::size_t word = 0; word < m_WordsPerRow; ++word)
      {
        m_Words[row + word] = ~m_Words[row + word];
      }
      m_Words[row + m_WordsPerRow - 1] &= LastWordMask();
    }
  }

  bool
  RowIsEmpty(long y, long z) const
  {
    const uint64_t * words = Row(y, z);
    return std::all_of(words, words + m_WordsPerRow, [](uint64_t word) { return word == 0; });
  }

  bool
  Any() const
  {
    return std::any_of(m_Words.begin(), m_Words.end(), [](uint64_t word) { return word != 0; });
  }

  std::size_t
  Count() const
  {
    std::size_t count = 0;
    for (const uint64_t word : m_Words)
    {
      count += static_cast<std::size_t>(__builtin_popcountll(word));
    }
    return count;
  }

  /** Every voxel of row (y, z) also sets its two neighbours along x. */
  void
  GrowRowAlongX(long y, long z)
  {
    uint64_t * words = Row(y, z);
    uint64_t   carryFromBelow = 0;
    for (std::size_t word = 0; word < m_WordsPerRow; ++word)
    {
      const uint64_t value = words[word];
      const uint64_t next = word + 1 < m_WordsPerRow ? words[word + 1] : 0;
      words[word] = value | (value << 1) | carryFromBelow | (value >> 1) | (next << 63);
      carryFromBelow = value >> 63;
    }
    words[m_WordsPerRow - 1] &= LastWordMask();
  }

  /** Calls visit(x, y, z) for every set voxel, in row order. */
  template <typename TVisit>
  void
  ForEachSet(TVisit && visit) const
  {
    for (long z = 0; z < m_Box.size[2]; ++z)
    {
      for (long y = 0; y < m_Box.size[1]; ++y)
      {
        const uint64_t * words = Row(y, z);
        for (std::size_t word = 0; word < m_WordsPerRow; ++word)
        {
          uint64_t bits = words[word];
          while (bits != 0)
          {
            visit(static_cast<long>(word * 64) + __builtin_ctzll(bits), y, z);
            bits &= bits - 1;
          }
        }
      }
    }
  }

private:
  /** The bits of a row's last word that are voxels of the box. */
  uint64_t
  LastWordMask() const
  {
    return (m_Box.size[0] & 63) == 0 ? ~uint64_t{ 0 } : (uint64_t{ 1 } << (m_Box.size[0] & 63)) - 1;
  }

  VoxelBox              m_Box;
  std::size_t           m_WordsPerRow;
  LargeVector<uint64_t> m_Words;
};

/** The voxels within the ball `rows` (centred on a voxel) of a voxel of `set`: rows along x grow a word at a time,
 * and each row of the ball ORs whole rows into the result. */
BoxBits
DilateByBall(BoxBits set, const std::vector<BallRow> & rows)
{
  const VoxelBox & box = set.Box();
  BoxBits          dilated(box);
  // The set grows along x in place: the callers' sets are temporaries.
  BoxBits & grown = set;
  long      widest = 0;
  for (const BallRow & row : rows)
  {
    widest = std::max(widest, row.halfWidth);
  }
  // Growing along x keeps empty rows empty: only the others are visited.
  std::vector<std::array<long, 2>> nonEmptyRows;
  nonEmptyRows.reserve(static_cast<std::size_t>(box.size[1] * box.size[2]));
  for (long z = 0; z < box.size[2]; ++z)
  {
    for (long y = 0; y < box.size[1]; ++y)
    {
      if (!set.RowIsEmpty(y, z))
      {
        nonEmptyRows.push_back({ { y, z } });
      }
    }
  }
  for (long width = 0; width <= widest; ++width)
  {
    if (width > 0)
    {
      for (const auto & [y, z] : nonEmptyRows)
      {
        grown.GrowRowAlongX(y, z);
      }
    }
    for (const BallRow & row : rows)
    {
      if (row.halfWidth != width)
      {
        continue;
      }
      // The ball is symmetric: the set's row (y, z) reaches the rows (y - dy, z - dz).
      for (const auto & [y, z] : nonEmptyRows)
      {
        const long targetY = y - row.dy;
        const long targetZ = z - row.dz;
        if (targetY < 0 || targetY >= box.size[1] || targetZ < 0 || targetZ >= box.size[2])
        {
          continue;
        }
        uint64_t *       target = dilated.Row(targetY, targetZ);
        const uint64_t * source = grown.Row(y, z);
        for (std::size_t word = 0; word < set.WordsPerRow(); ++word)
        {
          target[word] |= source[word];
        }
      }
    }
  }
  return dilated;
}

/** The voxel offsets within `radius` of a voxel, nearest first (ties: smaller linear offset first), with their
 * squared lengths: a search in this order stops at the first hit, which is the nearest. */
struct NeighbourOffset
{
  std::array<long, 3> delta;
  double              squaredLength;
  long                linear;
};

std::vector<NeighbourOffset>
NeighbourOffsetsByDistance(double radius, const Vector3 & spacing, const std::array<long, 3> & strides,
                           const std::array<long, 3> & longestOffset)
{
  std::vector<NeighbourOffset> offsets;
  // An offset longer than the grid along an axis leads out of it from every voxel.
  const std::array<long, 3> reach{ { std::min(static_cast<long>(std::ceil(radius / spacing[0])), longestOffset[0]),
                                     std::min(static_cast<long>(std::ceil(radius / spacing[1])), longestOffset[1]),
                                     std::min(static_cast<long>(std::ceil(radius / spacing[2])), longestOffset[2]) } };
  for (long dz = -reach[2]; dz <= reach[2]; ++dz)
  {
    for (long dy = -reach[1]; dy <= reach[1]; ++dy)
    {
      for (long dx = -reach[0]; dx <= reach[0]; ++dx)
      {
        const double x = static_cast<double>(dx) * spacing[0];
        const double y = static_cast<double>(dy) * spacing[1];
        const double z = static_cast<double>(dz) * spacing[2];
        const double squaredLength = x * x + y * y + z * z;
        if (squaredLength <= radius * radius)
        {
          offsets.push_back({ { { dx, dy, dz } }, squaredLength, dx + strides[1] * dy + strides[2] * dz });
        }
      }
    }
  }
  std::sort(offsets.begin(), offsets.end(), [](const NeighbourOffset & a, const NeighbourOffset & b) {
    return a.squaredLength < b.squaredLength || (a.squaredLength == b.squaredLength && a.linear < b.linear);
  });
  return offsets;
}
/** Face-connected components of a label image, found on its runs of equal labels along x (a uniform region is a
 * few long runs, so counting costs about a pass over the labels). The grid is cut into slabs of whole z-slices, one
 * per thread: each finds its runs and joins those within it, and the slabs' faces are joined after. A component's
 * root is always its first run (JoinOverlappingRuns), so the result does not depend on the number of threads. */
class LabelComponents
{
public:
  struct Statistics
  {
    std::size_t voxels{ 0 };
    std::size_t components{ 0 };
    /** The label's bounding box, grid coordinates. */
    std::array<long, 3> lowest{
      { std::numeric_limits<long>::max(), std::numeric_limits<long>::max(), std::numeric_limits<long>::max() }
    };
    std::array<long, 3> highest{ { -1, -1, -1 } };
  };

  /** A slab costs a thread (tens of microseconds to start): a slab of fewer voxels would save less than that. */
  static constexpr std::size_t MinimumVoxelsPerSlab = std::size_t{ 1 } << 16;

  template <typename TVoxelLabel>
  LabelComponents(const TVoxelLabel * labels, const std::array<std::size_t, 3> & size, unsigned int numberOfThreads)
    : m_Size(size)
  {
    const std::size_t lines = size[1] * size[2];
    const std::size_t voxelsPerSlice = size[0] * size[1];
    const std::size_t slabs = std::max<std::size_t>(
      1,
      std::min<std::size_t>(
        { numberOfThreads, size[2], voxelsPerSlice * size[2] / std::max(voxelsPerSlice, MinimumVoxelsPerSlab) }));
    // Slab s holds the z-slices [firstSlice[s], firstSlice[s + 1]).
    std::vector<std::size_t> firstSlice(slabs + 1);
    for (std::size_t slab = 0; slab <= slabs; ++slab)
    {
      firstSlice[slab] = size[2] * slab / slabs;
    }
    const auto inParallel = [slabs](const auto & work) { detail::ForEachIndexInParallel(slabs, slabs, work, [] {}); };
    // Each slab writes its runs from its own first run (CountRuns says why they are counted first).
    std::vector<std::size_t> firstRunOfSlab(slabs + 1, 0);
    inParallel([&](std::size_t slab) {
      firstRunOfSlab[slab + 1] = CountRuns(labels + firstSlice[slab] * voxelsPerSlice,
                                           (firstSlice[slab + 1] - firstSlice[slab]) * voxelsPerSlice,
                                           size[0]);
    });
    std::partial_sum(firstRunOfSlab.begin(), firstRunOfSlab.end(), firstRunOfSlab.begin());
    if (size[0] > std::numeric_limits<RunIndex>::max() || firstRunOfSlab[slabs] > std::numeric_limits<RunIndex>::max())
    {
      throw std::length_error("RegularizeLabels: the label image has more than 4294967295 runs of equal labels, or "
                              "rows of more voxels; the components are counted in 32 bits");
    }
    m_Runs.resize(firstRunOfSlab[slabs]);
    m_Parent.resize(firstRunOfSlab[slabs]);
    m_FirstRunOfLine.resize(lines + 1);
    m_FirstRunOfLine[lines] = firstRunOfSlab[slabs];
    std::vector<std::map<Label, Statistics>> statisticsOfSlab(slabs);
    inParallel([&](std::size_t slab) {
      const std::size_t firstLine = firstSlice[slab] * size[1];
      const std::size_t endLine = firstSlice[slab + 1] * size[1];
      std::size_t       next = firstRunOfSlab[slab];
      for (std::size_t line = firstLine; line < endLine; ++line)
      {
        m_FirstRunOfLine[line] = next;
        const std::size_t lineStart = line * size[0];
        for (std::size_t i = 0; i < size[0];)
        {
          const Label       label = labels[lineStart + i];
          const std::size_t end = RunEnd(labels + lineStart, i, size[0]);
          m_Runs[next] = { static_cast<RunIndex>(i), static_cast<RunIndex>(end - i), label };
          m_Parent[next] = static_cast<RunIndex>(next);
          ++next;
          i = end;
        }
      }
    });
    // Joins within a slab touch only its runs, but its last line's runs end where the next slab's begin: the runs
    // of every slab are found first.
    inParallel([&](std::size_t slab) {
      const std::size_t firstLine = firstSlice[slab] * size[1];
      const std::size_t endLine = firstSlice[slab + 1] * size[1];
      for (std::size_t line = firstLine; line < endLine; ++line)
      {
        if (line % size[1] > 0)
        {
          JoinOverlappingRuns(line - 1, line);
        }
        if (line >= firstLine + size[1])
        {
          JoinOverlappingRuns(line - size[1], line);
        }
      }
    });
    for (std::size_t slab = 1; slab < slabs; ++slab)
    {
      const std::size_t firstLine = firstSlice[slab] * size[1];
      for (std::size_t line = firstLine; line < firstLine + size[1]; ++line)
      {
        JoinOverlappingRuns(line - size[1], line);
      }
    }
    // A run is a component's root when it is its own parent: no Find, which would write across slabs.
    inParallel([&](std::size_t slab) {
      std::map<Label, Statistics> & statistics = statisticsOfSlab[slab];
      // Line by line, so that a run's coordinates need no divisions.
      for (std::size_t line = firstSlice[slab] * size[1]; line < firstSlice[slab + 1] * size[1]; ++line)
      {
        const long j = static_cast<long>(line % size[1]);
        const long k = static_cast<long>(line / size[1]);
        for (std::size_t run = m_FirstRunOfLine[line]; run < m_FirstRunOfLine[line + 1]; ++run)
        {
          Statistics & entry = statistics[m_Runs[run].label];
          const long   i = static_cast<long>(m_Runs[run].x);
          entry.lowest[0] = std::min(entry.lowest[0], i);
          entry.lowest[1] = std::min(entry.lowest[1], j);
          entry.lowest[2] = std::min(entry.lowest[2], k);
          entry.highest[0] = std::max(entry.highest[0], i + static_cast<long>(m_Runs[run].length) - 1);
          entry.highest[1] = std::max(entry.highest[1], j);
          entry.highest[2] = std::max(entry.highest[2], k);
          entry.voxels += m_Runs[run].length;
          entry.components += m_Parent[run] == run;
        }
      }
    });
    for (const std::map<Label, Statistics> & statistics : statisticsOfSlab)
    {
      for (const auto & [label, ofSlab] : statistics)
      {
        Statistics & entry = m_Statistics[label];
        for (int axis = 0; axis < 3; ++axis)
        {
          entry.lowest[axis] = std::min(entry.lowest[axis], ofSlab.lowest[axis]);
          entry.highest[axis] = std::max(entry.highest[axis], ofSlab.highest[axis]);
        }
        entry.voxels += ofSlab.voxels;
        entry.components += ofSlab.components;
      }
    }
  }

  const std::map<Label, Statistics> &
  PerLabel() const
  {
    return m_Statistics;
  }

  /** The component (its root run) of the voxel `x` voxels along line `line` (line = j + size[1] k). */
  std::size_t
  ComponentOf(std::size_t line, std::size_t x)
  {
    const auto first = m_Runs.begin() + static_cast<std::ptrdiff_t>(m_FirstRunOfLine[line]);
    const auto end = m_Runs.begin() + static_cast<std::ptrdiff_t>(m_FirstRunOfLine[line + 1]);
    const auto after =
      std::upper_bound(first, end, x, [](std::size_t value, const Run & run) { return value < run.x; });
    return Find(static_cast<std::size_t>(after - m_Runs.begin()) - 1);
  }

  std::size_t
  NumberOfRuns() const
  {
    return m_Runs.size();
  }

  /** Calls visit(component, label, first voxel offset, length) for every run, line by line. */
  template <typename TVisit>
  void
  ForEachRun(TVisit && visit)
  {
    for (std::size_t line = 0; line + 1 < m_FirstRunOfLine.size(); ++line)
    {
      for (std::size_t run = m_FirstRunOfLine[line]; run < m_FirstRunOfLine[line + 1]; ++run)
      {
        visit(Find(run), m_Runs[run].label, line * m_Size[0] + m_Runs[run].x, std::size_t{ m_Runs[run].length });
      }
    }
  }

  /** Calls visit(label) once for each component none of whose voxels satisfies keeps(voxel offset). */
  template <typename TKeeps, typename TVisit>
  void
  ForEachComponentLostWhole(TKeeps && keeps, TVisit && visit)
  {
    std::vector<bool> keepsAVoxel(m_Runs.size(), false);
    for (std::size_t line = 0; line + 1 < m_FirstRunOfLine.size(); ++line)
    {
      for (std::size_t run = m_FirstRunOfLine[line]; run < m_FirstRunOfLine[line + 1]; ++run)
      {
        const std::size_t start = line * m_Size[0] + m_Runs[run].x;
        for (std::size_t offset = start; offset < start + m_Runs[run].length; ++offset)
        {
          if (keeps(offset))
          {
            keepsAVoxel[Find(run)] = true;
            break;
          }
        }
      }
    }
    for (std::size_t run = 0; run < m_Runs.size(); ++run)
    {
      if (Find(run) == run && !keepsAVoxel[run])
      {
        visit(m_Runs[run].label);
      }
    }
  }

private:
  /** Runs and their places along a row in 32 bits: the run list and the parents are the largest buffers of the
   * regularisation on speckled labels (729,156 runs on the k-means tissues resampled to 1 mm: 23 MB with 64 bits,
   * 12 MB with 32), and fresh memory costs time (VoxelFlags). */
  using RunIndex = uint32_t;

  struct Run
  {
    /** Where the run begins along its row, and its length. */
    RunIndex x;
    RunIndex length;
    Label    label;
  };

  /** The number of runs of equal labels along x, lines `lineLength` long: the run list is then written once, into
   * memory allocated once, instead of being copied each time it grows (measured on the k-means tissues at δ = 18 mm,
   * a million voxels: the two passes of the regularisation were a quarter of its time, most of it in that growth). */
  template <typename TVoxelLabel>
  static std::size_t
  CountRuns(const TVoxelLabel * labels, std::size_t numberOfVoxels, std::size_t lineLength)
  {
    std::size_t runs = 0;
    for (std::size_t lineStart = 0; lineStart < numberOfVoxels; lineStart += lineLength)
    {
      ++runs;
      for (std::size_t voxel = lineStart + 1; voxel < lineStart + lineLength; ++voxel)
      {
        runs += labels[voxel] != labels[voxel - 1];
      }
    }
    return runs;
  }

  std::size_t
  Find(std::size_t run)
  {
    while (m_Parent[run] != run)
    {
      m_Parent[run] = m_Parent[m_Parent[run]];
      run = m_Parent[run];
    }
    return run;
  }

  /** Joins the runs of two neighbouring lines that share a label and overlap along x. The root of the union is the
   * smaller run, so that every component's root is its first run whatever the order of the joins. */
  void
  JoinOverlappingRuns(std::size_t lineA, std::size_t lineB)
  {
    std::size_t a = m_FirstRunOfLine[lineA];
    std::size_t b = m_FirstRunOfLine[lineB];
    while (a < m_FirstRunOfLine[lineA + 1] && b < m_FirstRunOfLine[lineB + 1])
    {
      const std::size_t endA = std::size_t{ m_Runs[a].x } + m_Runs[a].length;
      const std::size_t endB = std::size_t{ m_Runs[b].x } + m_Runs[b].length;
      if (m_Runs[a].label == m_Runs[b].label)
      {
        const std::size_t rootA = Find(a);
        const std::size_t rootB = Find(b);
        m_Parent[std::max(rootA, rootB)] = static_cast<RunIndex>(std::min(rootA, rootB));
      }
      if (endA <= endB)
      {
        ++a;
      }
      if (endB <= endA)
      {
        ++b;
      }
    }
  }

  std::array<std::size_t, 3>  m_Size;
  LargeVector<Run>            m_Runs;
  LargeVector<std::size_t>    m_FirstRunOfLine;
  LargeVector<RunIndex>       m_Parent;
  std::map<Label, Statistics> m_Statistics;
};

template <typename TVoxelLabel>
class LabelRegularizer
{
public:
  LabelRegularizer(TVoxelLabel * labels, const std::array<std::size_t, 3> & size, const Vector3 & spacing,
                   double radius, const std::function<bool(double)> & keepGoing, unsigned int numberOfThreads)
    : m_Labels(labels)
    , m_KeepGoing(keepGoing)
    , m_NumberOfThreads(std::max(1U, numberOfThreads))
    , m_Size(size)
    , m_Spacing(spacing)
    , m_Radius(radius)
    // Distances are between voxel centres, but a voxel is a cube: a centre whose nearest other label's centre is
    // d away is about d - h/2 from that label's voxels. Half the smallest spacing makes the erosion see that, so
    // that a one-voxel part (d = h) goes at a radius of h/2 already, as the continuous opening would; and the
    // dilation gives back every voxel whose cube reaches a survivor's ball (r + h/2 + h/2), so that a convex part
    // wider than the ball keeps its voxels, corners included, except beside what the opening removes (OpenLabel).
    // (The same ball for both steps, the textbook opening, takes the staircase's corners off every convex part:
    // balls of radius 5 and 7 mm at δ = 2 mm lost 2-4 % of their volume; bench/README.md, "At ac99b9d".)
    , m_Reach(Reach(radius, spacing, 0.5))
    , m_DilationReach(Reach(radius, spacing, 1.0))
    , m_NumberOfVoxels(size[0] * size[1] * size[2])
  {}

  LabelRegularizationReport
  Run()
  {
    LabelRegularizationReport report;
    report.radius = m_Radius;
    m_CallingThread = std::this_thread::get_id();
    Checkpoint();
    // The components before are freed before those after are counted, so that the second count reuses the first's
    // memory instead of faulting in fresh pages (DelaunayRefinementLargeBuffers.h says what a fault costs).
    auto before = std::make_unique<LabelComponents>(m_Labels, m_Size, m_NumberOfThreads);
    ReachStage(ProgressAfter::componentsBefore);
    for (const auto & [label, statistics] : before->PerLabel())
    {
      LabelRegularizationChange & change = ChangeOf(report, label);
      change.voxelsBefore = change.voxelsAfter = statistics.voxels;
      change.componentsBefore = change.componentsAfter = statistics.components;
    }
    if (m_Radius <= 0.0 || m_NumberOfVoxels == 0)
    {
      return report;
    }
    const VoxelChanges changes =
      ReachExceedsTheGrid() ? EveryTissueVoxelToBackground() : OpenEveryLabel(before->PerLabel());
    if (changes.empty())
    {
      return report;
    }
    report.changedVoxels = changes.size();
    std::vector<bool> changed(m_NumberOfVoxels, false);
    for (const auto & [offset, label] : changes)
    {
      ++ChangeOf(report, m_Labels[offset]).voxelsRemoved;
      ++ChangeOf(report, label).voxelsAdded;
      changed[offset] = true;
    }
    before->ForEachComponentLostWhole([&changed](std::size_t offset) { return !changed[offset]; },
                                      [&report](Label label) { ++ChangeOf(report, label).componentsRemoved; });
    before.reset();
    ReachStage(ProgressAfter::nearestSurvivors);
    for (const auto & [offset, label] : changes)
    {
      m_Labels[offset] = static_cast<TVoxelLabel>(label);
    }
    const LabelComponents after(m_Labels, m_Size, m_NumberOfThreads);
    for (auto & change : report.labels)
    {
      const auto found = after.PerLabel().find(change.label);
      change.voxelsAfter = found == after.PerLabel().end() ? 0 : found->second.voxels;
      change.componentsAfter = found == after.PerLabel().end() ? 0 : found->second.components;
    }
    return report;
  }

private:
  /** `radius` plus `voxels` times the smallest spacing, lengthened by LatticeTieMargin: the distances between voxel
   * centres are round and users choose round δ, so a reach often equals one of them, and a voxel at that distance
   * must be within the reach whatever δ's last bits (as it is at the round value itself). 0 without a radius. */
  static double
  Reach(double radius, const Vector3 & spacing, double voxels)
  {
    return radius > 0.0
             ? (radius + voxels * std::min({ spacing[0], spacing[1], spacing[2] })) * (1.0 + LatticeTieMargin)
             : 0.0;
  }

  /** Whether the erosion's reach is at least the grid's length along some axis: then every tissue voxel is within
   * the reach of the background outside the grid, and no tissue survives. */
  bool
  ReachExceedsTheGrid() const
  {
    for (int axis = 0; axis < 3; ++axis)
    {
      if (m_Reach >= static_cast<double>(m_Size[axis]) * m_Spacing[axis])
      {
        return true;
      }
    }
    return false;
  }

  /** Where no tissue survives, every tissue voxel goes to the background: the regularised object is empty, and
   * the caller says that every part of it is thinner than the scale. */
  VoxelChanges
  EveryTissueVoxelToBackground() const
  {
    VoxelChanges changes;
    for (std::size_t offset = 0; offset < m_NumberOfVoxels; ++offset)
    {
      if (m_Labels[offset] != BackgroundLabel)
      {
        changes.emplace_back(offset, BackgroundLabel);
      }
    }
    return changes;
  }

  /** Rough fractions of the work, for the progress reported to `keepGoing`: the component count before, the
   * openings (in proportion to their boxes' voxels, which their passes follow), the nearest survivors' search and
   * transform, the component count after. Measured on the CT-like probe of bench/README.md ("At 1161bcd"): the
   * openings are most of it. */
  struct ProgressAfter
  {
    static constexpr double componentsBefore = 0.05;
    static constexpr double openings = 0.85;
    static constexpr double nearestSurvivors = 0.95;
  };

  /** Throws RefinementAborted when asked to stop, and otherwise reports the fraction of the work done so far. Only on
   * the calling thread (an observer may not expect another); the other threads see the abort at their next
   * opening checkpoint. The labels change only at the very end, so they are intact. */
  void
  Checkpoint() const
  {
    if (m_KeepGoing && !m_KeepGoing(m_Reported))
    {
      m_AbortSeen = true;
      throw RefinementAborted("Label regularisation aborted by the progress observer");
    }
  }

  /** The work is done up to `fraction` (never less than reported before); checked there. */
  void
  ReachStage(double fraction) const
  {
    m_Reported = std::max(m_Reported, fraction);
    Checkpoint();
  }

  /** How far one label's opening has gone, in voxels of its box counted into m_OpenedBoxVoxels. */
  struct OpeningProgress
  {
    std::size_t boxVoxels;
    std::size_t counted;
  };

  /** Within the openings, on any thread: `partOfOwn` of the label this thread opens is done, and counted with the
   * others' progress (the openings run on the threads, the largest box first, and on a large image one label's
   * opening is a fraction of a second). The calling thread reports the openings' progress; another thread stops
   * here once the calling thread has seen an abort. */
  void
  OpeningCheckpoint(OpeningProgress & own, double partOfOwn) const
  {
    const auto reached = static_cast<std::size_t>(partOfOwn * static_cast<double>(own.boxVoxels));
    if (reached > own.counted)
    {
      m_OpenedBoxVoxels += reached - own.counted;
      own.counted = reached;
    }
    if (std::this_thread::get_id() == m_CallingThread)
    {
      ReportOpenings();
    }
    else if (m_AbortSeen)
    {
      throw RefinementAborted("Label regularisation aborted by the progress observer");
    }
  }

  /** Reports the openings' progress on every thread so far; on the calling thread only. */
  void
  ReportOpenings() const
  {
    ReachStage(ProgressAfter::componentsBefore + (ProgressAfter::openings - ProgressAfter::componentsBefore) *
                                                   std::min(1.0,
                                                            static_cast<double>(m_OpenedBoxVoxels.load()) /
                                                              std::max(1.0, static_cast<double>(m_BoxVoxelsToOpen))));
  }

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

  /** How far a step along each axis moves a grid offset. */
  std::array<long, 3>
  GridStrides() const
  {
    return { { 1, static_cast<long>(m_Size[0]), static_cast<long>(m_Size[0] * m_Size[1]) } };
  }

  std::size_t
  GridOffset(long i, long j, long k) const
  {
    return static_cast<std::size_t>(i) +
           m_Size[0] * (static_cast<std::size_t>(j) + m_Size[1] * static_cast<std::size_t>(k));
  }

  bool
  IsInGrid(long i, long j, long k) const
  {
    return i >= 0 && j >= 0 && k >= 0 && i < static_cast<long>(m_Size[0]) && j < static_cast<long>(m_Size[1]) &&
           k < static_cast<long>(m_Size[2]);
  }

  /** The voxels of `label` in `box` (grid coordinates, reaching outside the grid, where everything is background). */
  BoxBits
  VoxelsOf(Label label, const VoxelBox & box) const
  {
    BoxBits voxels(box);
    // Only the part of each row inside the grid can differ from the background.
    const long firstInGrid = std::max(0L, -box.lower[0]);
    const long lastInGrid = std::min(box.size[0], static_cast<long>(m_Size[0]) - box.lower[0]) - 1;
    for (long z = 0; z < box.size[2]; ++z)
    {
      for (long y = 0; y < box.size[1]; ++y)
      {
        const long j = box.lower[1] + y;
        const long k = box.lower[2] + z;
        uint64_t * words = voxels.Row(y, z);
        if (!IsInGrid(0, j, k) || firstInGrid > lastInGrid)
        {
          if (label == BackgroundLabel)
          {
            voxels.SetRange(y, z, 0, box.size[0]);
          }
          continue;
        }
        if (label == BackgroundLabel)
        {
          voxels.SetRange(y, z, 0, firstInGrid);
          voxels.SetRange(y, z, lastInGrid + 1, box.size[0]);
        }
        // A word at a time, filled in a register and stored once, rather than a read and a write of it per voxel;
        // a word's span of one label (most of them) is decided at once.
        const TVoxelLabel * row = m_Labels + GridOffset(box.lower[0] + firstInGrid, j, k);
        for (long x = firstInGrid; x <= lastInGrid;)
        {
          const long          endOfWord = std::min(lastInGrid + 1, (x | 63) + 1);
          const TVoxelLabel * span = row + (x - firstInGrid);
          if (AllEqual(span, static_cast<std::size_t>(endOfWord - x)))
          {
            if (span[0] == label)
            {
              voxels.SetRange(y, z, x, endOfWord);
            }
            x = endOfWord;
            continue;
          }
          uint64_t bits = 0;
          for (; x < endOfWord; ++x)
          {
            bits |= static_cast<uint64_t>(row[x - firstInGrid] == label) << (x & 63);
          }
          words[(x - 1) >> 6] |= bits;
        }
      }
    }
    return voxels;
  }

  /** The voxels of the box outside `voxels` with a face neighbour in it. */
  static BoxBits
  OuterBoundary(const BoxBits & voxels)
  {
    const VoxelBox & box = voxels.Box();
    BoxBits          boundary = voxels;
    for (long z = 0; z < box.size[2]; ++z)
    {
      for (long y = 0; y < box.size[1]; ++y)
      {
        boundary.GrowRowAlongX(y, z);
        uint64_t * target = boundary.Row(y, z);
        for (const auto & [dy, dz] : { std::pair<long, long>{ -1, 0 }, { 1, 0 }, { 0, -1 }, { 0, 1 } })
        {
          if (y + dy >= 0 && y + dy < box.size[1] && z + dz >= 0 && z + dz < box.size[2])
          {
            const uint64_t * source = voxels.Row(y + dy, z + dz);
            for (std::size_t word = 0; word < voxels.WordsPerRow(); ++word)
            {
              target[word] |= source[word];
            }
          }
        }
      }
    }
    boundary.Keep(voxels, true);
    return boundary;
  }

  /** The box a label is opened in: its bounding box with a voxel of margin; the grid with `backgroundMargin` for
   * the background. A tissue's erosion and dilation change its own voxels only, from sources next to them (its
   * outer boundary, its survivors next to a removed voxel): one voxel of margin holds them all. */
  VoxelBox
  OpeningBox(Label label, const LabelComponents::Statistics & statistics,
             const std::array<long, 3> & backgroundMargin) const
  {
    VoxelBox box;
    for (int axis = 0; axis < 3; ++axis)
    {
      const long margin = label == BackgroundLabel ? backgroundMargin[axis] : 1;
      const long lowest = label == BackgroundLabel ? 0 : statistics.lowest[axis];
      const long highest = label == BackgroundLabel ? static_cast<long>(m_Size[axis]) - 1 : statistics.highest[axis];
      box.lower[axis] = lowest - margin;
      box.size[axis] = highest - lowest + 1 + 2 * margin;
    }
    return box;
  }

  /** Opens one label in `box`: its voxels that the opening removes, in the box's coordinates (the box reaches
   * outside the grid); none when the erosion removes nothing. */
  std::optional<BoxBits>
  OpenLabel(Label label, const VoxelBox & box, const std::vector<BallRow> & erosionBall,
            const std::vector<BallRow> & dilationBall, OpeningProgress & progress) const
  {
    // Each set is made in place from the one before where it can: every copy of a box's bits is fresh memory, and
    // fresh memory costs a page fault per page (DelaunayRefinementLargeBuffers.h).
    BoxBits voxels = VoxelsOf(label, box);
    OpeningCheckpoint(progress, 0.1);
    BoxBits eroded = DilateByBall(OuterBoundary(voxels), erosionBall);
    OpeningCheckpoint(progress, 0.4);
    eroded.Keep(voxels, false);
    if (!eroded.Any())
    {
      return std::nullopt;
    }
    // The nearest survivor of the erosion has a face neighbour that is not one (as above): the dilation of its
    // survivors next to another voxel is the dilation of all of them, outside them.
    BoxBits & notKept = voxels;
    notKept.Keep(eroded, true);
    notKept.Invert();
    const BoxBits survivorsAtTheEdge = OuterBoundary(notKept);
    const BoxBits givenBack = DilateByBall(survivorsAtTheEdge, dilationBall);
    OpeningCheckpoint(progress, 0.7);
    BoxBits onlyByTheLastHalfVoxel = eroded;
    onlyByTheLastHalfVoxel.Keep(givenBack, false);
    BoxBits & lost = eroded;
    lost.Keep(givenBack, true);
    if (!lost.Any())
    {
      return std::move(lost);
    }
    // The dilation reaches half a voxel farther than the erosion to keep convex parts' voxel corners. Beside a part
    // the opening removes (a sheet thinner than 2r on a block), that half voxel would give back a strip one voxel
    // wide along its root, a fin thinner than δ that the refinement then samples: a voxel only that half voxel gives
    // back stays only when no face neighbour of its label is lost (none is when nothing is lost, above).
    onlyByTheLastHalfVoxel.Keep(DilateByBall(survivorsAtTheEdge, erosionBall), true);
    BoxBits fin = OuterBoundary(lost);
    fin.Keep(onlyByTheLastHalfVoxel, false);
    lost.Add(fin);
    return std::move(lost);
  }

  /** Opens every label with the ball and returns the voxels whose label changes (grid offset, new label). The
   * nearest voxel of another label is always face-adjacent to a voxel of the first label (a step from it towards
   * the first voxel comes closer), so a label's erosion removes its voxels within the reach of its outer boundary.
   * Each label is opened in its bounding box with a margin of the dilation's reach; the background's box is the
   * grid with that margin, since the grid's outside is background. */
  VoxelChanges
  OpenEveryLabel(const std::map<Label, LabelComponents::Statistics> & labels) const
  {
    std::array<long, 3> backgroundMargin{};
    std::array<long, 3> longestOffset{};
    for (int axis = 0; axis < 3; ++axis)
    {
      // The background outside the grid matters only as survivors that give voxels of the grid back; one grid
      // length out, every voxel is farther than the reach from every tissue (the reach is shorter than the grid
      // along every axis, see Run()), so it survives, and it is nearer to the grid than anything beyond it.
      backgroundMargin[axis] = std::min(static_cast<long>(std::ceil(m_DilationReach / m_Spacing[axis])) + 1,
                                        static_cast<long>(m_Size[axis]) + 1);
      longestOffset[axis] = static_cast<long>(m_Size[axis]) + 2 * backgroundMargin[axis] - 1;
    }
    const std::vector<BallRow> erosionBall = BallRows(m_Reach, m_Spacing, longestOffset);
    const std::vector<BallRow> dilationBall = BallRows(m_DilationReach, m_Spacing, longestOffset);
    // A label's opening flags its own voxels only (a voxel has one label, and the flags are bytes): the labels
    // are opened on the threads, the largest box first, each into its own list.
    std::vector<std::pair<Label, VoxelBox>> toOpen;
    for (const auto & [label, statistics] : labels)
    {
      toOpen.emplace_back(label, OpeningBox(label, statistics, backgroundMargin));
    }
    std::stable_sort(toOpen.begin(), toOpen.end(), [](const auto & a, const auto & b) {
      return a.second.NumberOfVoxels() > b.second.NumberOfVoxels();
    });
    // The labels' removed voxels come back as bits in their boxes, a bit a voxel, rather than as lists of grid
    // offsets, eight bytes a voxel: the lists were as long as the removed voxels (2.3 million on the k-means tissues
    // resampled to 1 mm at δ = 6 mm), and copied into one sorted list after, all of it fresh memory.
    std::vector<std::optional<BoxBits>> lostOfLabel(toOpen.size());
    m_BoxVoxelsToOpen = 0;
    for (const auto & [label, box] : toOpen)
    {
      m_BoxVoxelsToOpen += box.NumberOfVoxels();
    }
    m_OpenedBoxVoxels = 0;
    detail::ForEachIndexInParallel(
      toOpen.size(),
      m_NumberOfThreads,
      [&](std::size_t index) {
        OpeningProgress progress{ toOpen[index].second.NumberOfVoxels(), 0 };
        lostOfLabel[index] = OpenLabel(toOpen[index].first, toOpen[index].second, erosionBall, dilationBall, progress);
        OpeningCheckpoint(progress, 1.0);
      },
      [this] { ReportOpenings(); });
    ReachStage(ProgressAfter::openings);
    // Flagged here, not by the labels' openings on the threads, since neighbouring voxels share a word. A voxel has
    // one label, so no voxel is counted twice.
    VoxelFlags  removed(m_NumberOfVoxels);
    std::size_t numberRemoved = 0;
    for (std::optional<BoxBits> & lost : lostOfLabel)
    {
      if (!lost)
      {
        continue;
      }
      const VoxelBox & box = lost->Box();
      lost->ForEachSet([&](long x, long y, long z) {
        const long i = box.lower[0] + x;
        const long j = box.lower[1] + y;
        const long k = box.lower[2] + z;
        if (IsInGrid(i, j, k))
        {
          removed.Set(GridOffset(i, j, k));
          ++numberRemoved;
        }
      });
      lost.reset();
    }
    if (numberRemoved == 0)
    {
      return {};
    }
    VoxelOffsets removedVoxels;
    removedVoxels.reserve(numberRemoved);
    removed.ForEachSet([&removedVoxels](std::size_t voxel) { removedVoxels.push_back(voxel); });
    return GiveRemovedVoxelsTheNearestSurvivorsLabel(removed, std::move(removedVoxels));
  }

  /** Every voxel of the grid that its opening removed takes the label of the nearest voxel of the grid that
   * survived its own label's opening; it keeps its label when nothing survived. Returns the voxels whose label
   * changes. The removed voxels search the voxels around them, nearest first (a survivor is usually a few voxels
   * away); those with no survivor near, and all those left when the searches grow costly, take a distance transform
   * over a box around them. Either way the survivor is a nearest one; between survivors at exactly the same distance
   * the choice is deterministic. */
  VoxelChanges
  GiveRemovedVoxelsTheNearestSurvivorsLabel(const VoxelFlags & removed, VoxelOffsets removedVoxels) const
  {
    const double searchRadius = m_DilationReach + 2.0 * std::max({ m_Spacing[0], m_Spacing[1], m_Spacing[2] });
    const std::vector<NeighbourOffset> nearestFirst = NeighbourOffsetsByDistance(
      searchRadius,
      m_Spacing,
      GridStrides(),
      { { static_cast<long>(m_Size[0]) - 1, static_cast<long>(m_Size[1]) - 1, static_cast<long>(m_Size[2]) - 1 } });
    // At most one change per removed voxel: reserved at once, since growing the list copied it into fresh memory at
    // every doubling (a third of the transform's share of the k-means tissues at δ = 18 mm); pages never written are
    // never touched.
    VoxelChanges changes;
    changes.reserve(removedVoxels.size());
    const auto takeLabelOf = [&](std::size_t voxel, std::size_t survivor) {
      if (m_Labels[survivor] != m_Labels[voxel])
      {
        changes.emplace_back(voxel, m_Labels[survivor]);
      }
    };
    // The voxels with no survivor near are gathered in place at the front of the list, as they are passed (the list
    // stays sorted, and no second list is made): [0, numberFar) of removedVoxels.
    std::size_t numberFar = 0;
    // The search costs the offsets it tries. Once they outnumber SearchTriesPerBoxVoxel per voxel of the removed
    // voxels' box, the voxels not searched yet take the transform: searching stays cheap where survivors are near
    // (the usual case: the atlas phantom at 4 mm, 14,222 voxels in 0.5 ms against 33 ms for the transform), and
    // costs a fraction of the transform where they are not (a thick layer removed whole).
    const std::size_t budget = SearchTriesPerBoxVoxel * BoxAround(removedVoxels, searchRadius).NumberOfVoxels();
    std::size_t       tries = 0;
    // The distance from the previous voxel to its nearest survivor (more than the search radius when none was
    // found): a survivor nearer than that less h to this voxel, its neighbour along x, would be nearer to it.
    std::size_t previousVoxel = NoVoxel;
    double      previousDistance = 0.0;
    for (std::size_t index = 0; index < removedVoxels.size(); ++index)
    {
      if ((index & 0xffff) == 0xffff)
      {
        ReachStage(ProgressAfter::openings + (ProgressAfter::nearestSurvivors - ProgressAfter::openings) * 0.5 *
                                               static_cast<double>(index) / static_cast<double>(removedVoxels.size()));
      }
      // Every 4,096 voxels, the tries so far are extrapolated to all the voxels: the transform's box is about the
      // same whichever voxels are left to it, so searching on when the budget will run out anyway is wasted.
      const bool budgetWillRunOut = (index & 0xfff) == 0 && index > 0 && tries * removedVoxels.size() > budget * index;
      if (tries > budget || budgetWillRunOut)
      {
        if (numberFar < index)
        {
          std::copy(removedVoxels.begin() + static_cast<std::ptrdiff_t>(index),
                    removedVoxels.end(),
                    removedVoxels.begin() + static_cast<std::ptrdiff_t>(numberFar));
        }
        numberFar += removedVoxels.size() - index;
        break;
      }
      const std::size_t         voxel = removedVoxels[index];
      const std::array<long, 3> at = CoordinatesOf(voxel);
      auto                      first = nearestFirst.begin();
      if (voxel == previousVoxel + 1 && at[0] > 0 && previousDistance > m_Spacing[0])
      {
        // Slightly below the bound, so that rounding never skips an offset as long as the nearest.
        const double skippedBelow =
          (1.0 - 1e-9) * (previousDistance - m_Spacing[0]) * (previousDistance - m_Spacing[0]);
        first = std::partition_point(first, nearestFirst.end(), [skippedBelow](const NeighbourOffset & offset) {
          return offset.squaredLength < skippedBelow;
        });
      }
      const auto nearest = std::find_if(first, nearestFirst.end(), [&](const NeighbourOffset & candidate) {
        ++tries;
        const long i = at[0] + candidate.delta[0];
        const long j = at[1] + candidate.delta[1];
        const long k = at[2] + candidate.delta[2];
        return IsInGrid(i, j, k) && !removed[GridOffset(i, j, k)];
      });
      previousVoxel = voxel;
      if (nearest == nearestFirst.end())
      {
        previousDistance = searchRadius;
        removedVoxels[numberFar++] = voxel;
        continue;
      }
      previousDistance = std::sqrt(nearest->squaredLength);
      takeLabelOf(voxel, GridOffset(at[0] + nearest->delta[0], at[1] + nearest->delta[1], at[2] + nearest->delta[2]));
    }
    if (numberFar == 0)
    {
      return changes;
    }
    removedVoxels.resize(numberFar);
    const VoxelOffsets & farFromSurvivors = removedVoxels;
    if (!NearestSurvivorsInBox(BoxAround(farFromSurvivors, searchRadius), farFromSurvivors, removed, takeLabelOf))
    {
      VoxelBox whole;
      for (int axis = 0; axis < 3; ++axis)
      {
        whole.size[axis] = static_cast<long>(m_Size[axis]);
      }
      NearestSurvivorsInBox(whole, farFromSurvivors, removed, takeLabelOf);
    }
    return changes;
  }

  std::array<long, 3>
  CoordinatesOf(std::size_t offset) const
  {
    return { { static_cast<long>(offset % m_Size[0]),
               static_cast<long>((offset / m_Size[0]) % m_Size[1]),
               static_cast<long>(offset / (m_Size[0] * m_Size[1])) } };
  }

  /** The bounding box of `voxels` with a margin of `margin` (physical), within the grid. */
  VoxelBox
  BoxAround(const VoxelOffsets & voxels, double margin) const
  {
    std::array<long, 3> lowest = CoordinatesOf(voxels.front());
    std::array<long, 3> highest = lowest;
    for (const std::size_t voxel : voxels)
    {
      const std::array<long, 3> at = CoordinatesOf(voxel);
      for (int axis = 0; axis < 3; ++axis)
      {
        lowest[axis] = std::min(lowest[axis], at[axis]);
        highest[axis] = std::max(highest[axis], at[axis]);
      }
    }
    VoxelBox box;
    for (int axis = 0; axis < 3; ++axis)
    {
      const long voxelsOfMargin = static_cast<long>(std::ceil(margin / m_Spacing[axis])) + 1;
      box.lower[axis] = std::max(0L, lowest[axis] - voxelsOfMargin);
      box.size[axis] =
        std::min(static_cast<long>(m_Size[axis]) - 1, highest[axis] + voxelsOfMargin) - box.lower[axis] + 1;
    }
    return box;
  }

  /** The nearest survivor in `box` of each voxel (removed voxels in the box, in increasing order): found(voxel,
   * survivor) with their grid offsets, in the voxels' order, for each voxel with a survivor in the box; false,
   * with `found` never called, when a survivor outside the box might be nearer to one of them than the one found. */
  template <typename TFound>
  bool
  NearestSurvivorsInBox(const VoxelBox & box, const VoxelOffsets & voxels, const VoxelFlags & removed,
                        TFound && found) const
  {
    const bool small = m_NumberOfVoxels < std::numeric_limits<uint32_t>::max();
    if (NearestSiteTransform<int16_t>::Fits(box))
    {
      return small ? NearestSurvivorsInBoxWith<uint32_t, int16_t>(box, voxels, removed, found)
                   : NearestSurvivorsInBoxWith<std::size_t, int16_t>(box, voxels, removed, found);
    }
    return small ? NearestSurvivorsInBoxWith<uint32_t, int32_t>(box, voxels, removed, found)
                 : NearestSurvivorsInBoxWith<std::size_t, int32_t>(box, voxels, removed, found);
  }

  /** NearestSurvivorsInBox() with places in the box and grid offsets as `TPlace` (32 bits where the grid allows)
   * and the transform's steps as `TStep`. */
  template <typename TPlace, typename TStep, typename TFound>
  bool
  NearestSurvivorsInBoxWith(const VoxelBox & box, const VoxelOffsets & voxels, const VoxelFlags & removed,
                            TFound && found) const
  {
    Checkpoint();
    NearestSiteTransform<TStep> survivors(box, m_Spacing);
    // The box in grid order: its survivors are the sites, and the voxels, which come in the same order, are found
    // in it with their place in the box and how far the box's sides that are not the grid's are from them (no
    // divisions). Slabs of slices are read on the threads: the voxels of a slab are a
    // contiguous part of `voxels`, and each slab marks the lines it asks for in a list of its own.
    const std::size_t sliceVoxels = static_cast<std::size_t>(box.size[0] * box.size[1]);
    const std::size_t slabs = std::max<std::size_t>(
      1,
      std::min(
        { m_NumberOfThreads, static_cast<std::size_t>(box.size[2]), box.NumberOfVoxels() / MinimumVoxelsPerThread }));
    const std::size_t slicesPerSlab = (static_cast<std::size_t>(box.size[2]) + slabs - 1) / slabs;
    const auto        firstVoxelOfSlice = [&](std::size_t slice) {
      const std::size_t offset = GridOffset(box.lower[0], box.lower[1], box.lower[2] + static_cast<long>(slice));
      return static_cast<std::size_t>(std::lower_bound(voxels.begin(), voxels.end(), offset) - voxels.begin());
    };
    // Per voxel asked for: its place in the box, and a lower bound, in single precision (half the memory), of how
    // far it is from the box's sides that are not the grid's. A bound a little low only sends a voxel to the whole
    // grid's transform more often, which gives the same survivor.
    LargeVector<TPlace>               placeInBox(voxels.size());
    LargeVector<float>                toCutSides(voxels.size());
    std::vector<std::vector<uint8_t>> linesOfSlab(slabs);
    std::vector<uint8_t>              slabIsComplete(slabs, 0);
    detail::ForEachIndexInParallel(
      slabs,
      slabs,
      [&](std::size_t slab) {
        const std::size_t      firstSlice = std::min(slab * slicesPerSlab, static_cast<std::size_t>(box.size[2]));
        const std::size_t      endSlice = std::min(firstSlice + slicesPerSlab, static_cast<std::size_t>(box.size[2]));
        std::size_t            query = firstVoxelOfSlice(firstSlice);
        const std::size_t      endQuery = firstVoxelOfSlice(endSlice);
        std::vector<uint8_t> & lines = linesOfSlab[slab];
        lines.assign(sliceVoxels, 0);
        std::size_t index = firstSlice * sliceVoxels;
        for (long k = static_cast<long>(firstSlice); k < static_cast<long>(endSlice); ++k)
        {
          for (long j = 0; j < box.size[1]; ++j)
          {
            const std::size_t rowStart = GridOffset(box.lower[0], box.lower[1] + j, box.lower[2] + k);
            for (long i = 0; i < box.size[0]; ++i, ++index)
            {
              const std::size_t offset = rowStart + static_cast<std::size_t>(i);
              if (!removed[offset])
              {
                survivors.SetSite(index);
                continue;
              }
              survivors.SetNotSite(index);
              if (query < endQuery && voxels[query] == offset)
              {
                lines[static_cast<std::size_t>(i + box.size[0] * j)] = 1;
                placeInBox[query] = static_cast<TPlace>(index);
                toCutSides[query++] = FloatNotAbove(DistanceToTheCutSides(box, { { i, j, k } }));
              }
            }
          }
        }
        slabIsComplete[slab] = query == endQuery ? 1 : 0;
      },
      [] {});
    if (firstVoxelOfSlice(0) != 0 || firstVoxelOfSlice(static_cast<std::size_t>(box.size[2])) != voxels.size() ||
        std::find(slabIsComplete.begin(), slabIsComplete.end(), 0) != slabIsComplete.end())
    {
      throw std::logic_error("NearestSurvivorsInBox: the voxels are not removed voxels of the box in increasing order");
    }
    for (const std::vector<uint8_t> & lines : linesOfSlab)
    {
      for (std::size_t line = 0; line < sliceVoxels; ++line)
      {
        if (lines[line])
        {
          survivors.AddQueryLine(line);
        }
      }
    }
    // The transform's three passes: the second half of the nearest survivors' share.
    survivors.Compute(
      [this, pass = 0]() mutable {
        ReachStage(ProgressAfter::openings + (ProgressAfter::nearestSurvivors - ProgressAfter::openings) *
                                               (0.5 + static_cast<double>(pass++) / 6.0));
      },
      m_NumberOfThreads);
    // Whether every survivor found is nearer than the box's cut sides, on the threads; then the survivors, in order.
    std::atomic<bool> allInBox{ true };
    detail::ForEachRangeInParallel(
      voxels.size(), slabs, MinimumVoxelsPerThread, [&](std::size_t begin, std::size_t end) {
        for (std::size_t query = begin; query < end && allInBox; ++query)
        {
          const double toOutside = toCutSides[query];
          if (toOutside != Infinity && !(survivors.SquaredDistance(placeInBox[query]) <= toOutside * toOutside))
          {
            allInBox = false;
          }
        }
      });
    if (!allInBox)
    {
      return false;
    }
    const std::array<long, 3> gridStrides = GridStrides();
    for (std::size_t query = 0; query < voxels.size(); ++query)
    {
      if (survivors.HasSite(placeInBox[query]))
      {
        const std::array<long, 3> step = survivors.StepToSite(placeInBox[query]);
        const long toSite = step[0] * gridStrides[0] + step[1] * gridStrides[1] + step[2] * gridStrides[2];
        found(voxels[query], static_cast<std::size_t>(static_cast<long>(voxels[query]) + toSite));
      }
    }
    return true;
  }

  /** The largest float not above `value` (infinity stays infinity). */
  static float
  FloatNotAbove(double value)
  {
    const float rounded = static_cast<float>(value);
    return static_cast<double>(rounded) > value ? std::nextafter(rounded, 0.0F) : rounded;
  }

  /** How far the voxel at `inBox` is from the sides of the box that are not the grid's (beyond them, a survivor
   * might be nearer than any in the box); infinite when the box is the grid. */
  double
  DistanceToTheCutSides(const VoxelBox & box, const std::array<long, 3> & inBox) const
  {
    double distance = Infinity;
    for (int axis = 0; axis < 3; ++axis)
    {
      if (box.lower[axis] > 0)
      {
        distance = std::min(distance, static_cast<double>(inBox[axis] + 1) * m_Spacing[axis]);
      }
      if (box.lower[axis] + box.size[axis] < static_cast<long>(m_Size[axis]))
      {
        distance = std::min(distance, static_cast<double>(box.size[axis] - inBox[axis]) * m_Spacing[axis]);
      }
    }
    return distance;
  }

  /** How many offsets the searches for the nearest survivor may try per voxel of the removed voxels' box before
   * the transform takes over. A try costs about a twentieth of a voxel's three transform passes (measured: 4 ns
   * against 75 ns), so searches that end in the transform cost it a fifth more at most. */
  static constexpr std::size_t SearchTriesPerBoxVoxel = 4;

  TVoxelLabel *                       m_Labels;
  const std::function<bool(double)> & m_KeepGoing;
  /** The thread that called Run(), the only one that reports progress. */
  std::thread::id m_CallingThread;
  /** The fraction of the work reported so far (ProgressAfter). */
  mutable double m_Reported{ 0.0 };
  /** The voxels of the boxes the openings work on, and of those opened so far (on any thread, in part). */
  mutable std::size_t              m_BoxVoxelsToOpen{ 0 };
  mutable std::atomic<std::size_t> m_OpenedBoxVoxels{ 0 };
  /** Whether the calling thread has seen the observer ask for an abort: the other threads stop too. */
  mutable std::atomic<bool>  m_AbortSeen{ false };
  std::size_t                m_NumberOfThreads;
  std::array<std::size_t, 3> m_Size;
  Vector3                    m_Spacing;
  double                     m_Radius;
  double                     m_Reach;
  double                     m_DilationReach;
  std::size_t                m_NumberOfVoxels;
};
} // namespace

/** FindUnmarkedParts: the parts are the components of LabelComponents; each unmarked one's largest ball is measured
 * by scans of the cubes around its voxels, nearest first, up to the limit: every voxel's for a small part, only the
 * deepest voxels' for a large one. */
class LabelParts::Finder
{
public:
  template <typename TVoxelLabel>
  Finder(const TVoxelLabel * labels, const std::array<std::size_t, 3> & size, const Vector3 & spacing,
         unsigned int numberOfThreads)
    : m_Components(labels, size, numberOfThreads)
    , m_Size(size)
    , m_Spacing(spacing)
    , m_NumberOfThreads(numberOfThreads)
  {}

  std::vector<LabelPart>
  Find(const std::vector<std::size_t> & marked, double radiusLimit, std::size_t maximumVoxels)
  {
    std::vector<bool> isMarked(m_Components.NumberOfRuns(), false);
    for (const std::size_t voxel : marked)
    {
      isMarked[ComponentAt(voxel)] = true;
    }
    // The unmarked parts in the order of their first voxel, with their runs.
    std::map<std::size_t, std::size_t>                            partOfComponent;
    std::vector<LabelPart>                                        parts;
    std::vector<std::vector<std::pair<std::size_t, std::size_t>>> runsOfPart;
    m_Components.ForEachRun([&](std::size_t component, Label label, std::size_t first, std::size_t length) {
      if (label == BackgroundLabel || isMarked[component])
      {
        return;
      }
      const auto [entry, isNew] = partOfComponent.emplace(component, parts.size());
      if (isNew)
      {
        parts.push_back({ label, 0, first, 0.0 });
        runsOfPart.emplace_back();
      }
      parts[entry->second].voxels += length;
      runsOfPart[entry->second].emplace_back(first, length);
    });
    std::vector<LabelPart> measured;
    for (std::size_t part = 0; part < parts.size(); ++part)
    {
      if (parts[part].voxels <= maximumVoxels)
      {
        if (parts[part].voxels < VoxelsForDeepestFirst)
        {
          MeasureVoxelByVoxel(parts[part], runsOfPart[part], radiusLimit);
        }
        else
        {
          MeasureDeepestFirst(parts[part], runsOfPart[part], radiusLimit);
        }
        measured.push_back(parts[part]);
      }
    }
    return measured;
  }

private:
  using Runs = std::vector<std::pair<std::size_t, std::size_t>>;

  /** From this many voxels on, a part's largest ball is searched deepest voxels first (MeasureDeepestFirst): below
   * it, no voxel is far from the part's boundary, and a scan of every voxel costs less than a distance transform of
   * the part's box. A scan of every voxel costs the cubes within each voxel's clearance: on a part of 95 k voxels of
   * 2 x 3 x 2 mm at δ = 80 mm (the brain mask, its clearance up to about 30 mm) it took 7 s. */
  static constexpr std::size_t VoxelsForDeepestFirst = 256;

  /** A voxel's neighbour, with the distance from the voxel's centre to the neighbour's cube. */
  struct CubeOffset
  {
    std::array<long, 3> step;
    double              distance;
  };

  /** The distance from a voxel's centre to the cube of the voxel `step` away. */
  double
  CubeDistance(const std::array<long, 3> & step) const
  {
    double squared = 0.0;
    for (int axis = 0; axis < 3; ++axis)
    {
      const double gap = std::max(0.0, std::abs(static_cast<double>(step[axis])) - 0.5) * m_Spacing[axis];
      squared += gap * gap;
    }
    return std::sqrt(squared);
  }

  /** m_Offsets becomes the voxels whose cubes come closer than `radius` to a voxel's centre, nearest first (ties in
   * a fixed order); the voxels nearer than the radius it had come first, as the same set. */
  void
  GrowOffsets(double radius)
  {
    std::array<long, 3> reach{};
    for (int axis = 0; axis < 3; ++axis)
    {
      reach[axis] = static_cast<long>(std::ceil(radius / m_Spacing[axis] + 0.5));
    }
    m_Offsets.clear();
    for (long z = -reach[2]; z <= reach[2]; ++z)
    {
      for (long y = -reach[1]; y <= reach[1]; ++y)
      {
        for (long x = -reach[0]; x <= reach[0]; ++x)
        {
          const std::array<long, 3> step{ { x, y, z } };
          const double              distance = CubeDistance(step);
          if (distance < radius && (x != 0 || y != 0 || z != 0))
          {
            m_Offsets.push_back({ step, distance });
          }
        }
      }
    }
    std::stable_sort(m_Offsets.begin(), m_Offsets.end(), [](const CubeOffset & a, const CubeOffset & b) {
      return a.distance < b.distance;
    });
    m_OffsetsRadius = radius;
  }

  /** The clearance of the voxel at `index` in the part `component`: the distance from its centre to the nearest
   * cube outside the part (another label, another part, beyond the grid), `limit` when none is nearer. The cubes
   * are tried nearest first; the list of them grows as a scan needs it, so that a large limit costs only what the
   * clearances reach (the scans' answers do not depend on the order of cubes at the same distance). */
  double
  Clearance(const std::array<long, 3> & index, std::size_t component, double limit)
  {
    std::size_t next = 0;
    while (true)
    {
      for (; next < m_Offsets.size() && m_Offsets[next].distance < limit; ++next)
      {
        const std::array<long, 3> & step = m_Offsets[next].step;
        const std::array<long, 3>   other{ { index[0] + step[0], index[1] + step[1], index[2] + step[2] } };
        if (!IsInside(other) || ComponentAt(OffsetOf(other)) != component)
        {
          return m_Offsets[next].distance;
        }
      }
      if (next < m_Offsets.size() || m_OffsetsRadius >= limit)
      {
        return limit;
      }
      const double scanned = m_OffsetsRadius;
      const double maximumSpacing = std::max({ m_Spacing[0], m_Spacing[1], m_Spacing[2] });
      GrowOffsets(std::min(limit, std::max(2.0 * scanned, 4.0 * maximumSpacing)));
      next = static_cast<std::size_t>(
        std::lower_bound(m_Offsets.begin(),
                         m_Offsets.end(),
                         scanned,
                         [](const CubeOffset & offset, double radius) { return offset.distance < radius; }) -
        m_Offsets.begin());
    }
  }

  /** The part's largest ball centred on one of its voxel centres that no cube outside it reaches, up to `limit`, and
   * its centre: the first such voxel in the order of the runs (the grid's), its clearance (Clearance). A voxel whose
   * cube face touches another part has a ball of radius 0. Every voxel is scanned, in order, up to the first that
   * reaches the limit. */
  void
  MeasureVoxelByVoxel(LabelPart & part, const Runs & runs, double limit)
  {
    const std::size_t component = ComponentAt(part.deepestVoxel);
    part.radius = -1.0;
    for (const auto & [first, length] : runs)
    {
      for (std::size_t voxel = first; voxel < first + length; ++voxel)
      {
        const double clearance = Clearance(IndexOf(voxel), component, limit);
        if (clearance > part.radius)
        {
          part.radius = clearance;
          part.deepestVoxel = voxel;
          if (clearance >= limit)
          {
            return;
          }
        }
      }
    }
  }

  /** The same ball as MeasureVoxelByVoxel, scanning only the voxels that may hold it. A distance transform of the
   * part's box (one voxel of margin, every voxel outside the part a site) gives each voxel a cube outside the part,
   * its nearest site's: the distance to that cube bounds the voxel's clearance from above, and the distance to the
   * site's centre less half the cube's diagonal from below. Only the voxels whose upper bound reaches the largest
   * lower bound are candidates; they are scanned by decreasing upper bound, then in the runs' order, until the
   * bound falls below the best clearance found. The best, and the first voxel in the runs' order that has it, are
   * then what the scan of every voxel finds. */
  void
  MeasureDeepestFirst(LabelPart & part, const Runs & runs, double limit)
  {
    VoxelBox            box;
    std::array<long, 3> highest{};
    for (int axis = 0; axis < 3; ++axis)
    {
      box.lower[axis] = std::numeric_limits<long>::max();
      highest[axis] = std::numeric_limits<long>::min();
    }
    for (const auto & [first, length] : runs)
    {
      const std::array<long, 3> start = IndexOf(first);
      for (int axis = 0; axis < 3; ++axis)
      {
        box.lower[axis] = std::min(box.lower[axis], start[axis] - 1);
        highest[axis] = std::max(highest[axis], start[axis] + (axis == 0 ? static_cast<long>(length) : 1));
      }
    }
    for (int axis = 0; axis < 3; ++axis)
    {
      box.size[axis] = highest[axis] - box.lower[axis] + 1;
    }
    if (!NearestSiteTransform<int16_t>::Fits(box))
    {
      MeasureVoxelByVoxel(part, runs, limit);
      return;
    }
    const auto inBox = [&box](const std::array<long, 3> & index) {
      return static_cast<std::size_t>(index[0] - box.lower[0]) +
             static_cast<std::size_t>(box.size[0]) *
               (static_cast<std::size_t>(index[1] - box.lower[1]) +
                static_cast<std::size_t>(box.size[1]) * static_cast<std::size_t>(index[2] - box.lower[2]));
    };
    NearestSiteTransform<int16_t> transform(box, m_Spacing);
    for (std::size_t index = 0; index < box.NumberOfVoxels(); ++index)
    {
      transform.SetSite(index);
    }
    // A voxel's line along z is its index in the box modulo a slice.
    const std::size_t voxelsPerSlice = static_cast<std::size_t>(box.size[0] * box.size[1]);
    ForEachVoxel(runs, [&](std::size_t, std::size_t voxel) {
      const std::size_t index = inBox(IndexOf(voxel));
      transform.SetNotSite(index);
      transform.AddQueryLine(index % voxelsPerSlice);
    });
    transform.Compute([] {}, m_NumberOfThreads);

    // A cube's farthest point from its centre, and a relative margin that keeps the bounds bounds under rounding.
    const double halfDiagonal =
      0.5 * std::sqrt(m_Spacing[0] * m_Spacing[0] + m_Spacing[1] * m_Spacing[1] + m_Spacing[2] * m_Spacing[2]);
    constexpr double rounding = 1e-12;
    const auto       upperBound = [&](std::size_t voxel) {
      const std::size_t index = inBox(IndexOf(voxel));
      return std::min(limit, CubeDistance(transform.StepToSite(index)) * (1.0 + rounding));
    };
    double largestLowerBound = -1.0;
    ForEachVoxel(runs, [&](std::size_t, std::size_t voxel) {
      const double centre = std::sqrt(transform.SquaredDistance(inBox(IndexOf(voxel))));
      largestLowerBound = std::max(largestLowerBound, std::min(limit, (centre - halfDiagonal) * (1.0 - rounding)));
    });
    struct Candidate
    {
      double      upperBound;
      std::size_t order;
      std::size_t voxel;
    };
    std::vector<Candidate> candidates;
    ForEachVoxel(runs, [&](std::size_t order, std::size_t voxel) {
      const double bound = upperBound(voxel);
      if (bound >= largestLowerBound)
      {
        candidates.push_back({ bound, order, voxel });
      }
    });
    std::sort(candidates.begin(), candidates.end(), [](const Candidate & a, const Candidate & b) {
      return a.upperBound != b.upperBound ? a.upperBound > b.upperBound : a.order < b.order;
    });
    const std::size_t component = ComponentAt(part.deepestVoxel);
    part.radius = -1.0;
    std::size_t bestOrder = std::numeric_limits<std::size_t>::max();
    for (const Candidate & candidate : candidates)
    {
      if (candidate.upperBound < part.radius)
      {
        break;
      }
      const double clearance = Clearance(IndexOf(candidate.voxel), component, limit);
      if (clearance > part.radius || (clearance == part.radius && candidate.order < bestOrder))
      {
        part.radius = clearance;
        part.deepestVoxel = candidate.voxel;
        bestOrder = candidate.order;
      }
      // The candidates reaching the limit come first, in the runs' order: the first to reach it is the answer.
      if (part.radius >= limit)
      {
        return;
      }
    }
  }

  /** Calls visit(order, voxel) for the voxels of `runs`, in their order. */
  template <typename TVisit>
  static void
  ForEachVoxel(const Runs & runs, TVisit && visit)
  {
    std::size_t order = 0;
    for (const auto & [first, length] : runs)
    {
      for (std::size_t voxel = first; voxel < first + length; ++voxel)
      {
        visit(order++, voxel);
      }
    }
  }

  std::size_t
  ComponentAt(std::size_t voxel)
  {
    return m_Components.ComponentOf(voxel / m_Size[0], voxel % m_Size[0]);
  }

  std::array<long, 3>
  IndexOf(std::size_t voxel) const
  {
    return { { static_cast<long>(voxel % m_Size[0]),
               static_cast<long>(voxel / m_Size[0] % m_Size[1]),
               static_cast<long>(voxel / (m_Size[0] * m_Size[1])) } };
  }

  std::size_t
  OffsetOf(const std::array<long, 3> & index) const
  {
    return static_cast<std::size_t>(index[0]) +
           m_Size[0] * (static_cast<std::size_t>(index[1]) + m_Size[1] * static_cast<std::size_t>(index[2]));
  }

  bool
  IsInside(const std::array<long, 3> & index) const
  {
    for (int axis = 0; axis < 3; ++axis)
    {
      if (index[axis] < 0 || index[axis] >= static_cast<long>(m_Size[axis]))
      {
        return false;
      }
    }
    return true;
  }

  LabelComponents            m_Components;
  std::array<std::size_t, 3> m_Size;
  Vector3                    m_Spacing;
  unsigned int               m_NumberOfThreads;
  /** The cubes nearest first, within m_OffsetsRadius (Clearance grows them). */
  std::vector<CubeOffset> m_Offsets;
  double                  m_OffsetsRadius{ 0.0 };
};

template <typename TVoxelLabel>
LabelParts::LabelParts(const TVoxelLabel * labels, const std::array<std::size_t, 3> & size, const Vector3 & spacing,
                       unsigned int numberOfThreads)
  : m_Finder(size[0] * size[1] * size[2] == 0
               ? nullptr
               : std::make_unique<Finder>(labels, size, spacing, std::max(1U, numberOfThreads)))
{}

LabelParts::~LabelParts() = default;

std::vector<LabelPart>
LabelParts::FindUnmarked(const std::vector<std::size_t> & marked, double radiusLimit, std::size_t maximumVoxels)
{
  return m_Finder ? m_Finder->Find(marked, radiusLimit, maximumVoxels) : std::vector<LabelPart>();
}

template <typename TVoxelLabel>
std::vector<LabelPart>
FindUnmarkedParts(const TVoxelLabel * labels, const std::array<std::size_t, 3> & size, const Vector3 & spacing,
                  const std::vector<std::size_t> & marked, double radiusLimit, unsigned int numberOfThreads)
{
  return LabelParts(labels, size, spacing, numberOfThreads).FindUnmarked(marked, radiusLimit);
}

template <typename TVoxelLabel>
LabelRegularizationReport
RegularizeLabels(TVoxelLabel * labels, const std::array<std::size_t, 3> & size, const Vector3 & spacing, double radius,
                 const std::function<bool(double)> & keepGoing, unsigned int numberOfThreads)
{
  static_assert(IsVoxelLabelType<TVoxelLabel>, "labels are stored as Label, uint16_t or uint8_t");
  return LabelRegularizer<TVoxelLabel>(labels, size, spacing, radius, keepGoing, numberOfThreads).Run();
}

DelaunayRefinement_InstantiateLabelRegularization(, Label);
DelaunayRefinement_InstantiateLabelRegularization(, uint16_t);
DelaunayRefinement_InstantiateLabelRegularization(, uint8_t);

} // namespace delaunay_refinement
