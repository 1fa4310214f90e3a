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
#ifndef DelaunayRefinementVertexLinks_h
#define DelaunayRefinementVertexLinks_h

// The local manifold test (docs/algorithm.md, "Topology"): a label's boundary is a manifold at a vertex when the
// vertex's link in it (the edges opposite the vertex in its boundary facets) is empty or one cycle. It depends on
// the vertex's star only; the relabelling (TopologyRelabel) and the sliver perturbation (SliverPerturbation) ask it
// of the vertices whose star they change.

#include "DelaunayRefinementMeshState.h"

#include <algorithm>
#include <array>
#include <vector>

namespace delaunay_refinement
{
namespace detail
{

class VertexLinks
{
public:
  /** The union of the labels other than the background is keyed by the background's label. */
  static constexpr Label UnionKey = BackgroundLabel;

  /** How many labels' boundaries (the union's, keyed by the background, included) are not a manifold at the
   * vertex, whose incident cells are `star`: the facets of the star that separate the label from another make the
   * label's link, which must be empty or one cycle. */
  int
  NonManifoldLabelsAt(const Triangulation & triangulation, VertexHandle vertex,
                      const std::vector<CellHandle> & star) const
  {
    int nonManifold = 0;
    ForEachNonManifoldLabel(triangulation, vertex, star, EveryLabel, [&nonManifold](Label) { ++nonManifold; });
    return nonManifold;
  }

  /** How many of `labels` (in increasing order) have a boundary that is not a manifold at the vertex; the other
   * labels' links are not built. A change of labels in the star changes the links of the labels it moves cells
   * between only (and the union's, keyed by the background, only when one of them is the background). */
  int
  NonManifoldLabelsAmong(const Triangulation & triangulation, VertexHandle vertex, const std::vector<CellHandle> & star,
                         const std::vector<Label> & labels) const
  {
    int nonManifold = 0;
    ForEachNonManifoldLabel(
      triangulation,
      vertex,
      star,
      [&labels](Label label) { return std::binary_search(labels.begin(), labels.end(), label); },
      [&nonManifold](Label) { ++nonManifold; });
    return nonManifold;
  }

  /** The edge opposite the cell's corner `own` in its facet `facet` (facet != own): the facet's contribution to
   * that corner's link. */
  static std::array<VertexHandle, 2>
  LinkEdgeOf(CellHandle cell, int own, int facet)
  {
    std::array<VertexHandle, 2> edge{};
    int                         count = 0;
    for (int corner = 0; corner < 4; ++corner)
    {
      if (corner != facet && corner != own)
      {
        edge[count++] = cell->vertex(corner);
      }
    }
    return edge;
  }

  /** A triangle at a vertex, given by its edge opposite the vertex and the labels of its two tetrahedra: how a star
   * not in the triangulation yet (an insertion being weighed, SliverSplit) is described. A null handle stands for
   * the point being inserted. */
  struct FacetAtVertex
  {
    std::array<VertexHandle, 2> edge;
    Label                       label;
    Label                       other;
  };

  /** As NonManifoldLabelsAt(), for the star whose triangles at the vertex are `facets`, each once. */
  int
  NonManifoldLabelsAmongFacets(const std::vector<FacetAtVertex> & facets) const
  {
    m_Links.clear();
    for (const FacetAtVertex & facet : facets)
    {
      AddLinkEdges(facet.label, facet.other, facet.edge, EveryLabel);
    }
    int nonManifold = 0;
    VisitLabelsNotOneCycle([&nonManifold](Label) { ++nonManifold; });
    return nonManifold;
  }

  /** The same labels, in increasing order. */
  std::vector<Label>
  ListNonManifoldLabelsAt(const Triangulation & triangulation, VertexHandle vertex,
                          const std::vector<CellHandle> & star) const
  {
    std::vector<Label> labels;
    ForEachNonManifoldLabel(
      triangulation, vertex, star, EveryLabel, [&labels](Label label) { labels.push_back(label); });
    return labels;
  }

private:
  static bool
  EveryLabel(Label)
  {
    return true;
  }

  /** Calls visit(label) for each label with tested(label) whose link at the vertex is not empty and not one cycle,
   * in increasing order. */
  template <typename TTested, typename TVisit>
  void
  ForEachNonManifoldLabel(const Triangulation & triangulation, VertexHandle vertex,
                          const std::vector<CellHandle> & star, TTested && tested, TVisit && visit) const
  {
    // (label, link edge): a few dozen entries, so flat and sorted rather than a map of vectors.
    m_Links.clear();
    for (const CellHandle cell : star)
    {
      const int   own = cell->index(vertex);
      const Label label = LabelOf(triangulation, cell);
      for (int facet = 0; facet < 4; ++facet)
      {
        if (facet == own)
        {
          continue;
        }
        const CellHandle neighbor = cell->neighbor(facet);
        const Label      other = LabelOf(triangulation, neighbor);
        // Each facet is seen from both sides: once is enough.
        if (label == other || neighbor < cell)
        {
          continue;
        }
        AddLinkEdges(label, other, LinkEdgeOf(cell, own, facet), tested);
      }
    }
    VisitLabelsNotOneCycle(visit);
  }

  /** Adds the edge opposite the vertex in a triangle between tetrahedra of `label` and `other` (different) to the
   * links it is on: each tissue's, and the union's when one side is the background. */
  template <typename TTested>
  void
  AddLinkEdges(Label label, Label other, const std::array<VertexHandle, 2> & edge, TTested && tested) const
  {
    if (label == other)
    {
      return;
    }
    if (label != BackgroundLabel && tested(label))
    {
      m_Links.push_back({ label, edge });
    }
    if (other != BackgroundLabel && tested(other))
    {
      m_Links.push_back({ other, edge });
    }
    if ((label == BackgroundLabel) != (other == BackgroundLabel) && tested(UnionKey))
    {
      m_Links.push_back({ UnionKey, edge });
    }
  }

  /** Calls visit(label) for each label whose link in m_Links is not one cycle, in increasing order. */
  template <typename TVisit>
  void
  VisitLabelsNotOneCycle(TVisit && visit) const
  {
    std::sort(m_Links.begin(), m_Links.end(), [](const LinkEdge & a, const LinkEdge & b) { return a.label < b.label; });
    for (auto first = m_Links.begin(); first != m_Links.end();)
    {
      const auto last =
        std::find_if(first, m_Links.end(), [first](const LinkEdge & edge) { return edge.label != first->label; });
      if (!IsOneCycle(first, last))
      {
        visit(first->label);
      }
      first = last;
    }
  }

  /** An edge of a label's link at a vertex. */
  struct LinkEdge
  {
    Label                       label;
    std::array<VertexHandle, 2> ends;
  };

  /** Whether the edges make one cycle: every end in exactly two of them, and a walk from the first edge comes back
   * after visiting them all. */
  bool
  IsOneCycle(std::vector<LinkEdge>::const_iterator first, std::vector<LinkEdge>::const_iterator last) const
  {
    const auto                  edges = static_cast<std::size_t>(last - first);
    std::vector<VertexHandle> & ends = m_Ends;
    ends.clear();
    for (auto edge = first; edge != last; ++edge)
    {
      ends.push_back(edge->ends[0]);
      ends.push_back(edge->ends[1]);
    }
    std::sort(ends.begin(), ends.end());
    for (std::size_t index = 0; index < ends.size(); index += 2)
    {
      if (ends[index] != ends[index + 1] || (index + 2 < ends.size() && ends[index + 2] == ends[index]))
      {
        return false;
      }
    }
    // Walk: from the first edge's second end, take the other edge at the current end, until back at the start.
    const VertexHandle start = first->ends[0];
    VertexHandle       current = first->ends[1];
    auto               through = first;
    std::size_t        walked = 1;
    while (current != start && walked <= edges)
    {
      auto next = first;
      while (next == through || (next->ends[0] != current && next->ends[1] != current))
      {
        ++next;
      }
      current = next->ends[0] == current ? next->ends[1] : next->ends[0];
      through = next;
      ++walked;
    }
    return current == start && walked == edges;
  }

  static Label
  LabelOf(const Triangulation & triangulation, CellHandle cell)
  {
    return triangulation.is_infinite(cell) ? BackgroundLabel : cell->cache.label;
  }

  // Scratch space of NonManifoldLabelsAt(), which runs for every corner of every move tried.
  mutable std::vector<LinkEdge>     m_Links;
  mutable std::vector<VertexHandle> m_Ends;
};

} // namespace detail
} // namespace delaunay_refinement

#endif
