// The structured box generator (make_box): tiling, conformity, orientation and mirror symmetry.
#include <hemicontact/mesh/generators.hpp>
#include <hemicontact/mesh/slabs.hpp>

#include "../support/expect_error.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <utility>
#include <vector>

using namespace hemicontact;
using hemicontact::test::expect_input_error;

namespace {

using Key = std::array<int, 3>;

// Every triangular face of every tet, with the number of tets it belongs to.
std::map<Key, int> face_counts(const Mesh& m) {
  std::map<Key, int> count;
  static const int faces[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  for (Index c = 0; c < m.num_cells(); ++c)
    for (const auto& f : faces) {
      Key k{m.cells(c, f[0]), m.cells(c, f[1]), m.cells(c, f[2])};
      std::sort(k.begin(), k.end());
      ++count[k];
    }
  return count;
}

bool on_box_boundary(const Mesh& m, const Key& k, const BoxSpec& s) {
  const double lo[3] = {s.x0, s.y0, s.z0}, hi[3] = {s.x1, s.y1, s.z1};
  for (int a = 0; a < 3; ++a) {
    bool all_lo = true, all_hi = true;
    for (int v : k) {
      all_lo &= m.points(v, a) == lo[a];
      all_hi &= m.points(v, a) == hi[a];
    }
    if (all_lo || all_hi) return true;
  }
  return false;
}

}  // namespace

class BoxTiling : public ::testing::TestWithParam<std::tuple<BoxPattern, int>> {};

// Volumes sum to the box's, every tet is positive (check_cells), every face lies in exactly two
// tets unless it is on the box surface (conformity: a hanging face inside would be counted once),
// and the surface triangles add up to the surface area.
TEST_P(BoxTiling, VolumeConformityOrientation) {
  const auto [pattern, n] = GetParam();
  BoxSpec s;
  s.x1 = 2.0;
  s.y0 = -1.0;
  s.z1 = 0.5;
  s.nx = n;
  s.ny = n + 2;
  s.nz = n + 1;
  s.pattern = pattern;
  const Mesh m = make_box(s);
  EXPECT_EQ(m.num_cells(), 6 * s.nx * s.ny * s.nz);
  EXPECT_NO_THROW(check_cells(m));
  double vol = 0;
  for (Index c = 0; c < m.num_cells(); ++c) vol += m.cell_measure(c);
  EXPECT_NEAR(vol, 2.0 * 2.0 * 0.5, 1e-13);
  Index boundary = 0;
  for (const auto& [k, cnt] : face_counts(m)) {
    ASSERT_LE(cnt, 2);
    if (cnt == 1) {
      EXPECT_TRUE(on_box_boundary(m, k, s)) << "interior face (" << k[0] << "," << k[1] << "," << k[2]
                                            << ") belongs to one tet only: the split is not conforming";
      ++boundary;
    }
  }
  EXPECT_EQ(boundary, 4 * (s.nx * s.ny + s.ny * s.nz + s.nx * s.nz));
  EXPECT_EQ(m.num_facets(), boundary);
  double area = 0;
  for (Index f = 0; f < m.num_facets(); ++f) area += m.facet_measure(f);
  EXPECT_NEAR(area, 2 * (2.0 * 2.0 + 2.0 * 0.5 + 2.0 * 0.5), 1e-12);
}

INSTANTIATE_TEST_SUITE_P(BothPatterns, BoxTiling,
                         ::testing::Combine(::testing::Values(BoxPattern::KUHN, BoxPattern::SYMMETRIC),
                                            ::testing::Values(2, 4)));

// The reflections x → x0 + x1 − x and y → y0 + y1 − y map the node grid to itself; under each, the
// symmetric mesh's tets (as node sets) are mapped onto its tets. The Kuhn mesh is not symmetric.
TEST(Box, SymmetricPatternIsMirrorSymmetric) {
  for (BoxPattern p : {BoxPattern::SYMMETRIC, BoxPattern::KUHN}) {
    BoxSpec s;
    s.nx = 4;
    s.ny = 6;
    s.nz = 3;
    s.pattern = p;
    const Mesh m = make_box(s);
    const auto grid = [&](int i, int j, int k) { return (k * (s.ny + 1) + j) * (s.nx + 1) + i; };
    std::set<std::array<int, 4>> cells;
    for (Index c = 0; c < m.num_cells(); ++c) {
      std::array<int, 4> t{m.cells(c, 0), m.cells(c, 1), m.cells(c, 2), m.cells(c, 3)};
      std::sort(t.begin(), t.end());
      cells.insert(t);
    }
    for (int axis = 0; axis < 2; ++axis) {
      std::vector<int> image(m.num_nodes());
      for (int k = 0; k <= s.nz; ++k)
        for (int j = 0; j <= s.ny; ++j)
          for (int i = 0; i <= s.nx; ++i)
            image[grid(i, j, k)] = axis == 0 ? grid(s.nx - i, j, k) : grid(i, s.ny - j, k);
      // The node map is the geometric reflection.
      for (Index v = 0; v < m.num_nodes(); ++v) EXPECT_NEAR(m.points(image[v], axis), 1.0 - m.points(v, axis), 1e-15);
      int mapped = 0;
      for (const auto& t : cells) {
        std::array<int, 4> r{image[t[0]], image[t[1]], image[t[2]], image[t[3]]};
        std::sort(r.begin(), r.end());
        mapped += cells.count(r) ? 1 : 0;
      }
      if (p == BoxPattern::SYMMETRIC)
        EXPECT_EQ(mapped, static_cast<int>(cells.size())) << "axis " << axis;
      else
        EXPECT_LT(mapped, static_cast<int>(cells.size())) << "axis " << axis;
    }
  }
}

// On the xz faces (y = y0) the Kuhn split draws the 2D "right" diagonal from (x_i, z_k) to
// (x_{i+1}, z_{k+1}): the slab test relies on it to compare with make_rectangle's RIGHT mesh.
TEST(Box, KuhnFrontFaceIsTheRightDiagonal) {
  BoxSpec s;
  s.nx = 3;
  s.ny = 2;
  s.nz = 4;
  const Mesh m = make_box(s);
  int checked = 0;
  for (Index f = 0; f < m.num_facets(); ++f) {
    bool front = true;
    for (int a = 0; a < 3; ++a) front &= m.points(m.facets(f, a), 1) == 0.0;
    if (!front) continue;
    // The facet's edge that is not axis-parallel runs with dx·dz > 0.
    for (int a = 0; a < 3; ++a) {
      const auto p = m.points.row(m.facets(f, a)), q = m.points.row(m.facets(f, (a + 1) % 3));
      const double dx = q[0] - p[0], dz = q[2] - p[2];
      if (dx != 0 && dz != 0) {
        EXPECT_GT(dx * dz, 0.0);
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, 2 * s.nx * s.nz);
}

TEST(Box, PerturbedStaysValidAndKeepsTheBoundary) {
  BoxSpec s;
  s.nx = s.ny = s.nz = 4;
  s.perturb = 0.3;
  const Mesh m = make_box(s);
  EXPECT_NO_THROW(check_cells(m));
  double vol = 0;
  for (Index c = 0; c < m.num_cells(); ++c) vol += m.cell_measure(c);
  EXPECT_NEAR(vol, 1.0, 1e-13);
  EXPECT_EQ(m.num_facets(), 4 * 3 * 16);
}

TEST(Box, BadSpecsAreInputErrors) {
  BoxSpec s;
  s.pattern = BoxPattern::SYMMETRIC;
  s.nx = 3;
  expect_input_error([&] { make_box(s); }, {"even nx and ny"});
  BoxSpec e;
  e.nz = 0;
  expect_input_error([&] { make_box(e); }, {"nx, ny and nz"});
  BoxSpec f;
  f.z1 = f.z0;
  expect_input_error([&] { make_box(f); }, {"empty box"});
  expect_input_error([] { parse_box_pattern("freudenthal"); }, {"mesh.pattern"});
}

// ---------------------------------------------------------------- slabs (mesh/slabs.hpp)

namespace {

// Each cell as the sorted coordinates of its vertices (a key independent of the node numbering).
std::multiset<std::vector<double>> cell_places(const Mesh& m) {
  std::multiset<std::vector<double>> out;
  for (Index c = 0; c < m.num_cells(); ++c) {
    std::vector<std::vector<double>> v;
    for (int a = 0; a < m.cells.cols(); ++a)
      v.push_back(std::vector<double>(m.points.row(m.cells(c, a)).data(), m.points.row(m.cells(c, a)).data() + m.dim));
    std::sort(v.begin(), v.end());
    std::vector<double> key;
    for (const auto& p : v) key.insert(key.end(), p.begin(), p.end());
    out.insert(key);
  }
  return out;
}

// The facets each selector picks, counted on the whole mesh and summed over slabs that tile it.
std::vector<long> whole_counts(Mesh m, const BoundarySpec& spec) {
  const RowMat lo = m.points.colwise().minCoeff(), hi = m.points.colwise().maxCoeff();
  return assign_boundary_in_box(m, spec, lo, hi);
}

// Pieces of a box (slabs or blocks), added one by one: their cells' places and the facets each
// selector selected on them (with the whole box's sides), against the whole mesh's.
struct BoxPieces {
  BoxPieces(const BoxSpec& s, const BoundarySpec& spec) : spec(spec), lo(1, 3), hi(1, 3) {
    lo << s.x0, s.y0, s.z0;
    hi << s.x1, s.y1, s.z1;
  }
  void add(Mesh piece) {
    const std::vector<long> c = assign_boundary_in_box(piece, spec, lo, hi);
    sum.resize(c.size(), 0);
    for (size_t i = 0; i < c.size(); ++i) sum[i] += c[i];
    const auto p = cell_places(piece);
    cells.insert(p.begin(), p.end());
  }
  void expect_tile(const Mesh& whole, BoxPattern pattern) const {
    EXPECT_EQ(cells, cell_places(whole)) << to_string(pattern);
    EXPECT_EQ(sum, whole_counts(whole, spec)) << to_string(pattern);
  }
  const BoundarySpec& spec;
  RowMat lo, hi;
  std::multiset<std::vector<double>> cells;
  std::vector<long> sum;
};

}  // namespace

// The per-rank pieces of the petsc engine's distributed path: slabs that tile the mesh hold its
// cells, each once with the same vertices and split, and their boundary parts (taken with the
// whole box's sides) add up to the whole mesh's.
TEST(Box, SlabsTileTheBoxWithTheSameCellsAndParts) {
  for (BoxPattern pattern : {BoxPattern::KUHN, BoxPattern::SYMMETRIC}) {
    BoxSpec s;
    s.nx = 4, s.ny = 6, s.nz = 3, s.pattern = pattern;
    const Mesh whole = make_box(s);
    BoundarySpec spec;
    BoundarySelector left, bottom;
    left.side = "left", left.context = "left", left.from = 0.5;
    bottom.side = "bottom", bottom.context = "bottom";
    spec.gamma1 = {left};
    spec.gamma3 = {bottom};
    BoxPieces pieces(s, spec);
    for (auto [j0, j1] : {std::pair{0, 2}, std::pair{2, 3}, std::pair{3, 6}}) {
      Mesh slab = make_box_slab(s, j0, j1);
      EXPECT_EQ(slab.num_nodes(), Index(s.nx + 1) * (j1 - j0 + 1) * (s.nz + 1));
      pieces.add(std::move(slab));
    }
    pieces.expect_tile(whole, pattern);
  }
  // The rectangle, cut along x, graded along the cut as well.
  RectangleSpec r;
  r.nx = 6, r.ny = 4, r.diagonal = Diagonal::SYMMETRIC, r.grade_x = GradeTowards::BOTH, r.grading_power = 2;
  std::multiset<std::vector<double>> cells;
  for (auto [i0, i1] : {std::pair{0, 1}, std::pair{1, 4}, std::pair{4, 6}}) {
    const auto p = cell_places(make_rectangle_slab(r, i0, i1));
    cells.insert(p.begin(), p.end());
  }
  EXPECT_EQ(cells, cell_places(make_rectangle(r)));

  BoxSpec q;
  q.perturb = 0.1;
  expect_input_error([&] { (void)make_box_slab(q, 0, 2); }, {"mesh.perturb"});
  r.diagonal = Diagonal::CROSSED;
  expect_input_error([&] { (void)make_rectangle_slab(r, 0, 2); }, {"crossed"});
}

// The block split (more ranks than cell layers): columns [i0, i1) × [j0, j1) of a 3 × 2 grid tile
// the box with the whole mesh's cells and boundary parts, in both patterns (the symmetric one
// mirrors at the middle, which the blocks cross), and each block's nodes sit where its numbering
// says.
TEST(Box, BlocksTileTheBoxWithTheSameCellsAndParts) {
  for (BoxPattern pattern : {BoxPattern::KUHN, BoxPattern::SYMMETRIC}) {
    BoxSpec s;
    s.nx = 6, s.ny = 6, s.nz = 2, s.pattern = pattern;
    const Mesh whole = make_box(s);
    BoundarySpec spec;
    BoundarySelector left, bottom, front;
    left.side = "left", left.context = "left", left.from = 0.5;
    bottom.side = "bottom", bottom.context = "bottom";
    front.side = "front", front.context = "front", front.traction = Vec::Zero(3);
    spec.gamma1 = {left};
    spec.gamma2 = {front};
    spec.gamma3 = {bottom};
    BoxPieces pieces(s, spec);
    for (auto [i0, i1] : {std::pair{0, 2}, std::pair{2, 5}, std::pair{5, 6}})
      for (auto [j0, j1] : {std::pair{0, 4}, std::pair{4, 6}}) {
        Mesh block = make_box_block(s, i0, i1, j0, j1);
        ASSERT_EQ(block.num_nodes(), Index(i1 - i0 + 1) * (j1 - j0 + 1) * (s.nz + 1));
        for (int k = 0; k <= s.nz; ++k)
          for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i) {
              const Index v = (Index(k) * (j1 - j0 + 1) + j - j0) * (i1 - i0 + 1) + i - i0;
              const Index g = (Index(k) * (s.ny + 1) + j) * (s.nx + 1) + i;
              ASSERT_EQ(block.points.row(v), whole.points.row(g)) << i << " " << j << " " << k;
            }
        pieces.add(std::move(block));
      }
    pieces.expect_tile(whole, pattern);
  }
  BoxSpec q;
  q.perturb = 0.1;
  expect_input_error([&] { (void)make_box_block(q, 0, 1, 0, 2); }, {"mesh.perturb"});
}
