// The block split of the 3D paper scene's box (the petsc engine's producer for more ranks than
// cell layers): each block's nodes, numbered back into the whole box by block_global_node, sit
// where the whole mesh has them, and its boundary facets carry the whole mesh's parts, facet for
// facet; the blocks together hold each of the whole mesh's parted facets exactly once.
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/scene/slab_mesh.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <map>
#include <vector>

using namespace hemicontact;

namespace {

using FacetKey = std::array<long, 3>;

FacetKey key(long a, long b, long c) {
  FacetKey k{a, b, c};
  std::sort(k.begin(), k.end());
  return k;
}

}  // namespace

TEST(BlockMesh, BlocksOfTheSceneBoxCarryTheWholeMeshesNodesAndParts) {
  const auto scene = load_scene(HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-3d.json", {"mesh.n=6"});
  const Mesh whole = build_mesh(scene, HEMICONTACT_SOURCE_DIR "/problems");
  std::map<FacetKey, Part> parts;
  for (Index f = 0; f < whole.num_facets(); ++f)
    if (whole.facet_part[static_cast<size_t>(f)] != Part::NONE)
      parts[key(whole.facets(f, 0), whole.facets(f, 1), whole.facets(f, 2))] = whole.facet_part[static_cast<size_t>(f)];
  ASSERT_FALSE(parts.empty());
  std::map<FacetKey, int> seen;
  const std::vector<BlockRange> blocks = {{0, 2, 0, 6}, {2, 6, 0, 1}, {2, 5, 1, 6}, {5, 6, 1, 6}};
  for (const BlockRange& b : blocks) {
    std::vector<long> counts;
    const Mesh m = build_block_mesh(scene, b, counts);
    std::vector<long> g(static_cast<size_t>(m.num_nodes()));
    for (Index v = 0; v < m.num_nodes(); ++v) {
      g[static_cast<size_t>(v)] = block_global_node(scene, b, v);
      ASSERT_GE(g[static_cast<size_t>(v)], 0);
      ASSERT_LT(g[static_cast<size_t>(v)], whole.num_nodes());
      ASSERT_EQ(m.points.row(v), whole.points.row(g[static_cast<size_t>(v)])) << "node " << v;
    }
    for (Index f = 0; f < m.num_facets(); ++f) {
      if (m.facet_part[static_cast<size_t>(f)] == Part::NONE) continue;  // a cut face, or a face without a condition
      const FacetKey k = key(g[static_cast<size_t>(m.facets(f, 0))], g[static_cast<size_t>(m.facets(f, 1))],
                             g[static_cast<size_t>(m.facets(f, 2))]);
      ASSERT_TRUE(parts.count(k)) << "a block facet with a part that the whole mesh's facet lacks";
      EXPECT_EQ(m.facet_part[static_cast<size_t>(f)], parts.at(k));
      ++seen[k];
    }
  }
  EXPECT_EQ(seen.size(), parts.size()) << "every parted facet of the whole mesh lies in some block";
  for (const auto& [k, n] : seen) EXPECT_EQ(n, 1) << "a facet in two blocks";
}
