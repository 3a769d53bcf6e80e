#include <hemicontact/check/estimator.hpp>

#include <hemicontact/core/error.hpp>
#include <hemicontact/fem/p1.hpp>
#include <hemicontact/mesh/edge_key.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <unordered_map>

namespace hemicontact {
namespace {

using P = P1<2>;

// Cell strains (Voigt, engineering shear) and areas.
void cell_strains(const Model& md, const Vec& u, RowMat& eps, Vec& area) {
  const Mesh& m = md.mesh;
  eps.resize(m.num_cells(), 3);
  area.resize(m.num_cells());
  for (Index c = 0; c < m.num_cells(); ++c) {
    double meas = 0;
    const P::Grad G = P::gradients(m, c, meas);
    Eigen::Matrix<double, 6, 1> ue;
    for (int a = 0; a < 3; ++a) ue.segment<2>(2 * a) = u.segment<2>(2 * m.cells(c, a));
    eps.row(c) = (P::strain_matrix(G) * ue).transpose();
    area[c] = meas;
  }
}

// The traction σ_T n of a constant Voigt stress s = (σ11, σ22, σ12) on a unit normal n.
Eigen::Vector2d traction(const Vec& s, const Eigen::Vector2d& n) {
  return {s[0] * n[0] + s[2] * n[1], s[2] * n[0] + s[1] * n[1]};
}

ErrorEstimate zz(const Model& md, const Solution& sol) {
  const Mesh& m = md.mesh;
  RowMat eps;
  Vec area;
  cell_strains(md, sol.u, eps, area);
  // Area-weighted nodal averages ε*(x_a) = Σ_{T∋a} |T| ε_T / Σ |T|.
  RowMat rec = RowMat::Zero(m.num_nodes(), 3);
  Vec wsum = Vec::Zero(m.num_nodes());
  for (Index c = 0; c < m.num_cells(); ++c)
    for (int a = 0; a < 3; ++a) {
      rec.row(m.cells(c, a)) += area[c] * eps.row(c);
      wsum[m.cells(c, a)] += area[c];
    }
  for (Index v = 0; v < m.num_nodes(); ++v)
    if (wsum[v] > 0) rec.row(v) /= wsum[v];
  ErrorEstimate e;
  e.kind = EstimatorKind::ZZ;
  e.eta.resize(m.num_cells());
  // A linear law's tangent is the same in every cell: evaluated once, not per cell (a heap-allocated
  // matrix per cell was a third of the estimator's time at 120k cells).
  const bool linear = md.material->is_linear();
  const Mat C_linear = linear ? md.material->tangent(Vec::Zero(3)) : Mat();
  Mat C_cell;
  for (Index c = 0; c < m.num_cells(); ++c) {
    const Mat& C = linear ? C_linear : (C_cell = md.material->tangent(eps.row(c).transpose()));
    // δ = ε* − ε_h is affine on T: its values at the edge midpoints are the means of the vertex
    // values, and the midpoint rule (weights |T|/3) integrates the quadratic δᵀ C δ exactly.
    double s = 0;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d d = (0.5 * (rec.row(m.cells(c, k)) + rec.row(m.cells(c, (k + 1) % 3))) - eps.row(c)).transpose();
      s += d.dot(C * d);
    }
    e.eta[c] = std::sqrt(std::max(0.0, s * area[c] / 3.0));
  }
  return e;
}


ErrorEstimate residual(const Model& md, const Solution& sol) {
  const Mesh& m = md.mesh;
  const double mF = md.material->m_F();
  if (!(mF > 0)) input_error("adapt.estimator: 'residual' needs a strongly monotone material (m_F > 0)");
  RowMat eps;
  Vec area;
  cell_strains(md, sol.u, eps, area);
  std::vector<Vec> sigma(static_cast<size_t>(m.num_cells()));
  for (Index c = 0; c < m.num_cells(); ++c) sigma[static_cast<size_t>(c)] = md.material->stress(eps.row(c).transpose());

  Vec eta2 = Vec::Zero(m.num_cells());
  // Element residual: f0 + div σ_h = f0 (σ_h constant on each P1 cell); h_T = longest edge.
  const auto f0v = md.scene.at("loads").at("body_force").get<std::vector<double>>();
  const double scale = md.scene.at("loads").at("scale").get<double>();
  const Eigen::Vector2d f0(scale * f0v.at(0), scale * f0v.at(1));
  for (Index c = 0; c < m.num_cells(); ++c) {
    double hT = 0;
    for (int k = 0; k < 3; ++k)
      hT = std::max(hT, (m.points.row(m.cells(c, k)) - m.points.row(m.cells(c, (k + 1) % 3))).norm());
    eta2[c] += hT * hT * area[c] * f0.squaredNorm();
  }
  // Interior jumps: each edge seen from its two cells; ½ h_E ‖[σn]‖²_E to each (‖·‖²_E = |E|·|J|²).
  std::unordered_map<std::uint64_t, std::pair<Index, int>> first;  // edge → (cell, local edge)
  first.reserve(static_cast<size_t>(2 * m.num_cells()));
  for (Index c = 0; c < m.num_cells(); ++c)
    for (int k = 0; k < 3; ++k) {
      const int a = m.cells(c, k), b = m.cells(c, (k + 1) % 3);
      auto [it, fresh] = first.emplace(edge_key(a, b), std::make_pair(c, k));
      if (fresh) continue;
      const Index o = it->second.first;
      const Eigen::Vector2d t = (m.points.row(b) - m.points.row(a)).transpose();
      const double hE = t.norm();
      const Eigen::Vector2d n(t[1] / hE, -t[0] / hE);  // outward of c (c is counter-clockwise)
      const Eigen::Vector2d J = traction(sigma[static_cast<size_t>(c)], n) - traction(sigma[static_cast<size_t>(o)], n);
      const double q = 0.5 * hE * hE * J.squaredNorm();
      eta2[c] += q;
      eta2[o] += q;
    }
  // Boundary facets: the cell each belongs to.
  std::vector<Index> node_contact(static_cast<size_t>(m.num_nodes()), -1);
  for (Index k = 0; k < md.contact.size(); ++k) node_contact[static_cast<size_t>(md.contact.node[k])] = k;
  const auto nodal_traction = [&](int v, const Eigen::Vector2d& fallback) -> Eigen::Vector2d {
    const Index k = node_contact[static_cast<size_t>(v)];
    if (k < 0) return fallback;  // a Γ3 end that is clamped: no contact term there
    return sol.state.sigma_nu[k] * md.contact.normal.row(k).transpose() + sol.state.sigma_tau_vec.row(k).transpose();
  };
  for (Index f = 0; f < m.num_facets(); ++f) {
    const Part part = m.facet_part[static_cast<size_t>(f)];
    if (part == Part::GAMMA1) continue;
    const int a = m.facets(f, 0), b = m.facets(f, 1);
    const auto it = first.find(edge_key(a, b));
    if (it == first.end()) continue;
    const Index c = it->second.first;
    const Eigen::Vector2d n = m.facet_normal(f);
    const double hE = m.facet_measure(f);
    const Eigen::Vector2d s = traction(sigma[static_cast<size_t>(c)], n);
    if (part == Part::GAMMA3) {
      // t_h − σn is affine along E: ‖·‖²_E = |E|/3 (d_a² + d_a·d_b + d_b²).
      const Eigen::Vector2d da = nodal_traction(a, s) - s, db = nodal_traction(b, s) - s;
      eta2[c] += hE * hE / 3.0 * (da.squaredNorm() + da.dot(db) + db.squaredNorm());
    } else {
      const int load = m.facet_load[static_cast<size_t>(f)];
      Eigen::Vector2d g = Eigen::Vector2d::Zero();
      if (load >= 0) g = m.tractions[static_cast<size_t>(load)].head<2>();
      eta2[c] += hE * hE * (g - s).squaredNorm();
    }
  }
  ErrorEstimate e;
  e.kind = EstimatorKind::RESIDUAL;
  e.eta = (eta2 / mF).cwiseSqrt();
  return e;
}

}  // namespace

EstimatorKind parse_estimator(const std::string& name) {
  if (name == "zz") return EstimatorKind::ZZ;
  if (name == "residual") return EstimatorKind::RESIDUAL;
  input_error("adapt.estimator: unknown estimator '" + name + "' (expected zz or residual)");
}

const char* to_string(EstimatorKind k) { return k == EstimatorKind::ZZ ? "zz" : "residual"; }

ErrorEstimate estimate_error(const Model& md, const Solution& sol, EstimatorKind kind) {
  if (md.dim() != 2) input_error("adapt: error estimation is implemented for 2D meshes only");
  ErrorEstimate e = kind == EstimatorKind::ZZ ? zz(md, sol) : residual(md, sol);
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
