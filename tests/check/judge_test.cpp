// The one judge (check/judge.hpp): its reduction over the nodes a process owns gives the whole
// model's verdict, and its status rule reads what a node carries at every stiffness and scale.
#include <hemicontact/check/contact_status.hpp>
#include <hemicontact/check/evaluate.hpp>
#include <hemicontact/check/judge.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/solve.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace hemicontact {
namespace {

struct Solved {
  Model md;
  SolveOptions opt;
  Solution sol;
};

Solved solve_scene(const std::string& file, const std::vector<std::string>& sets) {
  Solved s;
  const nlohmann::json scene = load_scene(std::string(HEMICONTACT_SOURCE_DIR) + "/problems/" + file, sets);
  s.md = build_model(scene, ".");
  s.opt = solve_options_from_scene(scene);
  s.sol = solve(s.md, s.opt);
  return s;
}

// Two "ranks" of one process: the Γ3 nodes and the mesh nodes split at their middles; the serial
// reduction's rule (combine) joins their parts as MPI_Allreduce joins the ranks'.
struct Halves {
  JudgeScope a, b;
  explicit Halves(const Model& md) : a(whole_model_scope(md)), b(whole_model_scope(md)) {
    const Index nc = md.contact.size(), nv = md.mesh.num_nodes();
    a.nodes.assign(a.nodes.begin(), a.nodes.begin() + nc / 2);
    b.nodes.assign(b.nodes.begin() + nc / 2, b.nodes.end());
    a.owns = [nv](Index v) { return v < nv / 2; };
    b.owns = [nv](Index v) { return v >= nv / 2; };
  }
};

Judgement judge_in_halves(const Model& md, const Solution& sol, const SolveOptions& opt) {
  const Halves h(md);
  Judgement J;
  ScaleParts sa = scale_parts(md, sol.u, sol.state, h.a), sb = scale_parts(md, sol.u, sol.state, h.b);
  combine(sa, sb);
  const JudgeScales sc = judge_scales(sa, J.certificate);
  J.status = node_statuses(md, sol.state, sc, opt.status_tol);
  VerdictParts va = verdict_parts(md, sol.state, J.status, sc, opt.status_tol, h.a);
  const VerdictParts vb = verdict_parts(md, sol.state, J.status, sc, opt.status_tol, h.b);
  combine(va, vb);
  close_certificate(va, opt.certificate_tol, J.certificate);
  J.j_term = va.j, J.friction_term = va.friction, J.max_u_nu = va.u_nu_max, J.counts = va.counts;
  return J;
}

// fig2 at n = 8: Γ3 weights h and h/2 (h = 1/8) sum exactly, so the scales and every maximum agree
// bit for bit; the energy sums are added in another order (two halves), which floating point
// addition makes differ by a few ulps at most.
TEST(Judge, TwoHalvesGiveTheWholeModelsVerdict) {
  const Solved s = solve_scene("sofonea2017-fig2.json", {"mesh.n=8"});
  ASSERT_TRUE(s.sol.certificate.passed);
  const Judgement whole = judge(s.md, s.sol.u, s.sol.state, whole_model_scope(s.md), SerialReduction{},
                                s.opt.certificate_tol, s.opt.status_tol);
  const Judgement split = judge_in_halves(s.md, s.sol, s.opt);
  EXPECT_EQ(split.certificate.length_scale, whole.certificate.length_scale);
  EXPECT_EQ(split.certificate.traction_scale, whole.certificate.traction_scale);
  ASSERT_EQ(split.certificate.residuals.size(), 6u);
  for (size_t i = 0; i < 6; ++i) {
    EXPECT_EQ(split.certificate.residuals[i].value, whole.certificate.residuals[i].value) << i;
    EXPECT_EQ(split.certificate.residuals[i].worst, whole.certificate.residuals[i].worst) << i;
  }
  EXPECT_EQ(split.certificate.max_residual, whole.certificate.max_residual);
  for (size_t k = 0; k < whole.status.size(); ++k) EXPECT_EQ(split.status[k].str(), whole.status[k].str()) << k;
  EXPECT_EQ(split.counts, whole.counts);
  EXPECT_EQ(split.max_u_nu, whole.max_u_nu);
  const double ulp = std::numeric_limits<double>::epsilon();
  EXPECT_NEAR(split.j_term, whole.j_term, 8 * ulp * std::abs(whole.j_term));
  EXPECT_NEAR(split.friction_term, whole.friction_term, 8 * ulp * std::abs(whole.friction_term));
  // And the solve's own record is this judgement.
  EXPECT_EQ(s.sol.certificate.max_residual, whole.certificate.max_residual);
  EXPECT_EQ(s.sol.status_counts(), count_map(whole.counts));
}

// The same in 3D, where the weights (a third of facet areas) need not sum exactly: the scales and
// residuals then agree to round-off, the statuses and counts exactly.
TEST(Judge, TwoHalvesIn3D) {
  const Solved s = solve_scene("sofonea2017-3d.json", {"mesh.n=4"});
  const Judgement whole = judge(s.md, s.sol.u, s.sol.state, whole_model_scope(s.md), SerialReduction{},
                                s.opt.certificate_tol, s.opt.status_tol);
  const Judgement split = judge_in_halves(s.md, s.sol, s.opt);
  const double tol = 64 * std::numeric_limits<double>::epsilon();
  EXPECT_NEAR(split.certificate.max_residual, whole.certificate.max_residual, tol);
  EXPECT_EQ(split.certificate.passed, whole.certificate.passed);
  EXPECT_EQ(split.counts, whole.counts);
  EXPECT_NEAR(split.j_term, whole.j_term, tol * std::abs(whole.j_term));
}

// What each label claims of the node, checked on the node's own numbers with the judge's
// tolerances (t = tol·U a length, s = tol·S a traction, docs/model.md §3):
//   separated  — the layer is not compressed and carries nothing: u_ν ≤ t, ξ ≤ s, |σ_ν| ≤ s;
//   compliance — the layer carries the node below the foundation: u_ν < g − t or g ≤ t, and
//                u_ν > t or ξ > s;
//   contact    — the foundation is reached: u_ν ≥ g − t.
void expect_labels_agree(const Solved& s, const std::string& what) {
  const CertificateReport& c = s.sol.certificate;
  const double t = s.opt.status_tol * c.length_scale, tr = s.opt.status_tol * c.traction_scale;
  const ContactState& st = s.sol.state;
  for (Index k = 0; k < s.md.contact.size(); ++k) {
    const double un = st.u_nu[k], xi = st.xi[k], sn = st.sigma_nu[k], g = s.md.contact.g[k];
    const NodeStatus& a = s.sol.status[static_cast<size_t>(k)];
    const std::string at = what + ", node " + std::to_string(k) + " " + a.str() + " u_nu " + std::to_string(un) +
                           " xi " + std::to_string(xi) + " sigma_nu " + std::to_string(sn);
    if (a.normal == NormalStatus::SEPARATED) {
      EXPECT_LE(un, t) << at;
      EXPECT_LE(xi, tr) << at;
      EXPECT_LE(std::abs(sn), tr) << at;
    } else if (a.normal == NormalStatus::COMPLIANCE) {
      EXPECT_TRUE(un < g - t || g <= t) << at;
      EXPECT_TRUE(un > t || xi > tr) << at;
    } else {
      EXPECT_GE(un, g - t) << at;
    }
    // And the converse: a node the layer carries below the foundation is labelled compliance.
    if (un < g - t && (un > t || xi > tr)) EXPECT_EQ(a.normal, NormalStatus::COMPLIANCE) << at;
  }
}

// The stiff layer of the issue: at c1 = 1e12 every node once read "separated" while σ_ν = −2090
// and λ = 418 (u_ν ~ 1e-9, below t = 1e-8 U). Over c1 = 1e2 .. 1e14 the labels must say what the
// nodes carry: compliance wherever the layer pushes back.
TEST(Judge, StatusesReadWhatTheNodeCarriesAtEveryStiffness) {
  for (const char* c1 : {"1e2", "1e4", "1e6", "1e8", "1e10", "1e12", "1e14"}) {
    const Solved s = solve_scene("sofonea2017-fig2.json", {"mesh.n=8", std::string("contact.normal_law.c1=") + c1});
    ASSERT_TRUE(s.sol.certificate.passed) << c1;
    expect_labels_agree(s, std::string("c1 = ") + c1);
    if (std::stod(c1) >= 1e10) {
      // u_ν ~ σ/c1 is below t here: the old rule (by u_ν alone) read every node "separated".
      EXPECT_GT(s.sol.status_counts().at("compliance"), 0) << c1;
    }
  }
}

// Scales: the gap far below and far above the displacements, a stiff and a soft body.
TEST(Judge, StatusesReadWhatTheNodeCarriesAtEveryScale) {
  for (const char* g : {"1e-9", "1e-3", "0.15", "1e3"})
    for (const char* E : {"2", "2000", "2e9"}) {
      const Solved s = solve_scene("sofonea2017-fig2.json",
                                   {"mesh.n=8", std::string("contact.gap=") + g, std::string("material.E=") + E});
      const std::string what = std::string("g = ") + g + ", E = " + E;
      ASSERT_TRUE(s.sol.certificate.passed) << what;  // the labels of an uncertified answer mean nothing
      expect_labels_agree(s, what);
    }
}

}  // namespace
}  // namespace hemicontact
