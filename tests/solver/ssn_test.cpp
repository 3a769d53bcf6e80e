// The full-space exact solver (backend ssn, solver/ssn.hpp) and the status equations it shares with
// the polishes and the petsc engine (check/status_equations.hpp): each node block is the derivative
// of its forces (finite differences), and ssn reaches the condensed exact solver's answer (same
// statuses, Γ3 values to round-off) in 2D and 3D.
#include <hemicontact/check/status_equations.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/solve.hpp>
#include <hemicontact/solver/ssn.hpp>
#include <hemicontact/studies/random_scenes.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace hemicontact {
namespace {

Model model_of(const std::string& file, const std::vector<std::string>& sets, SolveOptions& opt) {
  const nlohmann::json scene = load_scene(std::string(HEMICONTACT_SOURCE_DIR) + "/problems/" + file, sets);
  opt = solve_options_from_scene(scene);
  return build_model(scene, ".");
}

// ssn from zero on a shipped scene, with the scene's limits: the model and the limits to rerun it.
struct SsnFromZero {
  Model md;
  SsnLimits lim;
  SsnOutcome a;
};
SsnFromZero ssn_from_zero(const std::string& file, const std::vector<std::string>& sets) {
  SolveOptions opt;
  Model md = model_of(file, sets, opt);
  const SsnLimits lim{opt.ssn.max_iters, opt.ssn.tol, opt.petsc.ksp_rtol};
  SsnOutcome a = ssn_full(md, lim, nullptr);
  return {std::move(md), lim, std::move(a)};
}

// The Jacobian block of a status's rows is the derivative of their forces: a central difference
// of each force over each unknown, with a step far below the branch widths of p_ν and F_b (so the
// difference is exact up to round-off, O(ε_mach/h) relative) and far below |x_τ| (the slip
// direction's curvature gives an O(h²/|x_τ|²) term).
TEST(StatusEquations, BlocksAreTheDerivativesOfTheForces) {
  SolveOptions opt;
  const Model md = model_of("sofonea2017-3d.json", {"mesh.n=2"}, opt);
  const NodeData n = node_data(md, 0);
  const double h = 1e-7;
  for (const double x_nu : {0.05, 0.12, 0.2}) {  // the three branches of the paper's p_ν (32)
    for (const NormalStatus ns : {NormalStatus::COMPLIANCE, NormalStatus::CONTACT}) {
      const NodeStatus st{ns, TangentialStatus::SLIP};
      const Eigen::Vector3d x(x_nu, 0.03, -0.04);
      const NodeRows at = status_rows(n, x, st, false, 0, h, true);
      for (int j = 0; j < 3; ++j) {
        Eigen::Vector3d xp = x, xm = x;
        xp[j] += h, xm[j] -= h;
        const Eigen::Vector3d fd =
            (status_rows(n, xp, st, false, 0, h, true).force - status_rows(n, xm, st, false, 0, h, true).force) /
            (2 * h);
        for (int i = 0; i < 3; ++i) {
          if (at.is_pinned(i)) continue;  // a pinned row is the pin, not a force balance
          // contact pins x_ν: its column's coupling is not in the block (x_ν does not move)
          if (j == 0 && ns == NormalStatus::CONTACT) continue;
          EXPECT_NEAR(at.block(i, j), fd[i], 1e-6 * (1 + std::abs(fd[i]))) << "x_nu " << x_nu << " row " << i << " col " << j;
        }
      }
    }
  }
}

// ssn's reading of a node: contact where the foundation pushes, stick inside the cone.
TEST(StatusEquations, SsnReadsContactAndStickFromTheComplementarityFunctions) {
  SolveOptions opt;
  const Model md = model_of("sofonea2017-3d.json", {"mesh.n=2"}, opt);
  const NodeData n = node_data(md, 0);
  const Eigen::Vector3d diag(1, 1, 1);
  // At g with a residual that presses (r_ν + w p < 0): contact, pinned at g.
  const SsnReading pressed = ssn_reading(n, Eigen::Vector3d(n.g, 0, 0), Eigen::Vector3d(-1e3, 0, 0), diag, false, false, 0);
  EXPECT_TRUE(pressed.code & 1);
  EXPECT_TRUE(pressed.rows.is_pinned(0));
  EXPECT_DOUBLE_EQ(pressed.rows.pin[0], n.g);
  // Below the layer's top with no load: not contact, and λ = F_b(0) = 0: no tangential rows.
  const SsnReading free = ssn_reading(n, Eigen::Vector3d(-0.01, 0, 0), Eigen::Vector3d::Zero(), diag, false, false, 0);
  EXPECT_FALSE(free.code & 1);
  EXPECT_FALSE(free.rows.is_pinned(1));
  // In the layer (λ > 0) with a small tangential residual: stick, both tangents pinned at 0.
  const SsnReading stick = ssn_reading(n, Eigen::Vector3d(0.05, 0, 0), Eigen::Vector3d(0, 1e-9, 0), diag, false, false, 0);
  EXPECT_TRUE(stick.code & 2);
  EXPECT_TRUE(stick.rows.is_pinned(1) && stick.rows.is_pinned(2));
}

// ssn against the condensed exact solver (the default), which solves the same discrete problem:
// both answers are exact up to their solves' round-off (κ(K) ε_mach), so the Γ3 displacements
// agree to 1e-10 U and the statuses exactly; both certified.
void expect_same_as_condensed(const std::string& file, const std::vector<std::string>& sets) {
  SolveOptions opt;
  const Model md = model_of(file, sets, opt);
  const Solution ref = solve(md, opt);
  SolveOptions o = opt;
  o.backend = SSN_BACKEND;
  const Solution s = solve(md, o);
  ASSERT_TRUE(ref.certificate.passed) << ref.message;
  ASSERT_TRUE(s.certificate.passed) << s.message;
  EXPECT_TRUE(s.backend_ok) << s.message;
  EXPECT_EQ(s.formulation, "full");
  EXPECT_EQ(s.solved_by(), "ssn (semismooth Newton, CHOLMOD)");
  const double U = ref.certificate.length_scale;
  for (Index k = 0; k < md.contact.size(); ++k) {
    EXPECT_EQ(s.status[static_cast<size_t>(k)].str(), ref.status[static_cast<size_t>(k)].str()) << k;
    const int v = md.contact.node[static_cast<size_t>(k)];
    for (int c = 0; c < md.dim(); ++c) EXPECT_NEAR(s.u[md.dim() * v + c], ref.u[md.dim() * v + c], 1e-10 * U) << k;
  }
  EXPECT_NEAR(s.energy, ref.energy, 1e-12 * std::abs(ref.energy));
}

TEST(Ssn, SameAnswerAsTheCondensedExactSolverIn2D) {
  expect_same_as_condensed("sofonea2017-fig2.json", {"mesh.n=16"});
  expect_same_as_condensed("sofonea2017-printed.json", {"mesh.n=16"});
}

TEST(Ssn, SameAnswerAsTheCondensedExactSolverIn3D) { expect_same_as_condensed("sofonea2017-3d.json", {"mesh.n=6"}); }

// A long strip (many Γ3 nodes against few interior ones: where the dense condensed path is slow)
// with the paper's law.
TEST(Ssn, SameAnswerOnALongStrip) {
  expect_same_as_condensed("sofonea2017-fig2.json", {"mesh.n=null", "mesh.x=[0,40]", "mesh.nx=80", "mesh.ny=2"});
}

// ssn's own record: converged in a few steps, the last ones without a status change, and a start
// at the answer converges at once (no step).
TEST(Ssn, StopsAtTheAnswerAndFromIt) {
  const auto [md, lim, a] = ssn_from_zero("sofonea2017-fig2.json", {"mesh.n=16"});
  ASSERT_TRUE(a.converged) << a.message;
  EXPECT_LE(a.steps, 12);
  EXPECT_EQ(a.record.back().at("status_changes"), 0);
  const SsnOutcome b = ssn_full(md, lim, &a.x);
  ASSERT_TRUE(b.converged) << b.message;
  EXPECT_LE(b.steps, 1);  // step 1 reads the statuses (all new to it) and confirms them
  EXPECT_LE((b.x - a.x).cwiseAbs().maxCoeff(), 1e-12 * a.x.cwiseAbs().maxCoeff());
}

// On statuses that hold, the conditions are linear and one Newton step is exact, pinned unknowns
// included: their prescribed steps enter the free rows through J's coupling, which the stored
// lower triangle holds once for both sides (a free row above a pinned column is an entry of the
// pinned row). From the answer moved by 1e-7 of its size in every unknown (contact nodes off g,
// every status kept), step 1 lands on the answer and the next reading confirms it with no step.
// (Without the upper side's term: two steps here, and 11 instead of 7 from zero on fig2 n = 8.)
TEST(Ssn, OneStepIsExactOnStatusesThatHold) {
  const auto [md, lim, a] = ssn_from_zero("sofonea2017-frictionless.json", {"mesh.n=8"});
  ASSERT_TRUE(a.converged) << a.message;
  const double size = a.x.cwiseAbs().maxCoeff();
  Vec x0 = a.x;
  for (Index i = 0; i < x0.size(); ++i) x0[i] += 1e-7 * size * std::sin(1.0 + static_cast<double>(i));
  const SsnOutcome b = ssn_full(md, lim, &x0);
  ASSERT_TRUE(b.converged) << b.message;
  EXPECT_EQ(b.steps, 1);
  EXPECT_LE((b.x - a.x).cwiseAbs().maxCoeff(), 1e-12 * size);
}

// A nonlinear material has no K_x to be the Newton matrix: refused, naming the fix.
// Where ssn cannot certify (a softening branch of p_ν steeper than the body: its Newton matrix is
// not positive definite), the engine's default backend takes over from the same start: the answer
// is certified and is exactly what that backend named alone gives, and it says that ssn ran first.
// Random scene 57 (studies/random_scenes.hpp, n in [4, 6]); 148 of the 1000 random scenes hand
// over (122 this way), and ssn named certifies 999 of them (docs/random-study.md).
TEST(Ssn, HandsOverToTheDefaultBackendWhereItCannotCertify) {
  const stress::RandomScene rs = stress::draw_scene(57, 4, 6);
  SCOPED_TRACE(rs.command());
  std::vector<std::string> sets = rs.overrides;
  sets.push_back("solver.backend=\"ssn\"");
  SolveOptions opt;
  const Model md = model_of("sofonea2017-fig2.json", sets, opt);
  const Solution s = solve(md, opt);
  ASSERT_TRUE(s.ok()) << s.message;
  EXPECT_EQ(s.message.rfind("ssn did not certify (ssn: the Newton matrix", 0), 0u) << s.message;
  ASSERT_FALSE(s.history.empty());
  EXPECT_EQ(s.history.front().solver, "ssn (semismooth Newton, CHOLMOD)");
  EXPECT_EQ(s.backend_use.requested, "ssn");
  opt.backend = s.backend;  // the default backend named alone, from zero
  const Solution named = solve(md, opt);
  ASSERT_TRUE(named.ok());
  EXPECT_EQ(s.solved_by(), named.solved_by());
  EXPECT_NEAR(s.energy, named.energy, 1e-12 * std::abs(named.energy));
}

TEST(Ssn, RefusesANonlinearMaterialAndTheCondensedFormulation) {
  SolveOptions opt;
  const Model md = model_of("sofonea2017-fig2.json", {"mesh.n=4"}, opt);
  SolveOptions o = opt;
  o.backend = SSN_BACKEND;
  o.formulation = "condensed";
  try {
    solve(md, o);
    FAIL() << "ssn with the condensed formulation was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("runs in the full space"), std::string::npos) << e.what();
  }
}
// The globalization's rules (solver/ssn.hpp). The cycle watch turns on at a signature seen in the
// SSN_CYCLE_MEMORY steps before (not further back), only on a step whose statuses changed, and stays on.
TEST(SsnGlobalization, CycleWatchTurnsOnAtARepeatedSignatureOnly) {
  const uint64_t A = ssn_node_signature(0, 1), B = ssn_node_signature(0, 2), C = ssn_node_signature(1, 1),
                 D = ssn_node_signature(1, 2);
  EXPECT_NE(A, B);
  EXPECT_NE(A, C);  // the node counts, not only its code
  SsnCycleWatch far;  // A comes back 4 steps later: beyond the memory
  for (const uint64_t s : {A, B, C, D, A}) far.see(s, 5);
  EXPECT_FALSE(far.cycling());
  SsnCycleWatch held;  // the same statuses again without a change: converging, not cycling
  for (const uint64_t s : {A, B, B, B}) held.see(s, s == A ? 5 : 0);
  EXPECT_FALSE(held.cycling());
  SsnCycleWatch two;  // period 2
  for (const uint64_t s : {A, B, A}) two.see(s, 3);
  EXPECT_TRUE(two.cycling());
  two.see(C, 1), two.see(D, 1);
  EXPECT_TRUE(two.cycling());  // and stays on
  SsnCycleWatch three;  // period 3, within the memory
  for (const uint64_t s : {A, B, C, A}) three.see(s, 2);
  EXPECT_TRUE(three.cycling());
}

// Backtracking: the first θ = 1, ½, ¼, … with sufficient decrease; the shortest where none has it.
TEST(SsnGlobalization, StepLengthIsTheFirstWithSufficientDecrease) {
  // merit(θ) = 1 + 10 θ (θ − 0.3): 8 at 1, 2 at ½, 0.875 at ¼.
  EXPECT_EQ(ssn_step_length(1.0, [](double t) { return 1 + 10 * t * (t - 0.3); }), 0.25);
  EXPECT_EQ(ssn_step_length(1.0, [](double t) { return 1 - 0.5 * t; }), 1.0);
  EXPECT_EQ(ssn_step_length(1.0, [](double) { return 2.0; }), std::ldexp(1.0, -SSN_HALVINGS));
  // Armijo's margin: a decrease by less than SSN_ARMIJO θ of the merit is not enough.
  EXPECT_EQ(ssn_step_length(1.0, [](double t) { return 1 - 0.5 * SSN_ARMIJO * t; }), std::ldexp(1.0, -SSN_HALVINGS));
}

// The coupling column is the derivative of the slip force w F_b(x_ν) t in x_ν (central difference
// with a step far below F_b's branch widths: exact up to round-off), zero where x_ν is pinned, and
// the node merit is zero at a node in equilibrium with its statuses.
TEST(StatusEquations, CouplingIsTheSlipForcesDerivativeInXnu) {
  SolveOptions opt;
  const Model md = model_of("sofonea2017-3d.json", {"mesh.n=2"}, opt);
  const NodeData n = node_data(md, 0);
  const Eigen::Vector3d diag(1e3, 1e3, 1e3), r(1e6, -40.0, 30.0);  // pushed off g, sliding along (40, −30)/50
  const double h = 1e-7;
  for (const double x_nu : {0.05, 0.12, 0.2}) {  // the three branches of p_ν (32), F_b = μ p_ν
    const Eigen::Vector3d x(x_nu, 0.0, 0.0);
    const SsnReading rd = ssn_reading(n, x, r, diag, false, false, 0);
    ASSERT_GT(rd.slip_dir.squaredNorm(), 0.0) << x_nu;
    ASSERT_FALSE(rd.rows.is_pinned(0)) << x_nu;
    const Eigen::Vector3d col = ssn_coupling(n, x, rd, h);
    const SsnReading up = ssn_reading(n, x + Eigen::Vector3d(h, 0, 0), r, diag, false, false, 0);
    const SsnReading down = ssn_reading(n, x - Eigen::Vector3d(h, 0, 0), r, diag, false, false, 0);
    EXPECT_EQ(col[0], 0.0);
    const double scale = col.norm();
    ASSERT_GT(scale, 0.0) << x_nu;
    for (int c = 1; c < 3; ++c)
      EXPECT_NEAR(col[c], (up.rows.force[c] - down.rows.force[c]) / (2 * h), 1e-6 * scale) << x_nu << " " << c;
  }
  // At g (contact: x_ν pinned) the column is zero: the step of x_ν is prescribed there.
  const Eigen::Vector3d at_g(n.g, 0.0, 0.0), pushed(-1e6, -40.0, 30.0);
  const SsnReading contact = ssn_reading(n, at_g, pushed, diag, false, false, 0);
  ASSERT_TRUE(contact.rows.is_pinned(0));
  EXPECT_EQ(ssn_coupling(n, at_g, contact, h).norm(), 0.0);
  // A node whose forces balance its statuses' rows has merit 0, and an imbalance of 5 on its
  // normal row makes it 5: r_ν = −w p(x_ν), and r_τ = −w λ t on the stick limit (|y| = wλ: stick).
  const Eigen::Vector3d x(0.12, 0.0, 0.0);
  const double wp = n.w * n.normal_law->p(x[0]), wl = n.w * n.friction->F(x[0]);
  const Eigen::Vector3d balanced(-wp, -0.8 * wl, 0.6 * wl);
  ASSERT_FALSE(ssn_reading(n, x, balanced, diag, false, false, 0).rows.is_pinned(0));
  EXPECT_NEAR(ssn_node_merit(n, x, balanced, diag, 0, 1.0), 0.0, 1e-12 * (std::abs(wp) + wl));
  EXPECT_NEAR(ssn_node_merit(n, x, balanced + Eigen::Vector3d(5, 0, 0), diag, 0, 1.0), 5.0, 1e-9);
}

// Random scene 152 (the default-settings study's, n in [8, 16]): plain ssn's statuses cycled there
// for ever (slip reversals of neighbouring nodes taking turns, then a node switching between
// separated and sliding). The globalization switches on, and ssn certifies it at the condensed
// exact solver's answer. On the paper's scene no signature comes back: every step is plain.
TEST(SsnGlobalization, CertifiesTheRandomSceneWhoseStatusesCycled) {
  const stress::RandomScene rs = stress::draw_default_scene(152, 8, 16);
  SCOPED_TRACE(rs.command());
  SolveOptions opt;
  const Model md = model_of("sofonea2017-fig2.json", rs.overrides, opt);
  const SsnOutcome a = ssn_full(md, {opt.ssn.max_iters, opt.ssn.tol, opt.petsc.ksp_rtol}, nullptr);
  ASSERT_TRUE(a.converged) << a.message;
  bool coupled = false;
  for (const auto& step : a.record) coupled = coupled || step.at("coupled_nodes").get<long>() > 0;
  EXPECT_TRUE(coupled);
  SolveOptions o = opt;
  o.backend = SSN_BACKEND;
  const Solution s = solve(md, o);
  ASSERT_TRUE(s.certificate.passed) << s.message;
  EXPECT_EQ(s.solved_by(), "ssn (semismooth Newton, CHOLMOD)");
  const Solution ref = solve(md, opt);  // the default: condensed, the exact solver
  ASSERT_TRUE(ref.certificate.passed) << ref.message;
  EXPECT_NEAR(s.energy, ref.energy, 1e-12 * std::abs(ref.energy));
  const auto [paper_md, lim, plain] = ssn_from_zero("sofonea2017-fig2.json", {"mesh.n=16"});
  ASSERT_TRUE(plain.converged) << plain.message;
  for (const auto& step : plain.record) {
    EXPECT_EQ(step.at("theta").get<double>(), 1.0);
    EXPECT_EQ(step.at("coupled_nodes").get<long>(), 0);
  }
}

}  // namespace
}  // namespace hemicontact
