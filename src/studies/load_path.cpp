// A quasi-static load history: steps in the load factor, each from the last state, with events
// bisected and jumps recorded (load_path.hpp).
//
// Nothing here changes the solver: it sets the loads, starts each solve from the previous state
// with the exact solver's local descent, and checks, bisects and records what comes back.

#include <hemicontact/studies/load_path.hpp>

#include <hemicontact/core/clock.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/core/format.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/solver/solve.hpp>
#include <hemicontact/studies/minima.hpp>

#include <algorithm>
#include <cmath>
#include <memory>

namespace hemicontact {

int PathReport::certified() const {
  return static_cast<int>(
      std::count_if(states.begin(), states.end(), [](const PathState& s) { return s.solution.certificate.passed; }));
}

std::vector<int> branch_signature(const Model& md, const Solution& sol) {
  std::vector<int> sig(sol.status.size());
  for (size_t k = 0; k < sol.status.size(); ++k) {
    int piece = 0;
    if (md.normal_law) {
      const auto& b = md.normal_law->breakpoints();
      piece = static_cast<int>(std::upper_bound(b.begin(), b.end(), sol.state.u_nu[static_cast<Index>(k)]) - b.begin());
    }
    const NodeStatus& st = sol.status[k];
    sig[k] = (static_cast<int>(st.normal) * 4 + static_cast<int>(st.tangential)) * 1000 + piece;
  }
  return sig;
}

namespace {

// A state on the way: the load factor and the answer there.
struct Point {
  double t = 0;
  Solution sol;
};

void check_path_options(const PathOptions& p) {
  if (p.loads.size() < 2) input_error("path: --load needs at least two load factors (e.g. 0,2,0)");
  for (size_t i = 0; i < p.loads.size(); ++i) {
    if (!std::isfinite(p.loads[i])) input_error("path: load factors must be finite numbers");
    if (i > 0 && p.loads[i] == p.loads[i - 1])
      input_error("path: neighbouring load factors must differ (" + fmt(p.loads[i], 6) + " twice)");
  }
  if (p.steps < 1) input_error("path: --steps must be >= 1");
  if (!(p.bisection_tol > 0) || !(p.energy_tol > 0) || !(p.jump_factor > 0) || !(p.zero_load_agreement > 0))
    input_error("path: bisection_tol, energy_tol, jump_factor and zero_load_agreement must be > 0");
  if (p.max_events_per_step < 1) input_error("path: max_events_per_step must be >= 1");
}

// One history in progress: the solver, the model at the current factor, the report so far.
class Follower {
 public:
  Follower(const Model& md, const SolveOptions& opt, const PathOptions& popt, PathReport& R)
      : md(md), opt(opt), popt(popt), R(R), loaded(md) {
    SolveOptions o = opt;
    o.exact_start = "always";  // from the previous state at once: no smoothed stage to re-choose
    o.exact_inner.local_descent = true;
    S = std::make_unique<ContactSolver>(md, o);
    if (S->formulation() != "condensed")
      input_error("path: needs the condensed formulation (a linear material; got '" +
                  (S->formulation().empty() ? std::string("linear, no contact") : S->formulation()) +
                  "'): the exact solver's local descent, which follows the branch, works on the condensed "
                  "Gamma3 unknowns");
  }
  bool run();

 private:
  Solution solve_at(double t, const Vec& z);
  Solution solve_from(double t, const Solution& from);
  std::string event(const Point& a, const Point& b) const;
  double predicted_energy(const Point& a, const Point& b) const;
  double distance(const Point& a, const Point& b) const;
  void note_rate(const Point& a, const Point& b);
  void record(int segment, const Point& p, const std::string& kind);
  bool advance(int segment, double t1, Point& cur);
  bool locate(int segment, Point& cur, const Point& far);

  const Model& md;
  const SolveOptions& opt;
  const PathOptions& popt;
  PathReport& R;
  Model loaded;  // md with the loads at the current factor (the solver's certificate reads it)
  std::unique_ptr<ContactSolver> S;
  double rate = 0;  // L: the largest ‖Δu‖_E/Δt of an event-free step so far
  double u_scale = 0;  // the largest ‖u‖_E of a recorded state so far
};

// The answer at factor t from solver unknowns z (the loads set on the one factorization).
Solution Follower::solve_at(double t, const Vec& z) {
  loaded.f = t * md.f;
  loaded.fx = t * md.fx;
  S->set_loads(loaded, t);
  ++R.solves;
  // The path speaks for its solves (a line per state, and why it stops): their own lines, and the
  // warnings of the bisection's probes that the path handles, are shown at the debug level only.
  const LogLevel level = log_level();
  if (level < LogLevel::DEBUG) set_log_level(LogLevel::QUIET);
  Solution s = S->solve(&z);
  set_log_level(level);
  return s;
}

// The answer at factor t from the state @p from. At t = 0 exactly the certificate's scales are the
// state's own forces (no load), which a state reached from a loaded one has only at round-off:
// there the answer from u = 0 stands in for it when the two agree to round-off of the path's
// displacements (PathOptions::zero_load_agreement · the largest ‖u‖_E so far), and the message says so.
Solution Follower::solve_from(double t, const Solution& from) {
  Solution s = solve_at(t, S->to_unknowns(from.x));
  if (t != 0 || s.certificate.passed) return s;
  Solution z = solve_at(0, Vec::Zero(S->size()));
  const Vec d = s.u - z.u;
  const double gap = std::sqrt(std::max(0.0, md.a(d, d)));
  if (!z.certificate.passed || !(gap <= popt.zero_load_agreement * u_scale)) return s;
  z.message = "load factor 0: the certified answer from u = 0, which the branch's own answer (certificate " +
              fmt(s.certificate.max_residual, 3) + " against its round-off forces) equals to " + fmt(gap, 3) +
              " in the energy norm; " + z.message;
  return z;
}

double Follower::distance(const Point& a, const Point& b) const {
  const Vec d = a.sol.u - b.sol.u;
  return std::sqrt(std::max(0.0, md.a(d, d)));
}

// E(t_b) predicted from the branch at a and b (load_path.hpp): dE/dt = −f·u + Σ_k w_k |u_τ,k|
// dF_b(u_ν,k)/dt (the second term: λ = F_b(u_ν) moves with u, so Π is not a potential of (22) when
// friction depends on u_ν), both integrated by the trapezoidal rule: exact on a fixed signature in
// 2D, where u, |u_τ| and F_b(u_ν) are affine in t.
double Follower::predicted_energy(const Point& a, const Point& b) const {
  const ContactState &sa = a.sol.state, &sb = b.sol.state;
  double friction = 0;
  for (Index k = 0; k < md.contact.size(); ++k)
    friction += md.contact.w[k] * 0.5 * (std::abs(sa.u_tau[k]) + std::abs(sb.u_tau[k])) * (sb.lambda[k] - sa.lambda[k]);
  return a.sol.energy - 0.5 * (b.t - a.t) * (md.f.dot(a.sol.u) + md.f.dot(b.sol.u)) + friction;
}

// The event test of a step a → b (load_path.hpp): empty when there is none, else its kind.
std::string Follower::event(const Point& a, const Point& b) const {
  if (!b.sol.certificate.passed || !b.sol.fixed_point_converged) return "not certified";
  if (branch_signature(md, a.sol) != branch_signature(md, b.sol)) return "statuses";
  const double predicted = predicted_energy(a, b);
  const double scale = std::max({std::abs(a.sol.energy), std::abs(b.sol.energy), 0.5 * (a.sol.a_uu + b.sol.a_uu)});
  if (std::abs(b.sol.energy - predicted) > popt.energy_tol * scale) return "energy";
  return "";
}

void Follower::note_rate(const Point& a, const Point& b) {
  if (b.t != a.t) rate = std::max(rate, distance(a, b) / std::abs(b.t - a.t));
}

// Record a state: its second-order check at its own load, its Γ3 summaries, progress.
void Follower::record(int segment, const Point& p, const std::string& kind) {
  PathState s;
  s.segment = segment;
  s.load = p.t;
  s.kind = kind;
  s.solution = p.sol;
  loaded.f = p.t * md.f;
  loaded.fx = p.t * md.fx;
  S->set_loads(loaded, p.t);
  if (p.sol.certificate.passed) s.second_order = second_order_check(*S, loaded, opt, p.sol, popt.second_order);
  const ContactState& st = p.sol.state;
  const Vec& w = md.contact.w;
  if (w.size() > 0) {
    s.reaction = 0.0 - w.dot(st.sigma_nu);  // 0.0 −: no "-0" for an unloaded Γ3
    s.mean_u_nu = w.dot(st.u_nu) / w.sum();
    s.max_u_nu = st.u_nu.maxCoeff();
  }
  u_scale = std::max(u_scale, p.sol.energy_norm);
  R.states.push_back(std::move(s));
  if (popt.on_state) popt.on_state(R.states.back(), static_cast<int>(R.states.size()));
}

// Bisect the event between cur and far (load_path.hpp) down to bisection_tol; record a jump, or
// count a continuous event; cur becomes the state just past the event. False when the state past
// it cannot be certified.
bool Follower::locate(int segment, Point& cur, const Point& far) {
  if (rate == 0) note_rate(cur, far);  // no event-free step yet: this step's own rate
  Point lo = cur;
  double t_hi = far.t;
  while (std::abs(t_hi - lo.t) > popt.bisection_tol) {
    Point mid{0.5 * (lo.t + t_hi), {}};
    mid.sol = solve_from(mid.t, lo.sol);
    if (event(lo, mid).empty()) {
      note_rate(lo, mid);
      lo = std::move(mid);
    } else {
      t_hi = mid.t;
    }
  }
  Point hi{t_hi, solve_from(t_hi, lo.sol)};
  if (!hi.sol.certificate.passed || !hi.sol.fixed_point_converged) {
    R.failure = "not certified at load factor " + fmt(t_hi, 10) + " (from the state at " + fmt(lo.t, 10) +
                ", a step of " + fmt(std::abs(t_hi - lo.t), 3) + "): " + hi.sol.message;
    record(segment, hi, "not certified");
    return false;
  }
  const double d = distance(lo, hi);
  if (d > popt.jump_factor * std::abs(hi.t - lo.t) * rate) {
    PathJump J;
    J.load_before = lo.t, J.load_after = hi.t;
    J.energy_before = lo.sol.energy, J.energy_after = hi.sol.energy;
    J.distance = d;
    J.direction = hi.t > lo.t ? 1 : -1;
    const std::vector<int> a = branch_signature(md, lo.sol), b = branch_signature(md, hi.sol);
    for (size_t k = 0; k < a.size(); ++k)
      if (a[k] != b[k]) J.switched.push_back(static_cast<Index>(k));
    J.before = static_cast<int>(R.states.size());
    record(segment, lo, "before jump");
    J.after = static_cast<int>(R.states.size());
    record(segment, hi, "after jump");
    log_info() << "path: jump at load factor " << fmt(hi.t, 10) << ": energy " << fmt(J.energy_before, 10) << " -> "
               << fmt(J.energy_after, 10) << ", " << J.switched.size() << " node(s) switched";
    R.jumps.push_back(std::move(J));
  } else {
    ++R.continuous_events;
  }
  cur = std::move(hi);
  return true;
}

// One step of the history from cur to t1, bisecting each event on the way; cur ends at t1.
bool Follower::advance(int segment, double t1, Point& cur) {
  for (int events = 0; cur.t != t1; ++events) {
    if (events >= popt.max_events_per_step) {
      R.failure = "more than " + std::to_string(popt.max_events_per_step) + " events in the step to load factor " +
                  fmt(t1, 10) + " (PathOptions::max_events_per_step): take more --steps";
      return false;
    }
    Point far{t1, solve_from(t1, cur.sol)};
    const std::string why = event(cur, far);
    if (why.empty()) {
      note_rate(cur, far);
      cur = std::move(far);
      break;
    }
    log_debug() << "path: event (" << why << ") between load factors " << fmt(cur.t, 10) << " and " << fmt(t1, 10);
    if (!locate(segment, cur, far)) return false;
  }
  record(segment, cur, "step");
  return true;
}

bool Follower::run() {
  const std::vector<double>& L = popt.loads;
  Point cur{L[0], solve_at(L[0], Vec::Zero(S->size()))};  // from the unloaded body
  if (!cur.sol.certificate.passed || !cur.sol.fixed_point_converged) {
    R.failure = "the first state (load factor " + fmt(L[0], 10) + ") is not certified: " + cur.sol.message;
    record(0, cur, "not certified");
    return false;
  }
  record(0, cur, "start");
  for (size_t seg = 0; seg + 1 < L.size(); ++seg)
    for (int i = 1; i <= popt.steps; ++i) {
      const double t1 = i == popt.steps ? L[seg + 1] : L[seg] + (L[seg + 1] - L[seg]) * i / popt.steps;
      if (!advance(static_cast<int>(seg), t1, cur)) return false;
    }
  return true;
}

}  // namespace

PathReport follow_load_path(const Model& md, const SolveOptions& opt, const PathOptions& popt) {
  const auto t0 = clk::now();
  check_path_options(popt);
  PathReport R;
  R.options = popt;
  Follower f(md, opt, R.options, R);
  R.complete = f.run();
  R.seconds = since(t0);
  return R;
}

}  // namespace hemicontact
