#include <hemicontact/check/judge.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace hemicontact {

namespace {

const char* const RESIDUAL_NAMES[] = {"feasibility",    "normal",         "complementarity",
                                      "friction_cone",  "slip_direction", "equilibrium"};
constexpr int EQUILIBRIUM = NODE_TERMS;  // the residual after the node terms

// Keep the larger value and its place; a NaN reads as +∞ (a failure, never a pass).
void take(CertificateResidual& c, double v, Index at) {
  if (v > c.value || std::isnan(v)) {
    c.value = std::isnan(v) ? INF : v;
    c.worst = at;
  }
}

}  // namespace

JudgeScope whole_model_scope(const Model& md) {
  JudgeScope s;
  s.nodes.resize(static_cast<size_t>(md.contact.size()));
  for (Index k = 0; k < md.contact.size(); ++k) s.nodes[static_cast<size_t>(k)] = k;
  s.owns = [](Index) { return true; };
  s.node_at = [](Index k) { return k; };
  s.dof_at = [](Index c) { return c; };
  return s;
}

void combine(ScaleParts& into, const ScaleParts& o) {
  into.u_max = std::max(into.u_max, o.u_max);
  into.f_max = std::max(into.f_max, o.f_max);
  into.h_max = std::max(into.h_max, o.h_max);
  into.w_sum += o.w_sum;
  into.count += o.count;
  into.traction_max = std::max(into.traction_max, o.traction_max);
}

void combine(VerdictParts& into, const VerdictParts& o) {
  for (size_t i = 0; i < into.residuals.size(); ++i) {
    CertificateResidual& a = into.residuals[i];
    const CertificateResidual& b = o.residuals[i];
    if (b.value > a.value || (b.value == a.value && b.worst < a.worst)) a.value = b.value, a.worst = b.worst;
  }
  into.j += o.j;
  into.friction += o.friction;
  into.u_nu_max = std::max(into.u_nu_max, o.u_nu_max);
  for (size_t i = 0; i < into.counts.size(); ++i) into.counts[i] += o.counts[i];
}

ScaleParts scale_parts(const Model& md, const Vec& u, const ContactState& state, const JudgeScope& scope) {
  ScaleParts p;
  const int d = md.dim();
  for (Index v = 0; v < md.mesh.num_nodes(); ++v)
    if (scope.owns(v))
      for (int c = 0; c < d; ++c) {
        p.u_max = std::max(p.u_max, std::abs(u[d * v + c]));
        p.f_max = std::max(p.f_max, std::abs(md.f[d * v + c]));
      }
  // The mesh size is U only where u = 0 (judge_scales): a rank whose u is not zero makes the
  // merged u_max nonzero, so its h_max is never read, and the edge walk (every evaluation, 1 % of
  // a small solve) is skipped.
  if (p.u_max == 0) p.h_max = md.mesh.max_edge_length();
  for (Index k : scope.nodes) {
    p.w_sum += md.contact.w[k];
    p.count += 1;
    p.traction_max = std::max({p.traction_max, std::abs(state.lambda[k]), std::abs(state.xi[k])});
  }
  return p;
}

JudgeScales judge_scales(const ScaleParts& all, CertificateReport& r) {
  // U: the displacement scale, the mesh size where u = 0 (a length either way).
  r.length_scale = all.u_max > 0 ? all.u_max : all.h_max;
  r.force_scale = all.f_max;
  const double wbar = all.count > 0 ? all.w_sum / all.count : 1.0;
  r.traction_scale = r.force_scale / wbar;
  if (all.count > 0) r.traction_scale = std::max(r.traction_scale, all.traction_max);
  // A problem without any load or contact force has the zero solution; any positive scale works.
  if (!(r.force_scale > 0)) r.force_scale = 1.0;
  if (!(r.traction_scale > 0)) r.traction_scale = 1.0;
  return JudgeScales{r.length_scale, r.force_scale, r.traction_scale};
}

std::vector<NodeStatus> node_statuses(const Model& md, const ContactState& state, const JudgeScales& sc,
                                      double status_tol) {
  std::vector<NodeStatus> out(static_cast<size_t>(md.contact.size()));
  for (Index k = 0; k < md.contact.size(); ++k)
    out[static_cast<size_t>(k)] = node_status(node_data(md, k), load_node(state, k), sc, status_tol);
  return out;
}

VerdictParts verdict_parts(const Model& md, const ContactState& state, const std::vector<NodeStatus>& status,
                           const JudgeScales& sc, double status_tol, const JudgeScope& scope) {
  VerdictParts p;
  for (const char* name : RESIDUAL_NAMES) p.residuals.push_back(CertificateResidual{name});
  for (Index k : scope.nodes) {
    const NodeData n = node_data(md, k);
    const NodeState s = load_node(state, k);
    const auto terms = node_terms(n, s, sc, status_tol);
    for (int i = 0; i < NODE_TERMS; ++i) take(p.residuals[static_cast<size_t>(i)], terms[static_cast<size_t>(i)], scope.node_at(k));
    const NodeEnergy e = node_energy(n, s);
    p.j += e.j;
    p.friction += e.friction;
    p.u_nu_max = std::max(p.u_nu_max, s.u_nu);
    count_status(p.counts, status[static_cast<size_t>(k)]);
  }
  // Interior equilibrium: the free components that are not Γ3 unknowns (nor clamped, nor held by
  // a roller: those are the reduced system's interior unknowns).
  const int d = md.dim();
  const std::vector<Index> sel = md.dofs.cartesian_selection();
  for (Index v = 0; v < md.mesh.num_nodes(); ++v)
    if (scope.owns(v))
      for (int i = 0; i < d; ++i) {
        const Index c = d * v + i, x = sel[static_cast<size_t>(c)];
        if (x >= 0 && x < md.dofs.n_interior()) take(p.residuals[EQUILIBRIUM], std::abs(state.residual[c]) / sc.F, scope.dof_at(c));
      }
  return p;
}

void close_certificate(const VerdictParts& all, double tol, CertificateReport& r) {
  r.tol = tol;
  r.residuals = all.residuals;
  r.max_residual = 0;
  for (const auto& c : r.residuals) r.max_residual = std::max(r.max_residual, c.value);
  r.passed = r.max_residual <= tol;
}

Judgement judge(const Model& md, const Vec& u, const ContactState& state, const JudgeScope& scope,
                const Reduction& reduce, double tol, double status_tol) {
  Judgement J;
  ScaleParts sp = scale_parts(md, u, state, scope);
  reduce.reduce(sp);
  const JudgeScales sc = judge_scales(sp, J.certificate);
  J.status = node_statuses(md, state, sc, status_tol);
  VerdictParts vp = verdict_parts(md, state, J.status, sc, status_tol, scope);
  reduce.reduce(vp);
  close_certificate(vp, tol, J.certificate);
  J.j_term = vp.j;
  J.friction_term = vp.friction;
  J.max_u_nu = std::isfinite(vp.u_nu_max) ? vp.u_nu_max : 0.0;
  J.counts = vp.counts;
  return J;
}

}  // namespace hemicontact
