// A 3D slab matches the 2D plane-strain solution (the 3D code checked against the 2D one).
//
// With Poisson's ratio ν = 0, plane strain has σ_yy = λ(ε_xx + ε_zz) = 0, so the plane-strain
// displacement field (extended constantly in y, with u_y = 0) also solves the 3D problem on the
// slab [0,1]×[0,t]×[0,1] with traction-free front and back faces: same clamped top, same
// tractions on the upper halves of the left and right sides, same soft layer and friction under
// the bottom. The two discrete solutions are different P1 approximations (the Kuhn tets restricted
// to an xz plane are the 2D `right` triangles, but the 3D space is not the extruded 2D one), so
// they agree up to the discretization error, O(h) in the energy norm for both: the test checks
// that the gap is small on a coarse mesh and shrinks when h is halved.
#include <hemicontact/check/contact_status.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/solve.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace hemicontact;
using json = nlohmann::json;

namespace {

constexpr double E = 2000, F2 = 4000, F0 = 500;  // half the fig2 side loads: compliance and contact

json slab_scene(int dim, int n, int ny, double nu = 0.0, bool rollers = false) {
  const double t = double(ny) / n;  // slab thickness: ny cubic cells
  json s = {{"material", {{"model", "linear_elastic"}, {"E", E}, {"nu", nu}, {"plane", "strain"}}},
            {"contact",
             {{"gap", 0.15},
              {"normal_law", {{"type", "paper"}, {"c1", 100}, {"c2", -100}, {"c3", 400}, {"r1", 0.1}, {"r2", 0.15}}},
              {"friction", {{"type", "coulomb_layer"}, {"mu", 0.2}}}}},
            {"check", {{"smallness", false}}}};
  if (dim == 2) {
    s["mesh"] = {{"type", "rectangle"}, {"n", n}, {"diagonal", "right"}};
    s["boundary"] = {{"gamma1", {{{"side", "top"}}}},
                     {"gamma2",
                      {{{"side", "left"}, {"from", 0.5}, {"traction", {F2, 0}}},
                       {{"side", "right"}, {"from", 0.5}, {"traction", {-F2, 0}}}}},
                     {"gamma3", {{{"side", "bottom"}}}}};
    s["loads"] = {{"body_force", {0, -F0}}};
  } else {
    s["mesh"] = {{"type", "box"}, {"nx", n}, {"ny", ny}, {"nz", n}, {"y", {0, t}}, {"pattern", "kuhn"}};
    s["material"].erase("plane");
    s["boundary"] = {{"gamma1", {{{"side", "top"}}}},
                     {"gamma2",
                      {{{"side", "left"}, {"from", 0.5}, {"traction", {F2, 0, 0}}},
                       {{"side", "right"}, {"from", 0.5}, {"traction", {-F2, 0, 0}}}}},
                     {"gamma3", {{{"side", "bottom"}}}}};
    s["loads"] = {{"body_force", {0, 0, -F0}}};
    if (rollers)
      s["boundary"]["rollers"] = {{{"side", "front"}, {"components", {"y"}}},
                                  {{"side", "back"}, {"components", {"y"}}}};
  }
  return validate_scene(s);
}

struct SlabSolved {
  Model md;
  Solution sol;
};

SlabSolved solve_slab(int dim, int n, int ny = 2, double nu = 0.0, bool rollers = false) {
  const json scene = slab_scene(dim, n, ny, nu, rollers);
  SlabSolved s{build_model(scene, "."), {}};
  s.sol = solve(s.md, solve_options_from_scene(scene));
  return s;
}

// Largest differences between the 2D answer and the 3D slab at matching Γ3 nodes (every 3D node
// with the 2D node's x), relative to the largest 2D displacement U.
struct Gap3D2D {
  double u_nu = 0, u_tau = 0, u_y = 0, energy = 0;
  int compared = 0, status_mismatches = 0;
};

Gap3D2D compare(const SlabSolved& a, const SlabSolved& b, double thickness) {
  Gap3D2D g;
  const double U = a.sol.u.cwiseAbs().maxCoeff();
  std::vector<Index> match(b.md.contact.size(), -1);
  for (Index k3 = 0; k3 < b.md.contact.size(); ++k3) {
    const double x = b.md.mesh.points(b.md.contact.node[k3], 0);
    for (Index k = 0; k < a.md.contact.size(); ++k)
      if (std::abs(a.md.mesh.points(a.md.contact.node[k], 0) - x) < 1e-12) match[k3] = k;
    EXPECT_GE(match[k3], 0) << "no 2D node at x = " << x;
    if (match[k3] < 0) return g;
  }
  const auto& s2 = a.sol.state;
  const auto& s3 = b.sol.state;
  for (Index k3 = 0; k3 < b.md.contact.size(); ++k3) {
    const Index k2 = match[k3];
    g.u_nu = std::max(g.u_nu, std::abs(s3.u_nu[k3] - s2.u_nu[k2]) / U);
    // 2D: τ = (1, 0) on the bottom; 3D: u_τ's x component.
    g.u_tau = std::max(g.u_tau, std::abs(s3.u_tau_vec(k3, 0) - s2.u_tau[k2]) / U);
    g.u_y = std::max(g.u_y, std::abs(s3.u_tau_vec(k3, 1)) / U);
  }
  // Statuses must agree (2D slip± = 3D slip with the sign in u_τ,x), except where the difference
  // is explained by the discretization gap: the 3D u_ν lies within twice the largest u_ν gap of the
  // status boundary (0 or g), or |u_τ,x| within twice the largest u_τ gap of 0. Such a node may
  // fall on either side in the two discretizations; it is counted as not compared.
  const double d_nu = 2 * g.u_nu * U, d_tau = 2 * g.u_tau * U;
  for (Index k3 = 0; k3 < b.md.contact.size(); ++k3) {
    const Index k2 = match[k3];
    const double un = s3.u_nu[k3], ut = s3.u_tau_vec(k3, 0), gap = b.md.contact.g[k3];
    const NodeStatus st2 = a.sol.status[k2], st3 = b.sol.status[k3];
    const bool slip2 = st2.tangential != TangentialStatus::STICK, slip3 = st3.tangential != TangentialStatus::STICK;
    const bool same_dir = !slip2 || !slip3 || (st2.tangential == TangentialStatus::SLIP_PLUS) == (ut > 0);
    const bool same_normal = st2.normal == st3.normal, same_tangential = slip2 == slip3 && same_dir;
    const bool near_normal = std::abs(un) <= d_nu || std::abs(un - gap) <= d_nu;
    if ((!same_normal && near_normal) || (!same_tangential && std::abs(ut) <= d_tau)) continue;
    ++g.compared;
    if (!same_normal || !same_tangential) {
      ++g.status_mismatches;
      std::printf("  x = %g y = %g: 2D %s (u_nu %.6g, u_tau %.3g), 3D %s (u_nu %.6g, u_tau_x %.3g)\n",
                  b.md.mesh.points(b.md.contact.node[k3], 0), b.md.mesh.points(b.md.contact.node[k3], 1),
                  st2.str().c_str(), s2.u_nu[k2], s2.u_tau[k2], st3.str().c_str(), un, ut);
    }
  }
  g.energy = std::abs(b.sol.energy / thickness - a.sol.energy) / std::abs(a.sol.energy);
  return g;
}

}  // namespace

TEST(Slab, MatchesPlaneStrainAndTheGapShrinksWithH) {
  Gap3D2D gaps[3];
  const int levels[3] = {4, 8, 16};
  for (int l = 0; l < 3; ++l) {
    const int n = levels[l], ny = 2;
    const SlabSolved s2 = solve_slab(2, n), s3 = solve_slab(3, n, ny);
    for (const SlabSolved* s : {&s2, &s3}) {
      ASSERT_TRUE(s->sol.ok()) << s->sol.message;
      EXPECT_LE(s->sol.certificate.max_residual, 1e-8);
    }
    ASSERT_EQ(s3.md.contact.size(), (ny + 1) * s2.md.contact.size());
    // The loads put Γ3 partly on the rigid foundation and partly in the layer only.
    const auto counts = s2.sol.status_counts();
    EXPECT_GT(counts.at("contact"), 0);
    EXPECT_GT(counts.at("compliance"), 0);
    gaps[l] = compare(s2, s3, double(ny) / n);
    const Gap3D2D& g = gaps[l];
    std::printf(
        "slab n = %d: |du_nu|/U = %.3e, |du_tau|/U = %.3e, |u_y|/U = %.3e, energy rel. %.3e, "
        "statuses compared at %d of %d nodes, mismatches %d\n",
        n, g.u_nu, g.u_tau, g.u_y, g.energy, g.compared, int(s3.md.contact.size()), g.status_mismatches);
    EXPECT_EQ(g.status_mismatches, 0) << "n = " << n;
    // Both discretizations are within O(h) of the same continuum solution (energy norm), so their
    // gap is O(h): relative to U it must stay below h/2 (measured: at most 0.25 h, the u_y of the
    // non-symmetric Kuhn split) ...
    const double h = 1.0 / n;
    for (double v : {g.u_nu, g.u_tau, g.u_y, g.energy}) EXPECT_LE(v, 0.5 * h) << "n = " << n;
    // ... and most nodes are far enough from a status boundary for the statuses to be compared.
    EXPECT_GE(g.compared, int(s3.md.contact.size()) * 3 / 4) << "n = " << n;
  }
  // ... and shrink under refinement: halving h twice must shrink every gap by at least 2 (observed
  // order ≥ 1/2; first order would give 4).
  const double g0[4] = {gaps[0].u_nu, gaps[0].u_tau, gaps[0].u_y, gaps[0].energy};
  const double g2[4] = {gaps[2].u_nu, gaps[2].u_tau, gaps[2].u_y, gaps[2].energy};
  for (int i = 0; i < 4; ++i) EXPECT_LE(g2[i], 0.5 * g0[i]) << "quantity " << i;
}

// Plane strain with ν ≠ 0 is the slab whose front and back faces are rollers (u_y = 0, the other
// components free, boundary.rollers): ε_yy = 0 everywhere is then the slab's own solution. One
// cell thick, every node is on a roller face, so u_y vanishes exactly (also on the Γ3 nodes, whose
// frames take y as a tangent); the remaining gap is the two P1 discretizations' and shrinks with h.
TEST(Slab, RollersMatchPlaneStrainWithPoisson) {
  constexpr double nu = 0.3;
  Gap3D2D gaps[3];
  const int levels[3] = {4, 8, 16};
  for (int l = 0; l < 3; ++l) {
    const int n = levels[l], ny = 1;
    const SlabSolved s2 = solve_slab(2, n, ny, nu), s3 = solve_slab(3, n, ny, nu, true);
    for (const SlabSolved* s : {&s2, &s3}) {
      ASSERT_TRUE(s->sol.ok()) << s->sol.message;
      EXPECT_LE(s->sol.certificate.max_residual, 1e-8);
    }
    // Γ3 nodes hold u_y = 0 through their rotated frames: zero up to the frames' round-off.
    const double U = s3.sol.u.cwiseAbs().maxCoeff();
    for (Index v = 0; v < s3.md.mesh.num_nodes(); ++v)
      EXPECT_LE(std::abs(s3.sol.u[3 * v + 1]), 1e-14 * U) << "node " << v;
    gaps[l] = compare(s2, s3, double(ny) / n);
    const Gap3D2D& g = gaps[l];
    std::printf(
        "roller slab n = %d: |du_nu|/U = %.3e, |du_tau|/U = %.3e, energy rel. %.3e, statuses compared "
        "at %d of %d nodes, mismatches %d\n",
        n, g.u_nu, g.u_tau, g.energy, g.compared, int(s3.md.contact.size()), g.status_mismatches);
    EXPECT_EQ(g.status_mismatches, 0) << "n = " << n;
    const double h = 1.0 / n;
    for (double v : {g.u_nu, g.u_tau, g.energy}) EXPECT_LE(v, 0.5 * h) << "n = " << n;
  }
  const double g0[3] = {gaps[0].u_nu, gaps[0].u_tau, gaps[0].energy};
  const double g2[3] = {gaps[2].u_nu, gaps[2].u_tau, gaps[2].energy};
  for (int i = 0; i < 3; ++i) EXPECT_LE(g2[i], 0.5 * g0[i]) << "quantity " << i;
}

// Rollers drop exactly the held components of the non-contact nodes from the unknowns (Γ3 nodes
// keep d unknowns and hold theirs by bounds), and bad rollers are refused naming the selector.
TEST(Rollers, UnknownsAndBadInput) {
  const int n = 4, ny = 1;
  const Model free_slab = build_model(slab_scene(3, n, ny, 0.3, false), ".");
  const Model roller_slab = build_model(slab_scene(3, n, ny, 0.3, true), ".");
  Index held = 0;  // non-clamped, non-Γ3 nodes on the front/back faces (all of them at ny = 1)
  std::vector<bool> on_gamma3(roller_slab.mesh.num_nodes(), false);
  for (int v : roller_slab.contact.node) on_gamma3[v] = true;
  for (Index v = 0; v < roller_slab.mesh.num_nodes(); ++v)
    if (!roller_slab.clamped[v] && !on_gamma3[v]) ++held;
  EXPECT_EQ(free_slab.dofs.n_free() - roller_slab.dofs.n_free(), held);
  ASSERT_EQ(roller_slab.contact.fixed_local.size(), roller_slab.contact.size());
  for (Index k = 0; k < roller_slab.contact.size(); ++k) EXPECT_EQ(roller_slab.contact.fixed_local[k], 1u << 2);

  json along_normal = slab_scene(3, n, ny, 0.3, true);
  along_normal["boundary"]["rollers"] = {{{"side", "bottom"}, {"components", {"z"}}}};
  try {
    build_model(validate_scene(along_normal), ".");
    ADD_FAILURE() << "a roller along Γ3's normal was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), EXIT_INPUT);
    EXPECT_NE(std::string(e.what()).find("not tangent to Γ3"), std::string::npos) << e.what();
  }
  json flat = slab_scene(2, n, ny, 0.3, false);
  flat["boundary"]["rollers"] = {{{"side", "left"}, {"components", {"z"}}}};
  try {
    build_model(validate_scene(flat), ".");
    ADD_FAILURE() << "a z roller on a 2D mesh was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), EXIT_INPUT);
    EXPECT_NE(std::string(e.what()).find("boundary.rollers[0].components"), std::string::npos) << e.what();
  }
}

// A symmetry plane is a roller: the fig2 scene on its mirror-symmetric mesh has a symmetric
// solution ((21) holds, so it is unique), hence u_x = 0 on x = ½. The left half with a roller
// (u_x = 0) on x = ½ is then the same discrete problem restricted to the half: its solution must be
// the full solution's left half to round-off, Γ3's centre node (roller and contact) included.
TEST(Rollers, HalfOfTheSymmetricFig2IsTheFullSolution) {
  const int n = 16;
  const json full_scene = load_scene(HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-fig2.json",
                                     {"mesh.n=" + std::to_string(n), "check.smallness=false"});
  json half = full_scene;
  half["mesh"] = {{"type", "rectangle"}, {"x", {0, 0.5}}, {"y", {0, 1}},
                  {"nx", n / 2},         {"ny", n},       {"diagonal", "right"}};  // the symmetric mesh's left half
  half["boundary"]["gamma2"] = {{{"side", "left"}, {"from", 0.5}, {"traction", {8000, 0}}}};
  half["boundary"]["rollers"] = {{{"side", "right"}, {"components", {"x"}}}};
  half = validate_scene(half);
  const Model md_full = build_model(full_scene, "."), md_half = build_model(half, ".");
  const Solution full = solve(md_full, solve_options_from_scene(full_scene));
  const Solution hs = solve(md_half, solve_options_from_scene(half));
  ASSERT_TRUE(full.ok()) << full.message;
  ASSERT_TRUE(hs.ok()) << hs.message;
  EXPECT_LE(hs.certificate.max_residual, 1e-12);
  const double U = full.u.cwiseAbs().maxCoeff();
  int matched = 0;
  for (Index v = 0; v < md_half.mesh.num_nodes(); ++v)
    for (Index w = 0; w < md_full.mesh.num_nodes(); ++w)
      if ((md_full.mesh.points.row(w) - md_half.mesh.points.row(v)).norm() < 1e-12) {
        ++matched;
        EXPECT_NEAR(hs.u[2 * v], full.u[2 * w], 1e-9 * U) << "node at " << md_half.mesh.points.row(v);
        EXPECT_NEAR(hs.u[2 * v + 1], full.u[2 * w + 1], 1e-9 * U) << "node at " << md_half.mesh.points.row(v);
      }
  EXPECT_EQ(matched, (n / 2 + 1) * (n + 1));
  EXPECT_NEAR(2 * hs.energy, full.energy, 1e-9 * std::abs(full.energy));
  // The Γ3 statuses: the half's are the full's left half (the centre node sticks in both).
  for (Index k = 0; k < md_half.contact.size(); ++k) EXPECT_EQ(hs.status[k].normal, full.status[k].normal) << k;
  EXPECT_EQ(hs.status.back().tangential, TangentialStatus::STICK);
}

// The same in 3D with two symmetry planes: the 3D paper scene (symmetric box pattern, mirror
// symmetric about x = ½ and y = ½, unique solution) and its quarter [0,½]² × [0,1] (Kuhn pattern,
// which is the symmetric pattern's lower quarter) with rollers u_x = 0 on x = ½ and u_y = 0 on
// y = ½. Γ3's corner node (½, ½, 0) is held in both tangential directions. The quarter's solution
// must be the full one's quarter to round-off.
TEST(Rollers, QuarterOfTheSymmetric3DScene) {
  const int n = 8;
  const json full_scene = load_scene(HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-3d.json",
                                     {"mesh.n=" + std::to_string(n), "check.smallness=false"});
  json q = full_scene;
  q["mesh"] = {{"type", "box"}, {"x", {0, 0.5}}, {"y", {0, 0.5}}, {"z", {0, 1}},
               {"nx", n / 2},   {"ny", n / 2},   {"nz", n},       {"pattern", "kuhn"}};
  q["boundary"]["gamma2"] = {{{"side", "left"}, {"from", 0.5}, {"traction", {8000, 0, 0}}}};
  q["boundary"]["rollers"] = {{{"side", "right"}, {"components", {"x"}}}, {{"side", "back"}, {"components", {"y"}}}};
  q = validate_scene(q);
  const Model md_full = build_model(full_scene, "."), md_q = build_model(q, ".");
  const Solution full = solve(md_full, solve_options_from_scene(full_scene));
  const Solution qs = solve(md_q, solve_options_from_scene(q));
  ASSERT_TRUE(full.ok()) << full.message;
  ASSERT_TRUE(qs.ok()) << qs.message;
  const double U = full.u.cwiseAbs().maxCoeff();
  int matched = 0;
  for (Index v = 0; v < md_q.mesh.num_nodes(); ++v)
    for (Index w = 0; w < md_full.mesh.num_nodes(); ++w)
      if ((md_full.mesh.points.row(w) - md_q.mesh.points.row(v)).norm() < 1e-12) {
        ++matched;
        for (int c = 0; c < 3; ++c)
          EXPECT_NEAR(qs.u[3 * v + c], full.u[3 * w + c], 1e-8 * U) << "node at " << md_q.mesh.points.row(v);
      }
  EXPECT_EQ(matched, (n / 2 + 1) * (n / 2 + 1) * (n + 1));
  EXPECT_NEAR(4 * qs.energy, full.energy, 1e-8 * std::abs(full.energy));
  bool corner = false;
  for (Index k = 0; k < md_q.contact.size(); ++k)
    if (md_q.contact.fixed_local[k] == ((1u << 1) | (1u << 2))) {
      corner = true;
      EXPECT_EQ(qs.status[k].tangential, TangentialStatus::STICK);
    }
  EXPECT_TRUE(corner);
}
