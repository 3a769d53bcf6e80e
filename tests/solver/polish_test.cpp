// The exact polish on its own (solver/polish.hpp): handed a smoothed answer whose statuses are
// right but whose values carry the smoothing error, it solves the unsmoothed status system and
// returns the exact discrete solution (certificate at round-off, the answer of the full pipeline);
// handed a candidate it cannot improve, it leaves x_C untouched and says why. 2D (λ iteration on
// the linear status system) and 3D (Newton on the nonlinear slip condition).
#include <hemicontact/check/evaluate.hpp>
#include <hemicontact/fem/condensation.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/polish.hpp>
#include <hemicontact/solver/solve.hpp>

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace hemicontact {
namespace {

struct Case {
  Model md;
  SolveOptions opt;
};

Case load_case(const std::string& scene, const std::vector<std::string>& overrides) {
  const nlohmann::json s = load_scene(HEMICONTACT_SOURCE_DIR "/problems/" + scene + ".json", overrides);
  Case c{build_model(s, "."), {}};
  c.opt = solve_options_from_scene(s);
  return c;
}

/// The Γ3 unknowns x_C (condensed order: d per Γ3 node) of a reduced vector x.
Vec gamma3_of(const Condensation& cond, const Vec& x) { return x.tail(cond.m()); }

Solution evaluate(const Case& c, const Condensation& cond, const Vec& x_C) {
  Solution s;
  s.x = cond.recover(x_C);
  s.u = c.md.dofs.to_full(s.x);
  evaluate_solution(c.md, c.opt, s);
  return s;
}

// A smoothed answer stopped at ε = @p eps·U (polish off) misses the certificate by the smoothing
// error; the polish alone makes it the exact solution that the default pipeline returns. The mesh
// is perturbed (10 % of h): on the symmetric meshes the sticking centre node has u_τ = 0 exactly
// and no node sits in a smoothing window, so the smoothed answer would already be exact.
void check_polish_recovers_exact_solution(const std::string& scene, const std::string& n, const std::string& eps) {
  const std::vector<std::string> mesh = {"mesh.n=" + n, "mesh.perturb=0.1"};
  const Case exact = load_case(scene, mesh);
  const Solution reference = solve(exact.md, exact.opt);
  ASSERT_TRUE(reference.ok()) << reference.message;

  std::vector<std::string> smoothed = mesh;
  // The continuation alone (solver.exact.enabled=false): the exact inner solver would hand back
  // an exact answer, and this test needs the smoothed one as the polish's input.
  smoothed.insert(smoothed.end(), {"solver.polish=false", "solver.eps_tau=" + eps, "solver.eps_nu=" + eps,
                                   "solver.continuation.eps_start=1e-2", "solver.exact.enabled=false"});
  const Case smooth = load_case(scene, smoothed);
  const Solution rough = solve(smooth.md, smooth.opt);
  ASSERT_GT(rough.certificate.max_residual, 1e-9) << "the smoothed answer is already exact: no test";

  const Index d = exact.md.dim(), nc = exact.md.contact.size();
  const Condensation cond(exact.md.Kx.lower(), exact.md.fx, d * nc);
  Vec x_C = gamma3_of(cond, rough.x);
  const PolishResult r = polish_condensed(exact.md, cond, exact.opt, x_C);
  EXPECT_TRUE(r.attempted);
  EXPECT_TRUE(r.accepted) << r.note;
  EXPECT_GE(r.iterations, 1);
  EXPECT_DOUBLE_EQ(r.before, rough.certificate.max_residual);
  EXPECT_LT(r.after, 1e-12);

  const Solution polished = evaluate(exact, cond, x_C);
  EXPECT_EQ(polished.certificate.max_residual, r.after);
  ASSERT_EQ(polished.status.size(), reference.status.size());
  for (size_t k = 0; k < polished.status.size(); ++k) EXPECT_EQ(polished.status[k].str(), reference.status[k].str());
  // Both solve the same linear (2D) / Newton-converged (3D) status system: they agree to its round-off.
  const double U = reference.u.cwiseAbs().maxCoeff();
  EXPECT_LE((polished.u - reference.u).cwiseAbs().maxCoeff(), 1e-10 * U);
}

TEST(Polish, RecoversTheExactSolutionFromASmoothedOne2D) {
  check_polish_recovers_exact_solution("sofonea2017-fig2", "16", "1e-3");
}

TEST(Polish, RecoversTheExactSolutionFromASmoothedOne3D) {
  check_polish_recovers_exact_solution("sofonea2017-3d", "4", "1e-2");
}

// An exact answer is kept as it is (a tie at round-off goes to the polish, which changes nothing
// measurable). A candidate far from the solution — every node 3 g below the layer and sliding the
// wrong way, so every status is wrong — is changed only to what the active-set rounds find, and
// only because its certificate is lower: the contract of accept_if_better, not a promise of the
// solution (that is the continuation's job).
TEST(Polish, KeepsExactAnswersAndOnlyAcceptsImprovements) {
  const Case c = load_case("sofonea2017-fig2", {"mesh.n=16"});
  const Solution sol = solve(c.md, c.opt);
  ASSERT_TRUE(sol.ok()) << sol.message;
  const Index d = c.md.dim(), nc = c.md.contact.size();
  const Condensation cond(c.md.Kx.lower(), c.md.fx, d * nc);
  const double U = sol.u.cwiseAbs().maxCoeff();

  Vec x_C = gamma3_of(cond, sol.x);
  const Vec before = x_C;
  const PolishResult kept = polish_condensed(c.md, cond, c.opt, x_C);
  EXPECT_LT(kept.after, 1e-12);
  EXPECT_LE((x_C - before).cwiseAbs().maxCoeff(), 1e-10 * U);

  Vec wrong = Vec::Zero(d * nc);
  for (Index k = 0; k < nc; ++k) {
    wrong[d * k] = -3 * c.md.contact.g[k];
    wrong[d * k + 1] = (k % 2 ? 1 : -1) * c.md.contact.g[k];
  }
  const Vec start = wrong;
  const PolishResult r = polish_condensed(c.md, cond, c.opt, wrong);
  EXPECT_DOUBLE_EQ(r.before, evaluate(c, cond, start).certificate.max_residual);
  if (r.accepted) {
    EXPECT_LT(r.after, r.before);
    EXPECT_EQ(evaluate(c, cond, wrong).certificate.max_residual, r.after);
  } else {
    EXPECT_FALSE(r.note.empty());
    EXPECT_EQ(wrong, start);
  }
}

}  // namespace
}  // namespace hemicontact
