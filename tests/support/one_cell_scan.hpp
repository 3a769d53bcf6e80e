#pragma once
// The exact piecewise-linear conditions of problems/minima-one-node.json (one cell, top clamped,
// frictionless): the free unknowns are the two bottom nodes' (ν, τ), x = (ν0, τ0, ν1, τ1), and
//   Π_t(x) = ½ xᵀK_x x − t f_xᵀx + Σ_k w_k j(x_ν,k),   x_ν,k ≤ g.
// On a choice of branch per node (a piece of the piecewise-linear p = j′, or the bound x_ν,k = g)
// the stationarity conditions are linear in (x, t); their solution is a stationary point when it
// lies on its pieces (off g) and every contact node has a rigid reaction R ≥ 0; the Hessian
// K_x + diag(w_k s_i) on the non-contact unknowns gives its index (0: a local minimum, 1: a saddle).
// Shared by the load-path scan and the barrier test.

#include <hemicontact/problem/model.hpp>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include <algorithm>
#include <vector>

namespace hemicontact::one_cell {

struct Piece {
  double lo, hi, a, s;  // p = a + s r on [lo, hi]
};

// The pieces of p below g; index pieces.size() is the bound x_ν = g.
inline std::vector<Piece> pieces_below_gap(const PiecewiseLinearLaw& law, double g) {
  const auto& r = law.breakpoints();
  const auto& s = law.slopes();
  std::vector<Piece> P;
  P.push_back({-INF, r[0], law.values_left()[0] - s[0] * r[0], s[0]});
  for (size_t i = 1; i < r.size(); ++i) P.push_back({r[i - 1], r[i], law.values_right()[i - 1] - s[i] * r[i - 1], s[i]});
  P.push_back({r.back(), INF, law.values_right().back() - s.back() * r.back(), s.back()});
  for (auto& p : P) p.hi = std::min(p.hi, g);
  return P;
}

// The stationary point of a branch choice at load factor t.
struct Branch {
  bool valid = false;    // on its pieces, reactions ≥ 0
  int negative = 0;      // negative eigenvalues of the reduced Hessian
  bool minimum = false;  // valid and positive definite
  Vec x;
  double energy = 0;
};

inline Branch on_branch(const Model& md, const std::vector<Piece>& P, const std::vector<int>& choice, double t) {
  const Mat K = Mat(md.Kx.full());
  const Vec f = t * md.fx;
  const int contact = static_cast<int>(P.size());
  Mat A = K, H = K;
  Vec b = f;
  std::vector<Index> keep;
  for (Index k = 0; k < 2; ++k) {
    const Index i = md.dofs.contact_dof(k, 0);
    const int c = choice[static_cast<size_t>(k)];
    if (c == contact) {
      A.row(i).setZero();
      A(i, i) = 1;
      b[i] = md.contact.g[k];
    } else {
      A(i, i) += md.contact.w[k] * P[static_cast<size_t>(c)].s;
      H(i, i) += md.contact.w[k] * P[static_cast<size_t>(c)].s;
      b[i] -= md.contact.w[k] * P[static_cast<size_t>(c)].a;
      keep.push_back(i);
    }
    keep.push_back(md.dofs.contact_dof(k, 1));
  }
  Branch B;
  Eigen::FullPivLU<Mat> lu(A);
  if (!lu.isInvertible()) return B;
  B.x = lu.solve(b);
  const Vec res = K * B.x - f;
  bool ok = true;
  for (Index k = 0; k < 2; ++k) {
    const Index i = md.dofs.contact_dof(k, 0);
    const int c = choice[static_cast<size_t>(k)];
    if (c == contact)
      ok = ok && -res[i] - md.contact.w[k] * md.normal_law->p(md.contact.g[k]) >= 0;
    else
      ok = ok && B.x[i] >= P[static_cast<size_t>(c)].lo && B.x[i] <= P[static_cast<size_t>(c)].hi &&
           B.x[i] < md.contact.g[k];
  }
  std::sort(keep.begin(), keep.end());
  Mat Hr(static_cast<Index>(keep.size()), static_cast<Index>(keep.size()));
  for (size_t a = 0; a < keep.size(); ++a)
    for (size_t c = 0; c < keep.size(); ++c) Hr(Index(a), Index(c)) = H(keep[a], keep[c]);
  const Vec ev = Eigen::SelfAdjointEigenSolver<Mat>(Hr).eigenvalues();
  B.valid = ok;
  B.negative = static_cast<int>((ev.array() < 0).count());
  B.minimum = ok && B.negative == 0;
  B.energy = 0.5 * B.x.dot(K * B.x) - f.dot(B.x);
  for (Index k = 0; k < 2; ++k) B.energy += md.contact.w[k] * md.normal_law->j(B.x[md.dofs.contact_dof(k, 0)]);
  return B;
}

}  // namespace hemicontact::one_cell
