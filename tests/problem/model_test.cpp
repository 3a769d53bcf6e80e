// Model keeps one stiffness, K_x = Tᵀ K T (the largest array of a run). Its bilinear form a(u, v),
// elastic energy and internal force must agree with the full K (assembled here independently)
// wherever they are used: on displacements that vanish on Γ1 and on roller-held components, and on
// the rows the certificate reads (free dofs and Γ3 nodes).
#include <hemicontact/check/evaluate.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/fem/assembly.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

using namespace hemicontact;

namespace {

// The half fig2 scene: a roller on x = ½ (held u_x, including one Γ3 node) besides Γ1 and Γ3.
Model half_scene(int n) {
  const auto scene = load_scene(HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-fig2-half.json",
                                {"mesh.n=" + std::to_string(n), "mesh.perturb=0.2"});
  return build_model(scene, HEMICONTACT_SOURCE_DIR "/problems");
}

// The 3D paper scene on an n³ box with its nodes moved (Γ3 frames, 3 × 3 node blocks).
Model perturbed_box(int n) {
  const auto scene = load_scene(HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-3d.json",
                                {"mesh.n=" + std::to_string(n), "mesh.perturb=0.2"});
  return build_model(scene, HEMICONTACT_SOURCE_DIR "/problems");
}

Vec random_vector(Index n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  Vec v(n);
  for (Index i = 0; i < n; ++i) v[i] = U(rng);
  return v;
}

}  // namespace

TEST(Model, BilinearFormAndEnergyEqualTheFullStiffness) {
  const Model md = half_scene(8);
  const SpMat K = assemble_stiffness(md.mesh, *md.material);
  ASSERT_EQ(K.rows(), md.dofs.n_full());
  ASSERT_GT(md.dofs.n_full(), md.dofs.n_free());  // Γ1 and the roller removed unknowns
  const Vec u = md.dofs.to_full(random_vector(md.dofs.n_free(), 1));
  const Vec v = md.dofs.to_full(random_vector(md.dofs.n_free(), 2));
  // a(u, v) is a sum of O(nnz) terms of size |K||u||v|: round-off of that order.
  const double scale = Mat(K).cwiseAbs().maxCoeff() * u.cwiseAbs().sum() * v.cwiseAbs().maxCoeff();
  EXPECT_NEAR(md.a(u, v), u.dot(K * v), 1e-14 * scale);
  EXPECT_NEAR(md.a(u, v), md.a(v, u), 1e-14 * scale);  // symmetry
  EXPECT_NEAR(md.a(u, u), u.dot(K * u), 1e-14 * scale);
  EXPECT_NEAR(md.elastic_energy(u), 0.5 * u.dot(K * u), 1e-14 * scale);
  EXPECT_GT(md.a(u, u), 0.0);  // positive definite on the admissible space
}

TEST(Model, InternalForceEqualsFullStiffnessOnTheRowsTheCertificateReads) {
  const Model md = half_scene(8);
  const SpMat K = assemble_stiffness(md.mesh, *md.material);
  const Vec u = md.dofs.to_full(random_vector(md.dofs.n_free(), 3));
  const Vec r = md.internal_force(u), Ku = K * u;
  const double scale = Ku.cwiseAbs().maxCoeff();
  const int d = md.dim();
  std::vector<bool> on_gamma3(md.mesh.num_nodes(), false);
  for (int v : md.contact.node) on_gamma3[v] = true;
  int checked = 0, held_gamma3 = 0;
  for (Index v = 0; v < md.mesh.num_nodes(); ++v)
    for (int i = 0; i < d; ++i) {
      const Index row = d * v + i;
      const bool held = md.mesh.held(v) & (1u << i);
      if (md.clamped[v]) {
        EXPECT_EQ(r[row], 0.0) << "Γ1 reactions are not computed";
      } else if (on_gamma3[v] || !held) {
        EXPECT_NEAR(r[row], Ku[row], 1e-13 * scale) << "node " << v << " component " << i;
        ++checked;
        held_gamma3 += on_gamma3[v] && held;
      } else {
        EXPECT_EQ(r[row], 0.0) << "a roller reaction off Γ3 is not computed";
      }
    }
  EXPECT_GT(checked, md.dofs.n_free() - 1);
  EXPECT_GE(held_gamma3, 1);  // the roller holds a Γ3 node: its full force is there
}

// K_x is assembled straight into the free dofs' pattern (no full K) and kept as its lower
// triangle. It must equal the definition Tᵀ K T (two sparse products of the full K) to round-off,
// hold no entry above the diagonal, and have sorted rows, on scenes
// with everything the selection handles: Γ1, a roller (held components, one on a Γ3 node),
// perturbed Γ3 frames in 2D, and 3D (frames with two tangents).
TEST(Model, ReducedAssemblyEqualsTheReducedFullStiffness) {
  const auto check = [](const Model& md) {
    const SpMat ref = md.dofs.reduce_by_products(assemble_stiffness(md.mesh, *md.material));
    ASSERT_EQ(md.Kx.rows(), ref.rows());
    const double scale = Mat(ref).cwiseAbs().maxCoeff();
    EXPECT_LE(Mat(md.Kx.full() - ref).cwiseAbs().maxCoeff(), 1e-14 * scale);
    const SpMat& L = md.Kx.lower();
    EXPECT_TRUE(L.isCompressed());
    EXPECT_EQ(2 * L.nonZeros() - L.rows(), ref.nonZeros());  // the lower triangle, diagonal included
    for (Index j = 0; j < L.cols(); ++j) {  // sorted rows (CHOLMOD and Ipopt rely on it), none above j
      ASSERT_EQ(L.innerIndexPtr()[L.outerIndexPtr()[j]], j);
      for (int p = L.outerIndexPtr()[j] + 1; p < L.outerIndexPtr()[j + 1]; ++p)
        ASSERT_LT(L.innerIndexPtr()[p - 1], L.innerIndexPtr()[p]);
    }
    const Vec x = Vec::LinSpaced(ref.cols(), -1.0, 2.0);
    EXPECT_LE((md.Kx * x - ref * x).norm(), 1e-14 * scale * x.norm() * std::sqrt(double(ref.cols())));
  };
  check(half_scene(8));
  const auto scene3d = load_scene(HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-3d.json", {"mesh.n=4", "mesh.perturb=0.1"});
  check(build_model(scene3d, HEMICONTACT_SOURCE_DIR "/problems"));
}

// Each rank of the petsc engine assembles only its own columns (= rows, K_x symmetric),
// split at node boundaries. Every such slice must be exactly those columns of K_x and nothing else:
// on the half fig2 scene (perturbed mesh, a roller on a Γ3 node: node blocks of uneven size) and
// on the 3D box (Γ3 frames, 3 × 3 blocks).
TEST(Model, ColumnRangeAssemblyIsThoseColumnsOfKx) {
  const Model md2 = half_scene(8);
  const Model md3 = perturbed_box(4);
  for (const Model* m : {&md2, &md3}) {
    const SpMat Kx = m->Kx.full();
    const Index n = Kx.cols();
    // The first x index of every node with a free component: the admissible split points.
    std::vector<Index> first;
    const std::vector<Index> sel = m->dofs.cartesian_selection();
    for (Index v = 0; v < m->mesh.num_nodes(); ++v) {
      Index lo = n;
      for (int c = 0; c < m->dim(); ++c)
        if (sel[m->dim() * v + c] >= 0) lo = std::min(lo, sel[m->dim() * v + c]);
      if (lo < n) first.push_back(lo);
    }
    std::sort(first.begin(), first.end());
    ASSERT_GT(first.size(), 6u);
    const Mat D = m->material->tangent(Vec::Zero(voigt_size(m->dim())));
    const double scale = Kx.coeffs().cwiseAbs().maxCoeff();
    Index covered = 0;
    for (int part = 0; part < 3; ++part) {
      const Index lo = first[first.size() * part / 3];
      const Index hi = part == 2 ? n : first[first.size() * (part + 1) / 3];
      const SpMat slice = assemble_reduced_stiffness(m->mesh, D, m->dofs, lo, hi);
      ASSERT_EQ(slice.rows(), n);
      ASSERT_EQ(slice.cols(), n);
      double diff = 0;
      for (Index j = 0; j < n; ++j) {
        const bool in = j >= lo && j < hi;
        if (!in) {
          EXPECT_EQ(slice.col(j).nonZeros(), 0) << "column " << j << " outside [" << lo << ", " << hi << ")";
          continue;
        }
        ++covered;
        diff = std::max(diff, (Vec(slice.col(j)) - Vec(Kx.col(j))).cwiseAbs().maxCoeff());
      }
      EXPECT_LE(diff, 1e-14 * scale) << "columns [" << lo << ", " << hi << ")";
    }
    EXPECT_EQ(covered, n);
  }
}

// The graph partitioner's parts are not runs of x: a rank assembles the columns of the nodes it
// was given. Every third node (and all Γ3 nodes in one of the two sets) on the same two scenes:
// exactly those nodes' columns of K_x, nothing else; and node_graph's lists, of the marked nodes
// only, are K_x's pattern of those columns read per node (itself included, symmetric).
TEST(Model, NodeMaskAssemblyIsThoseNodesColumnsOfKx) {
  const Model md2 = half_scene(8);
  const Model md3 = perturbed_box(4);
  for (const Model* m : {&md2, &md3}) {
    const SpMat Kx = m->Kx.full();
    const Index n = Kx.cols(), N = m->mesh.num_nodes();
    const int d = m->dim();
    const std::vector<Index> sel = m->dofs.cartesian_selection();
    const Mat D = m->material->tangent(Vec::Zero(voigt_size(d)));
    const double scale = Kx.coeffs().cwiseAbs().maxCoeff();
    for (int variant = 0; variant < 2; ++variant) {
      std::vector<char> own(static_cast<size_t>(N), 0);
      for (Index v = 0; v < N; ++v) own[static_cast<size_t>(v)] = v % 3 == variant;
      if (variant == 1)
        for (Index k = 0; k < m->contact.size(); ++k) own[static_cast<size_t>(m->contact.node[static_cast<size_t>(k)])] = 1;
      const SpMat slice = assemble_reduced_stiffness(m->mesh, D, m->dofs, own);
      ASSERT_EQ(slice.cols(), n);
      std::vector<char> col_owned(static_cast<size_t>(n), 0);
      for (size_t j = 0; j < sel.size(); ++j)
        if (sel[j] >= 0 && own[j / static_cast<size_t>(d)]) col_owned[static_cast<size_t>(sel[j])] = 1;
      double diff = 0;
      Index owned_cols = 0;
      for (Index j = 0; j < n; ++j) {
        if (!col_owned[static_cast<size_t>(j)]) {
          EXPECT_EQ(slice.col(j).nonZeros(), 0) << "column " << j << " of a node not in the mask";
          continue;
        }
        ++owned_cols;
        diff = std::max(diff, (Vec(slice.col(j)) - Vec(Kx.col(j))).cwiseAbs().maxCoeff());
      }
      EXPECT_GT(owned_cols, 0);
      EXPECT_LE(diff, 1e-14 * scale) << "variant " << variant;
      const NodeGraph g = node_graph(m->mesh, &own);
      for (Index v = 0; v < N; ++v) {
        if (!own[static_cast<size_t>(v)]) {
          EXPECT_EQ(g.size(v), 0) << "node " << v;
          continue;
        }
        ASSERT_TRUE(std::is_sorted(g.begin(v), g.end(v)));
        EXPECT_TRUE(std::binary_search(g.begin(v), g.end(v), static_cast<int>(v))) << "node " << v;
        // Node b is a neighbour iff the full stiffness couples v and b (P1: through a shared cell).
        std::vector<int> expect;
        for (Index c = 0; c < m->mesh.num_cells(); ++c) {
          bool has = false;
          for (int a = 0; a <= d; ++a) has = has || m->mesh.cells(c, a) == v;
          if (has)
            for (int a = 0; a <= d; ++a) expect.push_back(m->mesh.cells(c, a));
        }
        std::sort(expect.begin(), expect.end());
        expect.erase(std::unique(expect.begin(), expect.end()), expect.end());
        EXPECT_EQ(std::vector<int>(g.begin(v), g.end(v)), expect) << "node " << v;
      }
    }
  }
}

// The petsc engine's model keeps no K_x; the engine gives the judge K_x x (evaluate_solution's
// second form). That form must give what the model's own K_x gives, bit for bit, and the lean model
// must refuse to apply the K_x it does not hold rather than multiply by an empty matrix.
TEST(Model, AGivenStiffnessProductJudgesAsTheModelsOwnAndALeanModelRefuses) {
  const Model md = half_scene(8);
  const Model lean = build_model(load_scene(HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-fig2-half.json",
                                            {"mesh.n=8", "mesh.perturb=0.2"}),
                                 HEMICONTACT_SOURCE_DIR "/problems", /*stiffness=*/false);
  ASSERT_TRUE(lean.Kx.empty());
  const SolveOptions opt;
  Solution own, given;
  own.u = given.u = md.dofs.to_full(random_vector(md.dofs.n_free(), 3));
  evaluate_solution(md, opt, own);
  evaluate_solution(lean, opt, given, md.Kx * md.dofs.to_reduced(given.u));
  EXPECT_EQ(given.energy, own.energy);
  EXPECT_EQ(given.a_uu, own.a_uu);
  EXPECT_EQ(given.certificate.max_residual, own.certificate.max_residual);
  ASSERT_EQ(given.status.size(), own.status.size());
  for (size_t k = 0; k < own.status.size(); ++k) EXPECT_EQ(given.status[k].str(), own.status[k].str()) << "node " << k;
  EXPECT_THROW((void)lean.internal_force(own.u), Error);
  EXPECT_THROW((void)lean.a(own.u, own.u), Error);
}
