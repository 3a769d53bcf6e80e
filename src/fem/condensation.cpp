#include <hemicontact/fem/condensation.hpp>

#include <hemicontact/core/error.hpp>

#include <cholmod.h>

#include <chrono>
#include <numeric>

namespace hemicontact {
namespace {

using clk = std::chrono::steady_clock;
double since(clk::time_point t0) { return std::chrono::duration<double>(clk::now() - t0).count(); }

// A cholmod_sparse view (no copy) of the lower triangle of a compressed Eigen matrix.
cholmod_sparse view_lower(const SpMat& A) {
  cholmod_sparse s{};
  s.nrow = A.rows();
  s.ncol = A.cols();
  s.nzmax = A.nonZeros();
  s.p = const_cast<int*>(A.outerIndexPtr());
  s.i = const_cast<int*>(A.innerIndexPtr());
  s.x = const_cast<double*>(A.valuePtr());
  s.stype = -1;  // use the lower triangle only
  s.itype = CHOLMOD_INT;
  s.xtype = CHOLMOD_REAL;
  s.dtype = CHOLMOD_DOUBLE;
  s.sorted = 1;
  s.packed = 1;
  return s;
}

}  // namespace

struct Condensation::Impl {
  cholmod_common c{};
  cholmod_factor* L = nullptr;
  Impl() { cholmod_start(&c); }
  ~Impl() {
    if (L) cholmod_free_factor(&L, &c);
    cholmod_finish(&c);
  }
  Vec solve(const Vec& b) {
    cholmod_dense B{};
    B.nrow = b.size();
    B.ncol = 1;
    B.nzmax = b.size();
    B.d = b.size();
    B.x = const_cast<double*>(b.data());
    B.xtype = CHOLMOD_REAL;
    B.dtype = CHOLMOD_DOUBLE;
    cholmod_dense* X = cholmod_solve(CHOLMOD_A, L, &B, &c);
    Vec x = Eigen::Map<Vec>(static_cast<double*>(X->x), b.size());
    cholmod_free_dense(&X, &c);
    return x;
  }
};

Condensation::Condensation(const SpMat& K, const Vec& f, Index m) : m_impl(std::make_unique<Impl>()) {
  const Index n = K.rows(), nI = n - m;
  if (m < 0 || m > n) throw Error("condensation: bad number of condensed unknowns", EXIT_INTERNAL);
  cholmod_common& c = m_impl->c;
  c.supernodal = CHOLMOD_SUPERNODAL;
  auto t0 = clk::now();

  // 1. Fill-reducing ordering of the interior block alone (CHOLMOD's own choice, AMD or METIS).
  SpMat KII = K.topLeftCorner(nI, nI);
  KII.makeCompressed();
  std::vector<int> perm(n);
  if (nI > 0) {
    cholmod_sparse AII = view_lower(KII);
    // Nested dissection (CHOLMOD's NESDIS: METIS separators + constrained AMD): measured at 2.1M
    // dofs it gives 20% less fill than AMD and, with the Γ3 block appended last, a 2x faster
    // factorization (AMD's ordering lets the trailing block fill in far more).
    c.nmethods = 1;
    c.method[0].ordering = CHOLMOD_NESDIS;
    cholmod_factor* LII = cholmod_analyze(&AII, &c);
    if (!LII) throw Error("condensation: CHOLMOD analysis failed", EXIT_INTERNAL);
    std::copy_n(static_cast<int*>(LII->Perm), nI, perm.begin());
    cholmod_free_factor(&LII, &c);
  }
  // 2. The condensed unknowns last, in their own order. CHOLMOD's etree postordering improves the
  //    supernodes (≈2x faster factorization at 525k dofs) and in practice keeps the trailing block
  //    in place — but it may reorder, so it is verified and, if it moved C, redone without it.
  std::iota(perm.begin() + nI, perm.end(), static_cast<int>(nI));
  const int nmethods = c.nmethods, postorder = c.postorder, ordering = c.method[0].ordering;
  c.nmethods = 1;
  c.method[0].ordering = CHOLMOD_GIVEN;
  c.postorder = 1;
  SpMat Kc = K;
  Kc.makeCompressed();
  cholmod_sparse A = view_lower(Kc);
  const auto tail_in_place = [&](const cholmod_factor* F) {
    const auto* P = static_cast<const int*>(F->Perm);
    for (Index j = nI; j < n; ++j)
      if (P[j] != j) return false;
    return true;
  };
  m_impl->L = cholmod_analyze_p(&A, perm.data(), nullptr, 0, &c);
  if (m_impl->L && !tail_in_place(m_impl->L)) {
    cholmod_free_factor(&m_impl->L, &c);
    c.postorder = 0;
    m_impl->L = cholmod_analyze_p(&A, perm.data(), nullptr, 0, &c);
  }
  c.nmethods = nmethods;
  c.postorder = postorder;
  c.method[0].ordering = ordering;
  if (!m_impl->L) throw Error("condensation: CHOLMOD analysis failed", EXIT_INTERNAL);
  m_t_analyze = since(t0);

  t0 = clk::now();
  cholmod_factorize(&A, m_impl->L, &c);
  cholmod_factor* L = m_impl->L;
  if (c.status == CHOLMOD_NOT_POSDEF || L->minor < static_cast<size_t>(n))
    throw Error("condensation: the stiffness is not positive definite (is the body clamped on Γ1?)",
                EXIT_NOT_CONVERGED);
  m_t_factor = since(t0);

  // 3. S = L_CC L_CCᵀ from the trailing block of the supernodal factor. Supernode s holds columns
  //    super[s]..super[s+1]−1 as a dense column-major block with rows s[pi[s]..pi[s+1]) stored at x[px[s]].
  t0 = clk::now();
  if (!L->is_super) throw Error("condensation: expected a supernodal factor", EXIT_INTERNAL);
  Mat LCC = Mat::Zero(m, m);
  const auto* super = static_cast<const int*>(L->super);
  const auto* pi = static_cast<const int*>(L->pi);
  const auto* px = static_cast<const int*>(L->px);
  const auto* rows = static_cast<const int*>(L->s);
  const auto* x = static_cast<const double*>(L->x);
  for (size_t s = 0; s < L->nsuper; ++s) {
    const int k1 = super[s], k2 = super[s + 1];
    if (k2 <= nI) continue;
    const int nsrow = pi[s + 1] - pi[s];
    for (int j = std::max<int>(k1, static_cast<int>(nI)); j < k2; ++j)
      for (int r = j - k1; r < nsrow; ++r) {  // rows at or below the diagonal
        const int row = rows[pi[s] + r];
        if (row >= nI) LCC(row - nI, j - nI) = x[px[s] + static_cast<size_t>(j - k1) * nsrow + r];
      }
  }
  m_S = LCC.triangularView<Eigen::Lower>() * LCC.transpose();
  m_t_schur = since(t0);
  m_nnz = static_cast<double>(c.lnz);

  m_y = m_impl->solve(f);
  m_const = -0.5 * f.dot(m_y);
}

Condensation::~Condensation() = default;

Vec Condensation::solve(const Vec& b) const { return m_impl->solve(b); }

Vec Condensation::recover(const Vec& x_C, double load_scale) const {
  const Index n = m_y.size(), m = this->m();
  Vec rhs = Vec::Zero(n);
  rhs.tail(m) = m_S * (x_C - load_scale * m_y.tail(m));
  Vec x = load_scale * m_y + m_impl->solve(rhs);
  x.tail(m) = x_C;  // exact, not up to the solve's round-off
  return x;
}

}  // namespace hemicontact
