#include <hemicontact/solver/ssn.hpp>

#include <hemicontact/check/status_equations.hpp>
#include <hemicontact/core/clock.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/core/format.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/fem/sparse_cholesky.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace hemicontact {

namespace {

// One run: the iterate, the Newton matrix (the lower triangle of K's pattern, its values rewritten
// at each step: J is symmetric, as ssn_reading's blocks are) and
// what one step passes to the next. The steps are the petsc engine's (petsc_ssn.cpp) with
// CHOLMOD for CG + AMG.
struct SsnRun {
  const Model& md;
  SsnLimits lim;
  int d;
  Vec x, R, rhs, diag;
  SpMat J;
  SparseCholesky chol;
  double diag_scale = 1, F_s = 1;
  bool factored = false;     // chol holds a factorization of an earlier step's J
  bool fresh = false;        // this step factorized J
  std::vector<char> pinned;  // per unknown, this step
  Vec pin_step;              // a pinned unknown's prescribed step
  std::vector<int> code, prev_code;
  std::vector<Eigen::Vector2d> slip_dir;
  std::vector<char> hold_stick;
  int unchanged = 0;
  double prev_step = INF;
  bool cold;  // started from zero: the first reading puts every node in contact (ssn_reading)
  // The globalization (ssn.hpp): the cycle watch, this step's node signatures summed, each node's
  // coupling column (ssn_coupling) and, once cycling, the columns this step's Newton matrix takes.
  SsnCycleWatch watch;
  uint64_t signature = 0;
  std::vector<Eigen::Vector3d> coupling_col;
  std::vector<std::pair<Index, Eigen::Vector3d>> coupled;  // (the node's first unknown, its column)

  SsnRun(const Model& m, const SsnLimits& l, const Vec* x0);
  long linearize(int k);
  void add_node(Index q, int k, double slope_probe);
  double right_hand_side();
  bool step(int k, long changed, double res, SsnOutcome& out);
  bool newton_direction(long changed, Vec& dx, int& its);
  bool preconditioned_cg(Vec& dx, int& its) const;
  bool gmres(Vec& dx, int& its) const;
  Vec apply(const Vec& v) const;
  double merit(const Vec& xt) const;
  long stop_reversals(Vec& xt, std::vector<char>* held) const;
};

SsnRun::SsnRun(const Model& m, const SsnLimits& l, const Vec* x0)
    : md(m),
      lim(l),
      d(m.dim()),
      x(x0 ? *x0 : Vec::Zero(m.dofs.n_free())),
      J(m.Kx.lower()),
      chol(l.ordering),
      cold(x0 == nullptr) {
  if (x.size() != md.dofs.n_free()) throw Error("ssn: start vector of the wrong size", EXIT_INTERNAL);
  diag = md.Kx.diagonal();
  // A fixed unknown's row keeps a diagonal of K's own size (the mean K_ii), as in the petsc engine:
  // the matrix's conditioning does not see it as an outlier.
  diag_scale = diag.size() && diag.sum() > 0 ? diag.sum() / static_cast<double>(diag.size()) : 1.0;
  F_s = md.fx.size() && md.fx.cwiseAbs().maxCoeff() > 0 ? md.fx.cwiseAbs().maxCoeff() : 1.0;
  const auto nc = static_cast<size_t>(md.contact.size());
  code.assign(nc, -1);
  prev_code.assign(nc, -2);
  slip_dir.assign(nc, Eigen::Vector2d::Zero());
  hold_stick.assign(nc, 0);
  coupling_col.assign(nc, Eigen::Vector3d::Zero());
  chol.analyze(J);  // once: every step's J has K's pattern
}

// Node q's reading at step k: its forces into R, its block into J, its pinned unknowns, its
// signature and its coupling column (used once the statuses cycle).
void SsnRun::add_node(Index q, int k, double slope_probe) {
  const Index iv = md.dofs.contact_dof(q, 0);
  Eigen::Vector3d xl = Eigen::Vector3d::Zero(), rl = Eigen::Vector3d::Zero(), dl = Eigen::Vector3d::Zero();
  for (int c = 0; c < d; ++c) xl[c] = x[iv + c], rl[c] = R[iv + c], dl[c] = diag[iv + c];
  const auto qs = static_cast<size_t>(q);
  const NodeData nd = node_data(md, q);
  const SsnReading rd = ssn_reading(nd, xl, rl, dl, cold && k == 1, hold_stick[qs] != 0, roller_components(md, q));
  code[qs] = rd.code;
  slip_dir[qs] = rd.slip_dir;
  signature += ssn_node_signature(q, rd.code);
  coupling_col[qs] = ssn_coupling(nd, xl, rd, slope_probe);
  for (int c = 0; c < d; ++c) {
    if (rd.rows.is_pinned(c)) {
      pinned[static_cast<size_t>(iv + c)] = 1;
      pin_step[iv + c] = rd.rows.pin[c] - xl[c];
    } else {
      R[iv + c] += rd.rows.force[c];
    }
    for (int j = 0; j <= c; ++j)  // the lower triangle of the symmetric block
      if (rd.rows.block(c, j) != 0) J.coeffRef(iv + c, iv + j) += rd.rows.block(c, j);
  }
}

// Step k's statuses and linearization at the iterate: R = K x − f plus the Γ3 forces, J = K plus
// the Γ3 blocks. @return the number of status changes.
long SsnRun::linearize(int k) {
  R = md.Kx * x - md.fx;
  const SpMat& K = md.Kx.lower();
  std::copy(K.valuePtr(), K.valuePtr() + K.nonZeros(), J.valuePtr());
  pinned.assign(static_cast<size_t>(x.size()), 0);
  pin_step = Vec::Zero(x.size());
  long changed = 0;
  signature = 0;
  const double slope_probe = SSN_SLOPE_PROBE * (x.size() ? x.cwiseAbs().maxCoeff() : 0.0);
  for (Index q = 0; q < md.contact.size(); ++q) {
    add_node(q, k, slope_probe);
    if (code[static_cast<size_t>(q)] != prev_code[static_cast<size_t>(q)]) ++changed;
  }
  prev_code = code;
  unchanged = changed == 0 ? unchanged + 1 : 0;
  watch.see(signature, changed);
  coupled.clear();
  if (watch.cycling())
    for (Index q = 0; q < md.contact.size(); ++q)
      if (coupling_col[static_cast<size_t>(q)].squaredNorm() > 0)
        coupled.emplace_back(md.dofs.contact_dof(q, 0), coupling_col[static_cast<size_t>(q)]);
  return changed;
}

// ssn's merit at @p xt (ssn.hpp): ‖K xt − f‖∞ off Γ3, each Γ3 node's ssn_node_merit on it.
double SsnRun::merit(const Vec& xt) const {
  Vec Rt = md.Kx * xt - md.fx;
  for (Index q = 0; q < md.contact.size(); ++q) {
    const Index iv = md.dofs.contact_dof(q, 0);
    Eigen::Vector3d xl = Eigen::Vector3d::Zero(), rl = Eigen::Vector3d::Zero(), dl = Eigen::Vector3d::Zero();
    for (int c = 0; c < d; ++c) xl[c] = xt[iv + c], rl[c] = Rt[iv + c], dl[c] = diag[iv + c];
    const double m = ssn_node_merit(node_data(md, q), xl, rl, dl, roller_components(md, q), diag_scale);
    for (int c = 0; c < d; ++c) Rt[iv + c] = c == 0 ? m : 0.0;
  }
  return Rt.size() ? Rt.cwiseAbs().maxCoeff() : 0.0;
}

// rhs = −R on free rows, diag_scale × the prescribed step on pinned ones; the pinned rows and
// columns of J zeroed (their diagonal diag_scale), the columns' part moved to the right-hand side,
// so that J stays symmetric positive definite. An entry (r, c) of the stored lower triangle is
// also (c, r). @return the semismooth residual ‖rhs‖∞.
double SsnRun::right_hand_side() {
  rhs = -R;
  for (Index c = 0; c < J.outerSize(); ++c)
    for (SpMat::InnerIterator it(J, c); it; ++it) {
      const bool pr = pinned[static_cast<size_t>(it.row())] != 0, pc = pinned[static_cast<size_t>(c)] != 0;
      if (!pr && !pc) continue;
      if (it.row() == c) {
        it.valueRef() = diag_scale;
        continue;
      }
      if (pc && !pr) rhs[it.row()] -= it.value() * pin_step[c];
      if (pr && !pc) rhs[c] -= it.value() * pin_step[it.row()];
      it.valueRef() = 0;
    }
  for (Index i = 0; i < x.size(); ++i)
    if (pinned[static_cast<size_t>(i)]) rhs[i] = diag_scale * pin_step[i];
  return rhs.size() ? rhs.cwiseAbs().maxCoeff() : 0.0;
}

// The reversal rule (status_equations.hpp's ssn_reversed) on every sliding node of @p xt; @p held
// (hold_stick, or null for a trial point) gets which reversed. @return how many.
long SsnRun::stop_reversals(Vec& xt, std::vector<char>* held) const {
  long projected = 0;
  for (Index q = 0; q < md.contact.size(); ++q) {
    const auto qs = static_cast<size_t>(q);
    const Index iv = md.dofs.contact_dof(q, 0);
    Eigen::Vector3d xl = Eigen::Vector3d::Zero();
    for (int c = 0; c < d; ++c) xl[c] = xt[iv + c];
    const bool reversed = ssn_reversed(slip_dir[qs], d, xl);
    if (held) (*held)[qs] = reversed;  // one step only
    if (reversed) {
      for (int c = 1; c < d; ++c) xt[iv + c] = 0;
      ++projected;
    }
  }
  return projected;
}

// CG on J dx = rhs preconditioned by the last factorization (of a J with the same statuses, so
// M⁻¹J is near I: a few iterations). @return whether it reached rtol within MAX_ITS.
bool SsnRun::preconditioned_cg(Vec& dx, int& its) const {
  constexpr int MAX_ITS = 20;  // more means the factor no longer fits J: refactorize instead
  dx = Vec::Zero(rhs.size());
  Vec r = rhs, z = chol.solve(r), p = z;
  double rz = r.dot(z);
  const double stop = lim.rtol * rhs.norm();
  for (its = 1; its <= MAX_ITS; ++its) {
    const Vec Jp = J.selfadjointView<Eigen::Lower>() * p;
    const double alpha = rz / p.dot(Jp);
    dx += alpha * p;
    r -= alpha * Jp;
    if (!(r.norm() > stop)) return true;
    z = chol.solve(r);
    const double rz_next = r.dot(z);
    p = z + (rz_next / rz) * p;
    rz = rz_next;
  }
  return false;
}

// The Newton matrix with this step's coupling columns (J's lower triangle holds its symmetric part).
Vec SsnRun::apply(const Vec& v) const {
  Vec y = J.selfadjointView<Eigen::Lower>() * v;
  for (const auto& [iv, col] : coupled)
    for (int c = 1; c < d; ++c) y[iv + c] += col[c] * v[iv];
  return y;
}

// GMRES on (J + C) dx = rhs (C the coupling columns), right-preconditioned by the factor of J: the
// preconditioned matrix I + C J⁻¹ is the identity plus a rank of the coupled nodes' count, so it
// converges in about that many iterations. @return whether it reached lim.rtol within MAX_ITS.
bool SsnRun::gmres(Vec& dx, int& its) const {
  constexpr int MAX_ITS = 30;  // more means the factor no longer fits J: refactorize instead
  const double bnorm = rhs.norm();
  dx = Vec::Zero(rhs.size());
  its = 0;
  if (!(bnorm > 0)) return true;
  Mat V(rhs.size(), MAX_ITS + 1), H = Mat::Zero(MAX_ITS + 1, MAX_ITS);
  V.col(0) = rhs / bnorm;
  Vec y;
  bool done = false;
  while (its < MAX_ITS && !done) {
    const int j = its++;
    Vec w = apply(chol.solve(V.col(j)));
    for (int i = 0; i <= j; ++i) {  // modified Gram–Schmidt
      H(i, j) = w.dot(V.col(i));
      w -= H(i, j) * V.col(i);
    }
    H(j + 1, j) = w.norm();
    Vec e = Vec::Zero(j + 2);
    e[0] = bnorm;
    const auto Hj = H.topLeftCorner(j + 2, j + 1);
    y = Hj.colPivHouseholderQr().solve(e);
    done = (e - Hj * y).norm() <= lim.rtol * bnorm || !(H(j + 1, j) > 0);
    if (!done) V.col(j + 1) = w / H(j + 1, j);
  }
  dx = chol.solve(V.leftCols(y.size()) * y);
  return done;
}

// The Newton step: CG (GMRES once coupled) on the last factor where the statuses held, else (or if
// that stalls) a numeric factorization of J. @return false when J is not positive definite.
bool SsnRun::newton_direction(long changed, Vec& dx, int& its) {
  its = 0;
  fresh = false;
  const bool krylov_on_last = factored && changed == 0;
  if (krylov_on_last && (coupled.empty() ? preconditioned_cg(dx, its) : gmres(dx, its))) return true;
  fresh = true;
  try {
    chol.factorize(J);
  } catch (const Error&) {
    return false;
  }
  factored = true;
  if (!coupled.empty()) return gmres(dx, its), true;  // on a fresh factor: converged, or the best it has
  its = 0;
  dx = chol.solve(rhs);
  return true;
}

// Step k: the Newton direction, the update, the reversals and the record.
// @return true when ssn has converged (ssn_step_settled).
bool SsnRun::step(int k, long changed, double res, SsnOutcome& out) {
  const auto t0 = clk::now();
  Vec dx;
  int cg_its = 0;
  if (!newton_direction(changed, dx, cg_its)) {
    out.message = "ssn: the Newton matrix at step " + std::to_string(k) +
                  " is not positive definite (a softening branch of p_nu steeper than the body holds: the inner "
                  "problem is not convex there); the design's path (--backend ipopt) handles it";
    return false;
  }
  // Once the statuses cycle, the step is shortened until the merit of the iterate it leads to
  // (the reversal rule applied) decreases (ssn.hpp).
  const auto iterate = [&](double t) {
    Vec xt = x + t * dx;
    stop_reversals(xt, nullptr);
    return merit(xt);
  };
  const double theta = watch.cycling() ? ssn_step_length(merit(x), iterate) : 1.0;
  if (theta != 1.0) dx *= theta;
  x += dx;
  const long projected = stop_reversals(x, &hold_stick);
  const double step = dx.cwiseAbs().maxCoeff(), scale = x.cwiseAbs().maxCoeff();
  const double rel = scale > 0 ? step / scale : 0.0;
  const char* krylov = coupled.empty() ? "CG" : "GMRES";
  out.record.push_back({{"step", k}, {"status_changes", changed}, {"slip_reversals", projected}, {"cg", cg_its},
                        {"krylov_method", krylov}, {"coupled_nodes", coupled.size()}, {"theta", theta},
                        {"residual", res / F_s}, {"dx_rel", rel}, {"seconds", since(t0)}});
  log_info() << "ssn " << k << ": " << changed << " status changes, residual " << fmt(res / F_s, 3)
             << (fresh ? ", factorized" : "")
             << (cg_its > 0 ? std::string(", ") + krylov + " " + std::to_string(cg_its) + " it on the " +
                                  (fresh ? "new" : "last") + " factor"
                            : "")
             << (coupled.empty() ? "" : ", " + std::to_string(coupled.size()) + " nodes coupled")
             << (theta != 1.0 ? ", step " + fmt(theta, 3) : "") << ", |dx|/|x| " << fmt(rel, 3)
             << (projected > 0 ? ", " + std::to_string(projected) + " slip reversals set to 0" : "");
  const bool settled = ssn_step_settled(unchanged, rel, step, prev_step);
  prev_step = unchanged >= 1 ? step : INF;
  return settled;
}

}  // namespace

uint64_t ssn_node_signature(Index node, int code) {
  // splitmix64 of (node, code): a change of one node's code changes the sum in any of 2⁶⁴ ways.
  uint64_t z = static_cast<uint64_t>(node) * 0x9E3779B97F4A7C15ull + static_cast<uint64_t>(code) + 1;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

void SsnCycleWatch::see(uint64_t signature, long changed) {
  if (changed > 0 && std::find(m_recent.begin(), m_recent.end(), signature) != m_recent.end()) m_cycling = true;
  m_recent.push_back(signature);
  if (m_recent.size() > static_cast<size_t>(SSN_CYCLE_MEMORY)) m_recent.erase(m_recent.begin());
}

double ssn_step_length(double merit_now, const std::function<double(double)>& merit_at) {
  double theta = 1;
  for (int h = 0; h < SSN_HALVINGS; ++h, theta *= 0.5)
    if (merit_at(theta) < (1 - SSN_ARMIJO * theta) * merit_now) return theta;
  return theta;  // 1/2^SSN_HALVINGS: the shortest, whether or not it decreases the merit
}

SsnOutcome ssn_full(const Model& md, const SsnLimits& limits, const Vec* x0) {
  if (!md.material->is_linear()) throw Error("ssn: needs a linear material (K_x is its stiffness)", EXIT_INPUT);
  const auto t0 = clk::now();
  SsnRun run(md, limits, x0);
  SsnOutcome out;
  int k = 1;
  for (; k <= limits.max_iters && out.message.empty(); ++k) {
    const long changed = run.linearize(k);
    const double res = run.right_hand_side();
    // Converged at this iterate: its statuses are the last step's and the semismooth residual is
    // at most solver.ssn.tol of the load scale; no step is taken (petsc_ssn.cpp's rule).
    if (k > 1 && changed == 0 && res / run.F_s <= limits.tol) {
      out.converged = true;
      log_info() << "ssn " << k << ": statuses held, residual " << fmt(res / run.F_s, 3) << " <= solver.ssn.tol: converged";
      break;
    }
    if (run.step(k, changed, res, out)) {
      out.converged = true;
      ++k;
      break;
    }
  }
  out.steps = k - 1;
  if (!out.converged && out.message.empty())
    out.message = "ssn: no convergence in " + std::to_string(limits.max_iters) +
                  " Newton steps (solver.ssn.max_iters; the statuses still changed or the step did not reach "
                  "round-off)";
  out.x = std::move(run.x);
  out.seconds = since(t0);
  return out;
}

}  // namespace hemicontact
