#include <hemicontact/contact/contact_nodes.hpp>

#include <hemicontact/core/error.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

namespace hemicontact {

double Gap::at(const Eigen::Ref<const Eigen::RowVectorXd>& x) const {
  if (points.empty()) return constant;
  const double s = x[axis];
  if (s <= points.front().first) return points.front().second;
  if (s >= points.back().first) return points.back().second;
  const auto it = std::upper_bound(points.begin(), points.end(), s,
                                   [](double v, const std::pair<double, double>& p) { return v < p.first; });
  const auto& [s1, g1] = *it;
  const auto& [s0, g0] = *(it - 1);
  return s1 > s0 ? g0 + (g1 - g0) * (s - s0) / (s1 - s0) : g1;
}

std::string Gap::describe() const {
  std::ostringstream os;
  if (points.empty()) {
    if (constant == INF)
      os << "g = inf (no rigid obstacle)";
    else
      os << "g = " << constant;
  } else {
    os << "g piecewise linear in "
       << "xyz"[axis] << " through " << points.size() << " points";
  }
  return os.str();
}

bool gamma3_precedes(const double* a, long ia, const double* b, long ib, int dim) {
  for (int k = 0; k < dim; ++k)
    if (a[k] != b[k]) return a[k] < b[k];
  return ia < ib;
}

Gamma3Sums gamma3_sums(const Mesh& mesh) {
  const int d = mesh.dim;
  Gamma3Sums s{Vec::Zero(mesh.num_nodes()), RowMat::Zero(mesh.num_nodes(), d)};
  for (Index f = 0; f < mesh.num_facets(); ++f) {
    if (mesh.facet_part[f] != Part::GAMMA3) continue;
    const double a = mesh.facet_measure(f);
    const Vec n = mesh.facet_normal(f);
    for (int k = 0; k < d; ++k) {
      const int v = mesh.facets(f, k);
      s.w[v] += a / d;
      s.normal.row(v) += (a / d) * n.transpose();
    }
  }
  return s;
}

ContactNodes make_contact_nodes(const Mesh& mesh, const std::vector<bool>& clamped, const Gap& gap,
                                const GivenBoundary* given) {
  const int d = mesh.dim;
  const Index N = mesh.num_nodes();
  Gamma3Sums sums = gamma3_sums(mesh);
  if (given)
    for (size_t i = 0; i < given->node.size(); ++i) {
      sums.w[given->node[i]] = given->w[static_cast<Index>(i)];
      sums.normal.row(given->node[i]) = given->normal.row(static_cast<Index>(i));
    }
  const Vec& w = sums.w;
  const RowMat& nsum = sums.normal;
  std::vector<int> nodes;
  for (Index v = 0; v < N; ++v)
    if (w[v] > 0 && !clamped[v]) nodes.push_back(static_cast<int>(v));
  // Lexicographic order by coordinates: left to right along a bottom edge, as the reference data.
  std::sort(nodes.begin(), nodes.end(), [&](int a, int b) {
    double pa[3], pb[3];
    for (int k = 0; k < d; ++k) pa[k] = mesh.points(a, k), pb[k] = mesh.points(b, k);
    return gamma3_precedes(pa, a, pb, b, d);
  });
  ContactNodes c;
  c.node = nodes;
  const Index n = c.size();
  c.w.resize(n);
  c.normal.resize(n, d);
  c.tangent.resize(n, d);
  c.g.resize(n);
  for (Index i = 0; i < n; ++i) {
    const int v = nodes[i];
    c.w[i] = w[v];
    c.normal.row(i) = nsum.row(v) / nsum.row(v).norm();
    const unsigned char fixed = mesh.held(v);
    if (fixed) {
      // A roller on a Γ3 node: each fixed global axis must be tangent, and becomes a local tangent,
      // so that "u_c = 0" is the bound x_τ = 0 on one local unknown.
      if (c.fixed_local.empty()) c.fixed_local.assign(static_cast<size_t>(n), 0);
      std::vector<int> axes;
      for (int a = 0; a < d; ++a)
        if (fixed & (1u << a)) {
          if (std::abs(c.normal(i, a)) > 1e-9) {
            std::ostringstream os;
            os << "boundary.rollers: the Γ3 node at (" << mesh.points.row(v) << ") is held along "
               << "xyz"[a] << ", which is not tangent to Γ3 (normal " << c.normal.row(i)
               << "): a roller may only fix tangential components of a contact node";
            input_error(os.str());
          }
          axes.push_back(a);
        }
      if (d == 2) {
        c.tangent.row(i) = RowMat::Zero(1, 2);
        c.tangent(i, axes[0]) = 1.0;
        c.fixed_local[i] = 1u << 1;
      } else {
        // ν × (ν × e) = −e for a unit e ⟂ ν: with τ1 = ν × e the second tangent ν × τ1 is −e.
        const Eigen::Vector3d nu = c.normal.row(i).transpose();
        const Eigen::Vector3d e = Eigen::Vector3d::Unit(axes[0]);
        c.tangent.row(i) = nu.cross(e).normalized().transpose();
        c.fixed_local[i] = axes.size() == 1 ? (1u << 2) : ((1u << 1) | (1u << 2));
      }
    } else if (d == 2) {
      c.tangent(i, 0) = -c.normal(i, 1);
      c.tangent(i, 1) = c.normal(i, 0);
    } else {
      // First tangent: the unit vector of the projection of the axis least aligned with ν.
      Eigen::Vector3d nu = c.normal.row(i).transpose();
      Eigen::Index k;
      nu.cwiseAbs().minCoeff(&k);
      Eigen::Vector3d e = Eigen::Vector3d::Unit(k);
      Eigen::Vector3d t1 = (e - e.dot(nu) * nu).normalized();
      c.tangent.row(i) = t1.transpose();
    }
    c.g[i] = gap.at(mesh.points.row(v));
    if (!(c.g[i] >= 0)) {
      std::ostringstream os;
      os << "contact.gap: negative thickness g = " << c.g[i] << " at Γ3 node (" << mesh.points.row(v)
         << "); eq. (14) requires g >= 0";
      input_error(os.str());
    }
  }
  return c;
}

}  // namespace hemicontact
