#include <hemicontact/check/estimator.hpp>

#include <hemicontact/core/error.hpp>
#include <hemicontact/fem/p1.hpp>

#include <algorithm>
#include <cmath>
#include <array>
#include <map>
#include <numeric>

namespace hemicontact {
namespace {

// Cell strains (Voigt, engineering shears) and measures, for P1 in dimension D.
template <int D>
void cell_strains(const Model& md, const Vec& u, RowMat& eps, Vec& measure) {
  using P = P1<D>;
  const Mesh& m = md.mesh;
  eps.resize(m.num_cells(), P::NVOIGT);
  measure.resize(m.num_cells());
  for (Index c = 0; c < m.num_cells(); ++c) {
    double meas = 0;
    const typename P::Grad G = P::gradients(m, c, meas);
    Eigen::Matrix<double, P::NDOF, 1> ue;
    for (int a = 0; a < P::NV; ++a) ue.template segment<D>(D * a) = u.segment<D>(D * m.cells(c, a));
    eps.row(c) = (P::strain_matrix(G) * ue).transpose();
    measure[c] = meas;
  }
}

// The traction σ n of a constant Voigt stress s on a unit normal n (2D: (σ11, σ22, σ12); 3D:
// (σ11, σ22, σ33, σ23, σ13, σ12)).
template <int D>
Eigen::Matrix<double, D, 1> traction(const Vec& s, const Eigen::Matrix<double, D, 1>& n) {
  Eigen::Matrix<double, D, D> S;
  if constexpr (D == 2) S << s[0], s[2], s[2], s[1];
  else S << s[0], s[5], s[4], s[5], s[1], s[3], s[4], s[3], s[2];
  return S * n;
}

// ∫ over a simplex of measure @p meas with D_s + 1 vertices of δᵀ A δ, δ affine with vertex values
// d_i: ∫ λ_i λ_j = meas (1 + δ_ij) / ((D_s + 1)(D_s + 2)), so the integral is
// meas / ((D_s + 1)(D_s + 2)) · (Σ_i d_iᵀ A d_i + (Σ_i d_i)ᵀ A (Σ_i d_i)), exact.
template <class Vecs, class A>
double affine_square_integral(const Vecs& d, int n, const A& a, double meas) {
  double diag = 0;
  auto sum = d[0];
  sum.setZero();
  for (int i = 0; i < n; ++i) {
    diag += d[i].dot(a * d[i]);
    sum += d[i];
  }
  return meas / (n * (n + 1)) * (diag + sum.dot(a * sum));
}

// The longest edge of a cell or a facet (h_T, h_F).
double diameter(const Mesh& m, const Eigen::Ref<const Eigen::VectorXi>& v) {
  double h = 0;
  for (Index i = 0; i < v.size(); ++i)
    for (Index j = i + 1; j < v.size(); ++j) h = std::max(h, (m.points.row(v[i]) - m.points.row(v[j])).norm());
  return h;
}

// Per cell: h_T² ‖f0‖²_T, the element residual (σ_h constant on P1 cells: div σ_h = 0).
template <int D>
void element_residuals(const Model& md, const Vec& meas, Vec& eta2) {
  const Mesh& m = md.mesh;
  const auto f0v = md.scene.at("loads").at("body_force").get<std::vector<double>>();
  const double scale = md.scene.at("loads").at("scale").get<double>();
  Eigen::Matrix<double, D, 1> f0;
  for (int i = 0; i < D; ++i) f0[i] = scale * f0v.at(static_cast<size_t>(i));
  for (Index c = 0; c < m.num_cells(); ++c) {
    const double hT = diameter(m, m.cells.row(c).transpose());
    eta2[c] += hT * hT * meas[c] * f0.squaredNorm();
  }
}

// Interior jumps: each facet seen from its two cells; ½ h_F ‖[σn]‖²_F to each (‖·‖²_F = |F|·|J|²).
// @return per boundary facet (sorted nodes) its cell.
template <int D>
std::map<std::vector<int>, Index> jump_residuals(const Mesh& m, const std::vector<Vec>& sigma, Vec& eta2) {
  std::map<std::vector<int>, Index> first;
  for (Index c = 0; c < m.num_cells(); ++c)
    for (int k = 0; k <= D; ++k) {
      std::vector<int> f;
      for (int j = 0; j <= D; ++j)
        if (j != k) f.push_back(m.cells(c, j));
      std::sort(f.begin(), f.end());
      auto [it, fresh] = first.emplace(f, c);
      if (fresh) continue;
      const Index o = it->second;
      // The facet's unit normal from c's barycentric gradient of its opposite vertex (outward of c).
      double meas = 0;
      const auto G = P1<D>::gradients(m, c, meas);
      const Eigen::Matrix<double, D, 1> n = -G.row(k).transpose().normalized();
      const Eigen::Matrix<double, D, 1> J = traction<D>(sigma[static_cast<size_t>(c)], n) - traction<D>(sigma[static_cast<size_t>(o)], n);
      // |F| = D |T| |∇λ_k| / ... : the height of vertex k over F is 1/|∇λ_k|, |T| = |F| h / D.
      const double area = D * std::abs(meas) * G.row(k).norm();
      const Eigen::VectorXi fv = Eigen::Map<const Eigen::VectorXi>(f.data(), D);
      const double q = 0.5 * diameter(m, fv) * area * J.squaredNorm();
      eta2[c] += q;
      eta2[o] += q;
      first.erase(it);
    }
  return first;
}

// m_F, the strong-monotonicity constant (12)(b): a(e, e) ≥ m_F ‖ε(e)‖² turns squared
// tractions (h_F ‖·‖²_F) into energy.
double energy_scale(const Model& md, const char* estimator) {
  const double mF = md.material->m_F();
  if (!(mF > 0))
    input_error(std::string("adapt.estimator: '") + estimator + "' needs a strongly monotone material (m_F > 0)");
  return mF;
}

// Each Γ3 facet's cell: only cells with D vertices on Γ3 facets are looked at (the rest of the
// mesh costs one pass over its cells).
template <int D>
std::vector<std::pair<Index, Index>> gamma3_facet_cells(const Mesh& m) {
  std::map<std::vector<int>, Index> key_of;
  std::vector<char> on(static_cast<size_t>(m.num_nodes()), 0);
  for (Index f = 0; f < m.num_facets(); ++f) {
    if (m.facet_part[static_cast<size_t>(f)] != Part::GAMMA3) continue;
    std::vector<int> fv(m.facets.row(f).data(), m.facets.row(f).data() + D);
    for (int v : fv) on[static_cast<size_t>(v)] = 1;
    std::sort(fv.begin(), fv.end());
    key_of.emplace(std::move(fv), f);
  }
  std::vector<std::pair<Index, Index>> out;  // (facet, cell)
  for (Index c = 0; c < m.num_cells() && !key_of.empty(); ++c) {
    int count = 0;
    for (int a = 0; a <= D; ++a) count += on[static_cast<size_t>(m.cells(c, a))];
    if (count < D) continue;
    for (int k = 0; k <= D; ++k) {
      std::vector<int> fv;
      for (int j = 0; j <= D; ++j)
        if (j != k) fv.push_back(m.cells(c, j));
      std::sort(fv.begin(), fv.end());
      if (const auto it = key_of.find(fv); it != key_of.end()) out.emplace_back(it->second, c);
    }
  }
  return out;
}

// The Γ3 contact-traction mismatch Σ_{F⊂∂T∩Γ3} h_F ‖t_h − σ_h n‖²_F added to eta2[T] (not yet
// divided by m_F): t_h the P1 interpolant of the nodal contact tractions t_i = σ_ν,i ν_i + σ_τ,i
// (at a certified solution the layer's, the foundation's and friction's reactions, docs/model.md
// §4; a Γ3 node that is clamped has none: σ_h n itself). The one Γ3 term of both estimators.
template <int D>
void gamma3_residuals(const Model& md, const Solution& sol, const RowMat& eps, Vec& eta2) {
  using V = Eigen::Matrix<double, D, 1>;
  const Mesh& m = md.mesh;
  std::vector<Index> node_contact(static_cast<size_t>(m.num_nodes()), -1);
  for (Index k = 0; k < md.contact.size(); ++k) node_contact[static_cast<size_t>(md.contact.node[k])] = k;
  const auto nodal_traction = [&](int v, const V& fallback) -> V {
    const Index k = node_contact[static_cast<size_t>(v)];
    if (k < 0) return fallback;
    return sol.state.sigma_nu[k] * md.contact.normal.row(k).transpose() + sol.state.sigma_tau_vec.row(k).transpose();
  };
  for (const auto& [f, c] : gamma3_facet_cells<D>(m)) {
    const V s = traction<D>(md.material->stress(eps.row(c).transpose()), m.facet_normal(f));
    // t_h − σ_h n is affine on F: exact integral of its square.
    std::array<V, D> d;
    for (int j = 0; j < D; ++j) d[static_cast<size_t>(j)] = nodal_traction(m.facets(f, j), s) - s;
    eta2[c] += diameter(m, m.facets.row(f).transpose()) *
               affine_square_integral(d, D, Eigen::Matrix<double, D, D>::Identity(), m.facet_measure(f));
  }
}

template <int D>
ErrorEstimate zz(const Model& md, const Solution& sol, bool contact_term) {
  constexpr int NV = D + 1, NS = P1<D>::NVOIGT;
  const Mesh& m = md.mesh;
  RowMat eps;
  Vec meas;
  cell_strains<D>(md, sol.u, eps, meas);
  // Measure-weighted nodal averages ε*(x_a) = Σ_{T∋a} |T| ε_T / Σ |T|.
  RowMat rec = RowMat::Zero(m.num_nodes(), NS);
  Vec wsum = Vec::Zero(m.num_nodes());
  for (Index c = 0; c < m.num_cells(); ++c)
    for (int a = 0; a < NV; ++a) {
      rec.row(m.cells(c, a)) += meas[c] * eps.row(c);
      wsum[m.cells(c, a)] += meas[c];
    }
  for (Index v = 0; v < m.num_nodes(); ++v)
    if (wsum[v] > 0) rec.row(v) /= wsum[v];
  ErrorEstimate e;
  e.kind = contact_term ? EstimatorKind::ZZ_CONTACT : EstimatorKind::ZZ;
  e.eta.resize(m.num_cells());
  // A linear law's tangent is the same in every cell: evaluated once, not per cell (a heap-allocated
  // matrix per cell was a third of the estimator's time at 120k cells).
  const bool linear = md.material->is_linear();
  const Eigen::Matrix<double, NS, NS> C_linear =
      linear ? Eigen::Matrix<double, NS, NS>(md.material->tangent(Vec::Zero(NS))) : Eigen::Matrix<double, NS, NS>::Zero();
  std::array<Eigen::Matrix<double, NS, 1>, NV> d;
  for (Index c = 0; c < m.num_cells(); ++c) {
    const Eigen::Matrix<double, NS, NS> C =
        linear ? C_linear : Eigen::Matrix<double, NS, NS>(md.material->tangent(eps.row(c).transpose()));
    // δ = ε* − ε_h is affine on T: η_T² = ∫_T δᵀ C δ, exactly.
    for (int a = 0; a < NV; ++a) d[static_cast<size_t>(a)] = (rec.row(m.cells(c, a)) - eps.row(c)).transpose();
    e.eta[c] = std::max(0.0, affine_square_integral(d, NV, C, meas[c]));
  }
  // The recovery sees σ_h only. zz_contact adds the contact conditions through the residual
  // estimator's Γ3 term, the same function (docs/adaptivity.md §2).
  if (contact_term) {
    Vec g3 = Vec::Zero(m.num_cells());
    gamma3_residuals<D>(md, sol, eps, g3);
    if (g3.any()) e.eta += g3 / energy_scale(md, "zz_contact");
  }
  e.eta = e.eta.cwiseSqrt();
  return e;
}

template <int D>
ErrorEstimate residual(const Model& md, const Solution& sol) {
  using V = Eigen::Matrix<double, D, 1>;
  const Mesh& m = md.mesh;
  const double mF = energy_scale(md, "residual");
  RowMat eps;
  Vec meas;
  cell_strains<D>(md, sol.u, eps, meas);
  std::vector<Vec> sigma(static_cast<size_t>(m.num_cells()));
  for (Index c = 0; c < m.num_cells(); ++c) sigma[static_cast<size_t>(c)] = md.material->stress(eps.row(c).transpose());
  Vec eta2 = Vec::Zero(m.num_cells());
  element_residuals<D>(md, meas, eta2);
  const std::map<std::vector<int>, Index> boundary = jump_residuals<D>(m, sigma, eta2);
  for (Index f = 0; f < m.num_facets(); ++f) {
    const Part part = m.facet_part[static_cast<size_t>(f)];
    if (part == Part::GAMMA1 || part == Part::GAMMA3) continue;  // Γ3: gamma3_residuals
    std::vector<int> fv(static_cast<size_t>(D));
    for (int j = 0; j < D; ++j) fv[static_cast<size_t>(j)] = m.facets(f, j);
    std::sort(fv.begin(), fv.end());
    const auto it = boundary.find(fv);
    if (it == boundary.end()) continue;
    const V n = m.facet_normal(f);
    const V s = traction<D>(sigma[static_cast<size_t>(it->second)], n);
    const int load = m.facet_load[static_cast<size_t>(f)];
    V g = V::Zero();
    if (load >= 0) g = m.tractions[static_cast<size_t>(load)].head<D>();
    eta2[it->second] += diameter(m, m.facets.row(f).transpose()) * m.facet_measure(f) * (g - s).squaredNorm();
  }
  gamma3_residuals<D>(md, sol, eps, eta2);
  ErrorEstimate e;
  e.kind = EstimatorKind::RESIDUAL;
  e.eta = (eta2 / mF).cwiseSqrt();
  return e;
}

}  // namespace

EstimatorKind parse_estimator(const std::string& name) {
  if (name == "zz") return EstimatorKind::ZZ;
  if (name == "zz_contact") return EstimatorKind::ZZ_CONTACT;
  if (name == "residual") return EstimatorKind::RESIDUAL;
  input_error("adapt.estimator: unknown estimator '" + name + "' (expected zz, zz_contact or residual)");
}

const char* to_string(EstimatorKind k) {
  return k == EstimatorKind::ZZ ? "zz" : k == EstimatorKind::ZZ_CONTACT ? "zz_contact" : "residual";
}

ErrorEstimate estimate_error(const Model& md, const Solution& sol, EstimatorKind kind) {
  const bool contact = kind == EstimatorKind::ZZ_CONTACT;
  ErrorEstimate e;
  if (md.dim() == 2) e = kind == EstimatorKind::RESIDUAL ? residual<2>(md, sol) : zz<2>(md, sol, contact);
  else e = kind == EstimatorKind::RESIDUAL ? residual<3>(md, sol) : zz<3>(md, sol, contact);
  e.total = e.eta.norm();
  e.relative = sol.energy_norm > 0 ? e.total / sol.energy_norm : 0.0;
  return e;
}

namespace {
// Cell indices by decreasing indicator (ties by index: deterministic).
std::vector<Index> by_indicator(const Vec& eta) {
  std::vector<Index> order(static_cast<size_t>(eta.size()));
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](Index a, Index b) { return eta[a] > eta[b] || (eta[a] == eta[b] && a < b); });
  return order;
}
}  // namespace

std::vector<char> dorfler_mark(const Vec& eta, double theta) {
  std::vector<char> marked(static_cast<size_t>(eta.size()), 0);
  if (eta.size() == 0) return marked;
  const std::vector<Index> order = by_indicator(eta);
  const double total = eta.squaredNorm(), goal = theta * total;
  double sum = 0;
  double last = INF;
  for (Index c : order) {
    // Past the bulk, keep marking only the cells tied (to round-off) with the last one marked.
    if (sum >= goal && eta[c] < last * (1 - 1e-12)) break;
    marked[static_cast<size_t>(c)] = 1;
    sum += eta[c] * eta[c];
    last = eta[c];
  }
  return marked;
}

std::vector<char> mark_largest(const Vec& eta, Index count) {
  std::vector<char> marked(static_cast<size_t>(eta.size()), 0);
  if (eta.size() == 0 || count <= 0) return marked;
  const std::vector<Index> order = by_indicator(eta);
  Index n = 0;
  double last = INF;
  for (Index c : order) {
    // Past the count, keep marking only the cells tied (to round-off) with the last one marked.
    if (n >= count && eta[c] < last * (1 - 1e-12)) break;
    marked[static_cast<size_t>(c)] = 1;
    ++n;
    last = eta[c];
  }
  return marked;
}

}  // namespace hemicontact
