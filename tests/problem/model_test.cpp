// Model keeps one stiffness, K_x = Tᵀ K T (issue 14). Its bilinear form a(u, v), elastic energy and
// internal force must agree with the full K (assembled here independently) wherever they are used:
// on displacements that vanish on Γ1 and on roller-held components, and on the rows the
// certificate reads (free dofs and Γ3 nodes).
#include <hemicontact/fem/assembly.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>

#include <gtest/gtest.h>

#include <random>

using namespace hemicontact;

namespace {

// The half fig2 scene: a roller on x = ½ (held u_x, including one Γ3 node) besides Γ1 and Γ3.
Model half_scene(int n) {
  const auto scene = load_scene(HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-fig2-half.json",
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

// Issue 14: K_x is assembled straight into the free dofs' pattern (no full K). It must equal the
// definition Tᵀ K T (two sparse products of the full K) to round-off, with sorted rows, on scenes
// with everything the selection handles: Γ1, a roller (held components, one on a Γ3 node),
// perturbed Γ3 frames in 2D, and 3D (frames with two tangents).
TEST(Model, ReducedAssemblyEqualsTheReducedFullStiffness) {
  const auto check = [](const Model& md) {
    const SpMat ref = md.dofs.reduce_by_products(assemble_stiffness(md.mesh, *md.material));
    ASSERT_EQ(md.Kx.rows(), ref.rows());
    const double scale = Mat(ref).cwiseAbs().maxCoeff();
    EXPECT_LE(Mat(md.Kx - ref).cwiseAbs().maxCoeff(), 1e-14 * scale);
    EXPECT_TRUE(md.Kx.isCompressed());
    for (Index j = 0; j < md.Kx.cols(); ++j)  // sorted rows (CHOLMOD and Ipopt rely on it)
      for (int p = md.Kx.outerIndexPtr()[j] + 1; p < md.Kx.outerIndexPtr()[j + 1]; ++p)
        ASSERT_LT(md.Kx.innerIndexPtr()[p - 1], md.Kx.innerIndexPtr()[p]);
  };
  check(half_scene(8));
  const auto scene3d = load_scene(HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-3d.json", {"mesh.n=4", "mesh.perturb=0.1"});
  check(build_model(scene3d, HEMICONTACT_SOURCE_DIR "/problems"));
}
