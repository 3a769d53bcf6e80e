// The landscape studies' JSON (studies/study_json.hpp), for the CLI and the Python module alike.
#include <hemicontact/studies/study_json.hpp>

#include <cmath>

namespace hemicontact {

using json = nlohmann::json;

namespace {

json number_or_null(double v) { return std::isfinite(v) ? json(v) : json(); }

json state_json(const PathState& s) {
  return {{"segment", s.segment},
          {"kind", s.kind},
          {"load", s.load},
          {"energy", number_or_null(s.solution.energy)},
          {"reaction", number_or_null(s.reaction)},
          {"mean_u_nu", number_or_null(s.mean_u_nu)},
          {"max_u_nu", number_or_null(s.max_u_nu)},
          {"certificate", number_or_null(s.solution.certificate.max_residual)},
          {"certified", s.solution.certificate.passed},
          {"type", s.second_order.verdict},
          {"lambda_min", number_or_null(s.second_order.lambda_min)},
          {"status_counts", s.solution.status_counts()},
          {"solved_by", s.solution.solved_by()}};
}

json jump_json(const Model& md, const PathReport& R, const PathJump& J) {
  json nodes = json::array();
  const Solution &a = R.states[static_cast<size_t>(J.before)].solution, &b = R.states[static_cast<size_t>(J.after)].solution;
  for (Index k : J.switched) {
    const size_t q = static_cast<size_t>(k);
    json n = {{"index", k}, {"before", a.status[q].str()}, {"after", b.status[q].str()},
              {"u_nu_before", a.state.u_nu[k]}, {"u_nu_after", b.state.u_nu[k]}};
    const char* axes[] = {"x", "y", "z"};
    for (int c = 0; c < md.dim(); ++c) n[axes[c]] = md.mesh.points(md.contact.node[q], c);
    nodes.push_back(n);
  }
  return {{"state_before", J.before},         {"state_after", J.after},   {"load_before", J.load_before},
          {"load_after", J.load_after},       {"energy_before", J.energy_before}, {"energy_after", J.energy_after},
          {"distance", J.distance},           {"direction", J.direction > 0 ? "loading" : "unloading"},
          {"switched", nodes}};
}

}  // namespace

json path_json(const Model& md, const PathReport& R) {
  json states = json::array(), jumps = json::array();
  for (const PathState& s : R.states) states.push_back(state_json(s));
  for (const PathJump& J : R.jumps) jumps.push_back(jump_json(md, R, J));
  const PathOptions& o = R.options;
  return {{"loads", o.loads},
          {"steps", o.steps},
          {"options", {{"bisection_tol", o.bisection_tol}, {"energy_tol", o.energy_tol}, {"jump_factor", o.jump_factor},
                       {"max_events_per_step", o.max_events_per_step}}},
          {"complete", R.complete},
          {"failure", R.failure},
          {"certified_states", R.certified()},
          {"solves", R.solves},
          {"continuous_events", R.continuous_events},
          {"seconds", R.seconds},
          {"states", states},
          {"jumps", jumps}};
}


namespace {

nlohmann::json side_json(const BarrierSide& s) {
  const auto num = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
  return {{"minimum", s.minimum}, {"lambda", s.lambda}, {"neighbours", s.neighbours}, {"verified", s.verified},
          {"intermediate_minima", s.intermediate}, {"saddle_energies", s.saddles},
          {"energy_min", num(s.energy_min)}, {"energy_saddle", num(s.energy_saddle)}, {"barrier", num(s.barrier)},
          {"residual", num(s.residual)}, {"negative_eigenvalues", s.negative}, {"string_steps", s.steps},
          {"profile", s.profile}, {"note", s.note}};
}

}  // namespace

nlohmann::json barrier_json(const Barrier& b) {
  return {{"a", b.a}, {"b", b.b}, {"from_a", side_json(b.from_a)}, {"from_b", side_json(b.from_b)}};
}

nlohmann::json unseen_json(const UnseenEstimate& e, const MinimaOptions& mo) {
  return {{"estimator", "Chao1 (bias-corrected), 95% log-normal interval; samples: certified random-start runs"},
          {"samples", e.samples},
          {"observed", e.observed},
          {"f1", e.f1},
          {"f2", e.f2},
          {"chao1", e.chao1},
          {"interval", {e.lo, e.hi}},
          {"unseen", e.unseen},
          {"random_starts", e.random_starts},
          {"until_complete", mo.until_complete},
          {"max_starts", mo.max_starts},
          {"complete", e.complete}};
}

}  // namespace hemicontact
