#include <hemicontact/fem/prolongation.hpp>

#include <hemicontact/core/error.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

namespace hemicontact {
namespace {

// Barycentric tolerance: dimensionless, so "on the cell" means the same at every h. Round-off of
// λ = J⁻¹(x − p0) is ~1e-15 for shape-regular cells; 1e-10 leaves room for nodes that a mesh
// generator placed on a coarse edge by an independent computation.
constexpr double BARY_TOL = 1e-10;

// Uniform bucket grid over the coarse mesh: each bucket lists the cells whose (slightly padded)
// bounding box meets it, in CSR form. About two cells per bucket keeps a query at a handful of
// barycentric evaluations whatever the mesh size.
struct BucketGrid {
  int d = 2;
  Eigen::Vector3d lo = Eigen::Vector3d::Zero(), size = Eigen::Vector3d::Ones();
  Eigen::Vector3i n = Eigen::Vector3i::Ones();
  std::vector<Index> start, cells;

  int coord(double x, int k) const {
    const double t = std::floor((x - lo[k]) / size[k]);
    return static_cast<int>(std::clamp(t, 0.0, static_cast<double>(n[k] - 1)));
  }
  Index flat(const Eigen::Vector3i& b) const { return (static_cast<Index>(b[2]) * n[1] + b[1]) * n[0] + b[0]; }
};

BucketGrid make_grid(const Mesh& m) {
  BucketGrid g;
  const int d = m.dim;
  g.d = d;
  const Index M = m.num_cells();
  Eigen::Vector3d hi = Eigen::Vector3d::Zero();
  for (int k = 0; k < d; ++k) {
    g.lo[k] = m.points.col(k).minCoeff();
    hi[k] = m.points.col(k).maxCoeff();
  }
  // Bucket edge s with (∏ extents)/s^d ≈ M/2; a flat direction (zero extent) gets one bucket.
  double vol = 1;
  int live = 0;
  double diam = 0;
  for (int k = 0; k < d; ++k) diam = std::hypot(diam, hi[k] - g.lo[k]);
  for (int k = 0; k < d; ++k)
    if (hi[k] - g.lo[k] > 1e-12 * diam) {
      vol *= hi[k] - g.lo[k];
      ++live;
    }
  const double s = live ? std::pow(2.0 * vol / static_cast<double>(M), 1.0 / live) : 1.0;
  for (int k = 0; k < d; ++k) {
    const double ext = hi[k] - g.lo[k];
    g.n[k] = ext > 1e-12 * diam ? std::max(1, std::min(1 << 14, static_cast<int>(ext / s))) : 1;
    g.size[k] = ext > 0 ? ext / g.n[k] : 1.0;
  }
  const Index nb = static_cast<Index>(g.n[0]) * g.n[1] * g.n[2];

  // Two passes (count, fill) over the bucket range of each cell's padded bounding box.
  std::vector<std::pair<Eigen::Vector3i, Eigen::Vector3i>> range(M);
  for (Index c = 0; c < M; ++c) {
    Eigen::Vector3i b0 = Eigen::Vector3i::Zero(), b1 = Eigen::Vector3i::Zero();
    for (int k = 0; k < d; ++k) {
      double a = INF, b = -INF;
      for (int v = 0; v <= d; ++v) {
        a = std::min(a, m.points(m.cells(c, v), k));
        b = std::max(b, m.points(m.cells(c, v), k));
      }
      const double pad = 1e-8 * (b - a) + 1e-14 * diam;  // covers the barycentric tolerance
      b0[k] = g.coord(a - pad, k);
      b1[k] = g.coord(b + pad, k);
    }
    range[c] = {b0, b1};
  }
  g.start.assign(nb + 1, 0);
  const auto each_bucket = [&](Index c, auto&& f) {
    const auto& [b0, b1] = range[c];
    Eigen::Vector3i b;
    for (b[2] = b0[2]; b[2] <= b1[2]; ++b[2])
      for (b[1] = b0[1]; b[1] <= b1[1]; ++b[1])
        for (b[0] = b0[0]; b[0] <= b1[0]; ++b[0]) f(g.flat(b));
  };
  for (Index c = 0; c < M; ++c) each_bucket(c, [&](Index i) { ++g.start[i + 1]; });
  for (Index i = 0; i < nb; ++i) g.start[i + 1] += g.start[i];
  g.cells.resize(g.start[nb]);
  std::vector<Index> fill(g.start.begin(), g.start.end() - 1);
  for (Index c = 0; c < M; ++c) each_bucket(c, [&](Index i) { g.cells[fill[i]++] = c; });
  return g;
}

}  // namespace

Vec prolongate(const Mesh& coarse, const Vec& u_coarse, const Mesh& fine) {
  const int d = coarse.dim;
  if (fine.dim != d)
    throw Error("prolongate: the coarse mesh is " + std::to_string(d) + "-D, the fine mesh " +
                std::to_string(fine.dim) + "-D");
  if (d < 2 || d > 3) throw Error("prolongate: dimension " + std::to_string(d) + " is not supported");
  if (u_coarse.size() != coarse.num_nodes() * d)
    throw Error("prolongate: the coarse field has " + std::to_string(u_coarse.size()) + " entries, the mesh " +
                std::to_string(coarse.num_nodes() * d) + " dofs");
  if (coarse.num_cells() == 0) throw Error("prolongate: the coarse mesh has no cells");

  // λ_{1..d} = J⁻¹ (x − p0), J = [p1 − p0, …, pd − p0]; λ_0 = 1 − Σ λ_k. J⁻¹ once per cell.
  const Index M = coarse.num_cells();
  std::vector<Mat> Jinv(M);
  for (Index c = 0; c < M; ++c) {
    Mat J(d, d);
    for (int v = 1; v <= d; ++v)
      J.col(v - 1) = (coarse.points.row(coarse.cells(c, v)) - coarse.points.row(coarse.cells(c, 0))).transpose();
    Jinv[c] = J.inverse();
  }
  const BucketGrid grid = make_grid(coarse);

  const Index Nf = fine.num_nodes();
  Vec out = Vec::Zero(Nf * d);
  Vec lam(d + 1), best_lam(d + 1), x(d);
  for (Index a = 0; a < Nf; ++a) {
    x = fine.points.row(a).transpose();
    Eigen::Vector3i b = Eigen::Vector3i::Zero();
    for (int k = 0; k < d; ++k) b[k] = grid.coord(x[k], k);
    const Index bucket = grid.flat(b);
    // The cell with the largest smallest coordinate: inside beats on-the-edge beats outside.
    Index best = -1;
    double best_min = -INF;
    for (Index i = grid.start[bucket]; i < grid.start[bucket + 1]; ++i) {
      const Index c = grid.cells[i];
      lam.tail(d) = Jinv[c] * (x - coarse.points.row(coarse.cells(c, 0)).transpose());
      lam[0] = 1.0 - lam.tail(d).sum();
      const double mn = lam.minCoeff();
      if (mn > best_min) {
        best_min = mn;
        best = c;
        best_lam = lam;
        if (mn >= 0) break;  // strictly inside or exactly on the boundary: no better cell exists
      }
    }
    if (best < 0 || best_min < -BARY_TOL) {
      std::ostringstream os;
      os.precision(17);
      os << "prolongate: fine node " << a << " at (";
      for (int k = 0; k < d; ++k) os << (k ? ", " : "") << x[k];
      os << ") lies in no cell of the coarse mesh";
      if (best >= 0)
        os << " (nearest candidate: cell " << best << ", smallest barycentric coordinate " << best_min << ")";
      throw Error(os.str());
    }
    for (int v = 0; v <= d; ++v) out.segment(d * a, d) += best_lam[v] * u_coarse.segment(d * coarse.cells(best, v), d);
  }
  return out;
}

double energy_norm_difference(const SpMat& K_fine, const Vec& u_fine, const Vec& u_prolongated) {
  if (K_fine.rows() != K_fine.cols() || K_fine.rows() != u_fine.size() || u_fine.size() != u_prolongated.size())
    throw Error("energy_norm_difference: K is " + std::to_string(K_fine.rows()) + "x" + std::to_string(K_fine.cols()) +
                ", the fields have " + std::to_string(u_fine.size()) + " and " + std::to_string(u_prolongated.size()) +
                " entries");
  const Vec e = u_fine - u_prolongated;
  return std::sqrt(std::max(0.0, e.dot(K_fine * e)));
}

}  // namespace hemicontact
