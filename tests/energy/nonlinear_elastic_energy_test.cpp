// NonlinearElasticEnergy (nonlinear_elastic_energy.hpp): value → gradient → Hessian by finite
// differences in the reduced unknowns (Γ1 eliminated, Γ3 nodes in their rotated (ν, τ) frames), in
// 2D (the hencky paper scene on a coarse mesh) and 3D (a cube of 6 tetrahedra); and for a linear
// material the term equals ½ xᵀ K x exactly (same K as the assembly).

#include <hemicontact/energy/nonlinear_elastic_energy.hpp>
#include <hemicontact/energy/total_energy.hpp>
#include <hemicontact/fem/assembly.hpp>
#include <hemicontact/material/hencky.hpp>
#include <hemicontact/material/linear_elastic.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>

#include "support/fd_check.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <random>

using namespace hemicontact;

namespace {

// Dense Hessian from the lower-triangular pattern the term fills.
Mat dense_hessian(const NonlinearElasticEnergy& e, const Vec& x) {
  SpMat H = e.lower();
  std::fill(H.valuePtr(), H.valuePtr() + H.nonZeros(), 0.0);
  e.add_hessian(x, H, Psd::NONE);
  const Mat L = Mat(H);
  return Mat(L.selfadjointView<Eigen::Lower>());
}

// Central differences on unknowns of size `scale` (strains ~ scale/h ≫ ε_ref, so the law is well
// inside its nonlinear range): the energy is a sum of ~100 smooth cell terms, |E| ~ μ (scale/h)²;
// step 1e-6·max(1, |x|) gives truncation ~1e-12·|E'''| and round-off ~1e-10·|E|, both ≪ 1e-6 of the
// gradient; the Hessian differentiates the exact gradient once: 1e-5.
void check_fd(const NonlinearElasticEnergy& e, const Vec& x) {
  Vec g = Vec::Zero(x.size());
  e.add_gradient(x, g);
  const Vec fd_g = test::fd_gradient([&](const Vec& y) { return e.value(y); }, x);
  EXPECT_TRUE(test::near_rel(g, fd_g, 1e-6, 0));
  const Mat fd_H = test::fd_jacobian(
      [&](const Vec& y) {
        Vec gy = Vec::Zero(y.size());
        e.add_gradient(y, gy);
        return gy;
      },
      x);
  const Mat H = dense_hessian(e, x);
  EXPECT_TRUE(test::near_rel(H, fd_H, 1e-5, 0));
  std::printf("[ fd       ] %zu unknowns: gradient %.2e, Hessian %.2e (max abs error / max abs entry)\n",
              static_cast<size_t>(x.size()), (g - fd_g).cwiseAbs().maxCoeff() / g.cwiseAbs().maxCoeff(),
              (H - fd_H).cwiseAbs().maxCoeff() / H.cwiseAbs().maxCoeff());
  EXPECT_LE((fd_H - fd_H.transpose()).cwiseAbs().maxCoeff(), 1e-5 * fd_H.cwiseAbs().maxCoeff());
}

}  // namespace

TEST(NonlinearElasticEnergy, FiniteDifferences2D) {
  const auto scene = load_scene(HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-fig2-hencky.json", {"mesh.n=4"});
  const Model md = build_model(scene, HEMICONTACT_SOURCE_DIR "/problems");
  ASSERT_FALSE(md.material->is_linear());
  const NonlinearElasticEnergy e(md.mesh, md.material, md.dofs);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  for (double scale : {1e-3, 0.05, 0.5}) {
    Vec x(md.dofs.n_free());
    for (Index i = 0; i < x.size(); ++i) x[i] = scale * u(rng);
    check_fd(e, x);
  }
  // The Hessian at 0 is the reduced small-strain stiffness K(0) the model assembled.
  const Mat H0 = dense_hessian(e, Vec::Zero(md.dofs.n_free()));
  EXPECT_TRUE(test::near_rel(H0, Mat(md.Kx.full()), 1e-13, 0));
  // The model's internal force and energy are this term's, in full unknowns.
  Vec x(md.dofs.n_free());
  for (Index i = 0; i < x.size(); ++i) x[i] = 0.1 * u(rng);
  Vec g = Vec::Zero(x.size());
  e.add_gradient(x, g);
  EXPECT_TRUE(test::near_rel(md.dofs.to_reduced(md.internal_force(md.dofs.to_full(x))), g, 1e-14, 0));
  EXPECT_DOUBLE_EQ(md.elastic_energy(md.dofs.to_full(x)), e.value(x));
}

TEST(NonlinearElasticEnergy, FiniteDifferences3D) {
  // Unit cube, 6 tetrahedra around the diagonal (0,0,0)–(1,1,1) (Kuhn), node 0 clamped.
  Mesh m;
  m.dim = 3;
  m.points.resize(8, 3);
  for (int k = 0; k < 8; ++k) m.points.row(k) << (k & 1), (k >> 1) & 1, (k >> 2) & 1;
  m.cells.resize(6, 4);
  const int perms[6][3] = {{1, 2, 4}, {1, 4, 2}, {2, 1, 4}, {2, 4, 1}, {4, 1, 2}, {4, 2, 1}};
  for (int t = 0; t < 6; ++t) {
    const int a = perms[t][0], b = a | perms[t][1];
    m.cells.row(t) << 0, a, b, 7;
    // Orient positively.
    Eigen::Matrix3d J;
    for (int k = 0; k < 3; ++k) J.col(k) = (m.points.row(m.cells(t, k + 1)) - m.points.row(0)).transpose();
    if (J.determinant() < 0) std::swap(m.cells(t, 1), m.cells(t, 2));
  }
  std::vector<bool> clamped(8, false);
  clamped[0] = true;
  const DofMap dofs(m, clamped, ContactNodes{});
  ASSERT_EQ(dofs.n_free(), 21);
  auto law = std::make_shared<Hencky>(Hencky::from_young(2000, 0.3, 0.4, 0.02, 3));
  const NonlinearElasticEnergy e(m, law, dofs);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1, 1);
  for (double scale : {1e-3, 0.05, 0.5}) {
    Vec x(dofs.n_free());
    for (Index i = 0; i < x.size(); ++i) x[i] = scale * u(rng);
    check_fd(e, x);
  }
  // Linear material: the term is ½ xᵀ K x with K from the linear assembly (to round-off).
  auto lin = std::make_shared<LinearElastic>(2000, 0.3, PlaneMode::NONE_3D);
  const NonlinearElasticEnergy el(m, lin, dofs);
  const SpMat Kx = dofs.reduce(assemble_stiffness(m, *lin));
  Vec x(dofs.n_free());
  for (Index i = 0; i < x.size(); ++i) x[i] = u(rng);
  EXPECT_NEAR(el.value(x), 0.5 * x.dot(Kx * x), 1e-13 * x.dot(Kx * x));
  EXPECT_TRUE(test::near_rel(dense_hessian(el, x), Mat(Kx), 1e-13, 0));
}

// The term owns its mesh and dof map (copies): it outlives the Model it was built from.
TEST(NonlinearElasticEnergy, OutlivesTheModel) {
  const auto scene = load_scene(HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-fig2-hencky.json", {"mesh.n=2"});
  std::unique_ptr<NonlinearElasticEnergy> e;
  Vec x, g_ref;
  double v_ref = 0;
  {
    const Model md = build_model(scene, HEMICONTACT_SOURCE_DIR "/problems");
    e = std::make_unique<NonlinearElasticEnergy>(md.mesh, md.material, md.dofs);
    x = Vec::LinSpaced(md.dofs.n_free(), -0.01, 0.02);
    v_ref = md.elastic_energy(md.dofs.to_full(x));
    g_ref = md.dofs.to_reduced(md.internal_force(md.dofs.to_full(x)));
  }
  EXPECT_DOUBLE_EQ(e->value(x), v_ref);
  Vec g = Vec::Zero(x.size());
  e->add_gradient(x, g);
  EXPECT_TRUE(test::near_rel(g, g_ref, 1e-14, 0));
}
