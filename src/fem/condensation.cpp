#include <hemicontact/fem/condensation.hpp>

#include <hemicontact/core/clock.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/core/interrupt.hpp>
#include <hemicontact/core/process.hpp>

#include <cholmod.h>

#include <algorithm>
#include <chrono>
#include <new>
#include <numeric>
#include <string>

// LAPACK (CHOLMOD's own dependency): U Uᵀ of an upper-triangular U, in place (m³/3 flops).
extern "C" void dlauum_(const char* uplo, const int* n, double* a, const int* lda, int* info);

namespace hemicontact {
namespace {

// Every CHOLMOD call's status, checked (an unchecked out-of-memory factorization left L->x null
// and the Schur complement's copy below crashed on it). Out of memory (and "too large", an
// integer overflow of the sizes) is the memory message; anything else an internal error.
void check_condensation_status(const cholmod_common& c, const std::string& phase, Index n) {
  if (c.status == CHOLMOD_OUT_OF_MEMORY || c.status == CHOLMOD_TOO_LARGE)
    memory_error("the condensation's " + phase + " (" + std::to_string(n) + " unknowns)");
  if (c.status < CHOLMOD_OK)
    throw Error("condensation: CHOLMOD " + phase + " failed with status " + std::to_string(c.status), EXIT_INTERNAL);
}

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

// The quotient graph of a symmetric matrix A (compressed, both triangles or the lower one
// stored): consecutive columns of the same pattern (the d unknowns of one node) are one vertex, a
// group. Ordering it and expanding to the unknowns gives d times fewer vertices and d² times fewer
// edges to order, and no worse fill (the unknowns of a node are indistinguishable to the
// elimination). In the lower triangle a node's column j − 1 is {j − 1} and its column j.
struct NodeGraph {
  std::vector<int> first;   // each group's first column (increasing)
  std::vector<int> gp, gi;  // the groups' lower-triangular pattern, compressed by column
  int ng = 0;               // groups
  int ng_interior = 0;      // groups of the columns < nI (a group never straddles nI)
  Index unknowns = 0;       // A's columns
};

NodeGraph quotient_graph(const SpMat& A, Index nI) {
  const int* p = A.outerIndexPtr();
  const int* i = A.innerIndexPtr();
  const Index n = A.cols();
  NodeGraph G;
  G.unknowns = n;
  std::vector<int> group(n);
  for (Index j = 0; j < n; ++j) {
    const bool same_full = j > 0 && p[j + 1] - p[j] == p[j] - p[j - 1] && std::equal(i + p[j - 1], i + p[j], i + p[j]);
    const bool same_lower = j > 0 && p[j] - p[j - 1] == p[j + 1] - p[j] + 1 && i[p[j - 1]] == j - 1 &&
                            std::equal(i + p[j - 1] + 1, i + p[j], i + p[j]);
    const bool same = j != nI && (same_full || same_lower);
    if (!same) G.first.push_back(static_cast<int>(j));
    group[j] = static_cast<int>(G.first.size()) - 1;
    if (j + 1 == nI) G.ng_interior = static_cast<int>(G.first.size());
  }
  G.ng = static_cast<int>(G.first.size());
  G.gp.assign(G.ng + 1, 0);
  G.gi.reserve(static_cast<size_t>(A.nonZeros() / std::max<Index>(1, n / std::max(1, G.ng))));
  for (int g = 0; g < G.ng; ++g) {
    int last = -1;
    for (int k = p[G.first[g]]; k < p[G.first[g] + 1]; ++k) {
      const int h = group[i[k]];
      if (h >= g && h != last) G.gi.push_back(h), last = h;  // rows sorted, so groups too
    }
    G.gp[g + 1] = static_cast<int>(G.gi.size());
  }
  return G;
}

// A pattern-only cholmod_sparse view of the graph's first @p ng groups (lower triangle); @p gp and
// @p gi receive the leading block's arrays where ng < G.ng.
cholmod_sparse leading_pattern(const NodeGraph& G, int ng, std::vector<int>& gp, std::vector<int>& gi) {
  gp.assign(ng + 1, 0);
  gi.clear();
  for (int g = 0; g < ng; ++g) {
    for (int k = G.gp[g]; k < G.gp[g + 1] && G.gi[k] < ng; ++k) gi.push_back(G.gi[k]);
    gp[g + 1] = static_cast<int>(gi.size());
  }
  cholmod_sparse Q{};
  Q.nrow = Q.ncol = ng;
  Q.nzmax = gi.size();
  Q.p = gp.data();
  Q.i = gi.data();
  Q.stype = -1;
  Q.itype = CHOLMOD_INT;
  Q.xtype = CHOLMOD_PATTERN;
  Q.dtype = CHOLMOD_DOUBLE;
  Q.sorted = 1;
  Q.packed = 1;
  return Q;
}

// The groups in elimination order. amd: CHOLMOD's constrained AMD (CAMD) on the whole graph with
// the Γ3 groups constrained last, so that the interior's order counts the fill its elimination
// makes in the Γ3 columns; AMD on the interior alone does not see them (a random 104 × 13 strip
// with Γ3 along its bottom: 2.3e7 against 1.0e7 predicted flops, 172k against 120k nonzeros).
// nesdis (METIS separators + CAMD) and metis order the interior's graph alone.
std::vector<int> order_groups(const NodeGraph& G, const std::string& method, cholmod_common& c) {
  std::vector<int> gp, gi;
  const bool whole = method == "amd";
  cholmod_sparse Q = leading_pattern(G, whole ? G.ng : G.ng_interior, gp, gi);
  std::vector<int> P(Q.ncol);
  bool ok;
  if (method == "amd") {
    std::vector<int> member(G.ng, 0);
    std::fill(member.begin() + G.ng_interior, member.end(), 1);
    ok = cholmod_camd(&Q, nullptr, 0, member.data(), P.data(), &c) != 0;
  } else if (method == "nesdis") {
    std::vector<int> cparent(Q.ncol), cmember(Q.ncol);
    ok = cholmod_nested_dissection(&Q, nullptr, 0, P.data(), cparent.data(), cmember.data(), &c) >= 0;
  } else if (method == "metis") {
    ok = cholmod_metis(&Q, nullptr, 0, /*postorder=*/0, P.data(), &c) != 0;
  } else {
    throw Error("condensation: unknown ordering '" + method + "' (expected auto, amd, metis or nesdis)", EXIT_INPUT);
  }
  check_condensation_status(c, "ordering", G.unknowns);
  if (!ok) throw Error("condensation: CHOLMOD ordering failed", EXIT_INTERNAL);
  return P;
}

// Fill-reducing order of the interior unknowns (the columns < nI of the symmetric A, its lower
// triangle or both stored) on the node graph, the Γ3 unknowns (≥ nI) to follow. "auto", by
// measurement (fig2 scene 'right' mesh, 3D box scene; ordering + symbolic / numeric factorization /
// peak memory of the whole run):
//   2D n = 256  (66k nodes):  AMD 0.05 / 0.43 s;  NESDIS 0.24 / 0.39 s (dof graph: 0.29 / 0.37 s)
//   2D n = 1024 (1.05M nodes): AMD 1.6 / 15.6 s, 4.5 GB;  NESDIS 5.9 / 10.7 s, 4.0 GB
//   3D n = 24   (15k nodes):  AMD 0.06 / 2.16 s, 1.6 GB;  NESDIS (dof graph) 0.15 / 1.08 s, 0.65 GB
//   whole runs, 2026-11-29: 2D n = 512 NESDIS 2.9 s, 707 MB, METIS 2.9 s, 691 MB; n = 1024
//   NESDIS 14.9 s, 2.98 GB, METIS 14.8 s, 2.86 GB; 3D n = 24 the same time and memory
// so AMD for small 2D meshes, where its cheap analysis wins, METIS for large 2D meshes, NESDIS for
// 3D, where their smaller fill does. The unknowns per vertex (n/ng) tell 2D from 3D. Only the
// permutation is wanted, so the ordering routines are called directly: cholmod_analyze on the
// graph would also compute its symbolic factorization, which is thrown away.
std::vector<int> interior_ordering(const SpMat& A, Index nI, std::string& method, cholmod_common& c) {
  const NodeGraph G = quotient_graph(A, nI);
  const bool three_d = static_cast<double>(A.cols()) / std::max(G.ng, 1) > 2.5;
  if (method == "auto") method = three_d ? "nesdis" : G.ng_interior > 200000 ? "metis" : "amd";
  const std::vector<int> P = order_groups(G, method, c);
  std::vector<int> perm;
  perm.reserve(nI);
  for (const int g : P) {
    if (g >= G.ng_interior) continue;  // a Γ3 group (CAMD puts them last)
    const int end = g + 1 < G.ng ? G.first[g + 1] : static_cast<int>(G.unknowns);
    for (int j = G.first[g]; j < end; ++j) perm.push_back(j);
  }
  return perm;
}

// cholmod_factorize's steps for a lower triangle and a permuted supernodal factor, with the
// permuted copy of K made first and the intermediate one given back before the numeric work:
// cholmod_factorize_p permutes a lower triangle by two transposes, triu(PAPᵀ) and then its
// transpose tril(PAPᵀ), and frees the first only as the factorization starts; its arrays (below
// the 32 MB mmap threshold, core/process.cpp) stayed resident through the factorization, whose
// end, the whole factor written, is the run's peak. fig2 n = 512: one copy of K's lower triangle,
// ~47 MB, off that peak (docs/performance.md).
void factorize_with_one_copy(cholmod_sparse& A, cholmod_factor* L, cholmod_common& c, Index n) {
  cholmod_sparse* upper = cholmod_ptranspose(&A, 2, static_cast<int*>(L->Perm), nullptr, 0, &c);  // triu(PAPᵀ)
  cholmod_sparse* lower = upper ? cholmod_ptranspose(upper, 2, nullptr, nullptr, 0, &c) : nullptr;  // tril(PAPᵀ)
  cholmod_free_sparse(&upper, &c);
  check_condensation_status(c, "factorization", n);
  if (!lower) throw Error("condensation: CHOLMOD could not permute the matrix", EXIT_INTERNAL);
  hand_back_freed_memory(n);
  double zero[2] = {0, 0};
  cholmod_super_numeric(lower, nullptr, zero, L, &c);
  cholmod_free_sparse(&lower, &c);
}

// S = L Lᵀ for the lower-triangular trailing block L of the factor, in m³/3 flops (LAPACK's
// dlauum) instead of the m³ of a triangular × dense product, and no m × m temporary: with J the
// exchange matrix, U = J L J is upper triangular and J (U Uᵀ) J = L Lᵀ. At m = 258 (a random
// study's 128-cell strip) this is 0.3 ms instead of 1.3 ms of a 23 ms process.
// S is L's size already (allocated where a failure names the memory).
void schur_from_factor(const Mat& L, Mat& S) {
  const int m = static_cast<int>(L.rows());
  S = L.reverse();  // J L J: upper triangular
  int info = 0;
  if (m > 0) dlauum_("U", &m, S.data(), &m, &info);
  if (info != 0) throw Error("condensation: LAPACK dlauum failed with info " + std::to_string(info), EXIT_INTERNAL);
  S.reverseInPlace();  // its lower triangle is now L Lᵀ's
  for (int j = 1; j < m; ++j)
    for (int i = 0; i < j; ++i) S(i, j) = S(j, i);
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
  Mat LCC;  // the factor's trailing m×m block (lower triangular): S = L_CC L_CCᵀ
  Vec solve(const Vec& b, int system = CHOLMOD_A) {
    cholmod_dense B{};
    B.nrow = b.size();
    B.ncol = 1;
    B.nzmax = b.size();
    B.d = b.size();
    B.x = const_cast<double*>(b.data());
    B.xtype = CHOLMOD_REAL;
    B.dtype = CHOLMOD_DOUBLE;
    cholmod_dense* X = cholmod_solve(system, L, &B, &c);
    check_condensation_status(c, "solve", b.size());
    if (!X) throw Error("condensation: CHOLMOD solve failed", EXIT_INTERNAL);
    Vec x = Eigen::Map<Vec>(static_cast<double*>(X->x), b.size());
    cholmod_free_dense(&X, &c);
    return x;
  }
};

Condensation::Condensation(const SpMat& K, const Vec& f, Index m, const std::string& ordering)
    : Condensation(K, m, ordering) {
  factorize(K, f);
}

Condensation::Condensation(const SpMat& K, Index m, const std::string& ordering) : m_impl(std::make_unique<Impl>()) {
  const Index n = K.rows(), nI = n - m;
  if (m < 0 || m > n) throw Error("condensation: bad number of condensed unknowns", EXIT_INTERNAL);
  m_m = m;
  cholmod_common& c = m_impl->c;
  c.supernodal = CHOLMOD_SUPERNODAL;
  if (n >= MEMORY_BOUND_UNKNOWNS) {
    // A milder relaxed amalgamation than CHOLMOD's default (nrelax 4, 16, 48; zrelax 0.8, 0.1,
    // 0.05): fewer explicit zeros in the supernodes. fig2 n = 512, METIS: peak 721 → 691 MB at
    // +0.03 s (of 2.9 s); n = 256, AMD: 188 → 179 MB at +0.01 s; the 3D box at n = 24: −4 MB, same
    // time. Small matrices keep the default: a random scene of 4 128 unknowns factorized in 5.5
    // instead of 4.4 ms (2026-11-29, docs/performance.md). No relaxation at all: +0.4 s at n = 512.
    const int nrelax[3] = {4, 8, 16};
    const double zrelax[3] = {0.5, 0.05, 0.02};
    std::copy(nrelax, nrelax + 3, c.nrelax);
    std::copy(zrelax, zrelax + 3, c.zrelax);
  }
  const auto t0 = clk::now();

  // 1. Fill-reducing ordering of the interior block alone, on its node graph.
  // K is read in place (a view): a compressed copy only if the caller's K is not compressed.
  SpMat K_compressed;
  if (!K.isCompressed()) {
    K_compressed = K;
    K_compressed.makeCompressed();
  }
  const SpMat& Kc = K.isCompressed() ? K : K_compressed;
  std::vector<int> perm(n);
  if (nI > 0) {
    m_ordering = ordering;
    const std::vector<int> pI = interior_ordering(Kc, nI, m_ordering, c);
    std::copy(pI.begin(), pI.end(), perm.begin());
  }
  // 2. The condensed unknowns last, in their own order. CHOLMOD's etree postordering improves the
  //    supernodes (≈2x faster factorization at 525k dofs) and in practice keeps the trailing block
  //    in place — but it may reorder, so it is verified and, if it moved C, redone without it.
  std::iota(perm.begin() + nI, perm.end(), static_cast<int>(nI));
  const int nmethods = c.nmethods, postorder = c.postorder, saved_ordering = c.method[0].ordering;
  c.nmethods = 1;
  c.method[0].ordering = CHOLMOD_GIVEN;
  c.postorder = 1;
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
  c.method[0].ordering = saved_ordering;
  check_condensation_status(c, "analysis", n);
  if (!m_impl->L) throw Error("condensation: CHOLMOD analysis failed", EXIT_INTERNAL);
  // The analysis's own prediction of the numeric factorization (CHOLMOD Common: lnz, fl).
  m_nnz = static_cast<double>(c.lnz);
  m_flops = static_cast<double>(c.fl);
  m_t_analyze = since(t0);
}

void Condensation::factorize(const SpMat& K, const Vec& f) {
  const Index n = K.rows(), m = m_m, nI = n - m;
  if (!m_impl->L || m_impl->L->n != static_cast<size_t>(n) || m_y.size() > 0)
    throw Error("condensation: factorize() needs the analysis of this matrix, once", EXIT_INTERNAL);
  cholmod_common& c = m_impl->c;
  SpMat K_compressed;
  if (!K.isCompressed()) {
    K_compressed = K;
    K_compressed.makeCompressed();
  }
  cholmod_sparse A = view_lower(K.isCompressed() ? K : K_compressed);
  auto t0 = clk::now();
  // The factor is the run's largest array. Freed blocks below the mmap threshold (32 MB, main's
  // mallopt) stay resident in the heap: the assembly's and the analysis's before the factor
  // (65 MB at fig2 n = 512), CHOLMOD's permuted copy of K and its workspaces after it (~85 MB).
  // Handed back to the system on both sides, the process's peak is what is alive, not the sum.
  // (Each call walks the heap: 0.2 ms, a tenth of a small scene's factorization: large ones only.)
  hand_back_freed_memory(n);
  factorize_with_one_copy(A, m_impl->L, c, n);
  hand_back_freed_memory(n);
  cholmod_factor* L = m_impl->L;
  check_condensation_status(c, "factorization", n);
  if (c.status == CHOLMOD_NOT_POSDEF || L->minor < static_cast<size_t>(n))
    throw Error("condensation: the stiffness is not positive definite (is the body clamped on Γ1?)",
                EXIT_NOT_CONVERGED);
  m_t_factor = since(t0);
  // CHOLMOD's factorization cannot be stopped from outside (no callback): a host's interrupt
  // (core/interrupt.hpp) takes effect as soon as it returns, before the Schur complement.
  check_interrupt();
  t0 = clk::now();
  extract_schur(nI, m);
  m_t_schur = since(t0);
  m_y = m_impl->solve(f);
  m_const = -0.5 * f.dot(m_y);
}

// 3. S = L_CC L_CCᵀ from the trailing block of the supernodal factor. Supernode s holds columns
//    super[s]..super[s+1]−1 as a dense column-major block with rows s[pi[s]..pi[s+1]) stored at x[px[s]].
void Condensation::extract_schur(Index nI, Index m) {
  const cholmod_factor* L = m_impl->L;
  if (!L->is_super) throw Error("condensation: expected a supernodal factor", EXIT_INTERNAL);
  Mat& LCC = m_impl->LCC;
  // The two dense m × m blocks (L_CC and S) are what a long Γ3 costs: named when they do not fit.
  try {
    LCC = Mat::Zero(m, m);
    m_S.resize(m, m);
  } catch (const std::bad_alloc&) {
    memory_error("the condensed Γ3 stiffness (two dense " + std::to_string(m) + " x " + std::to_string(m) +
                 " matrices, " + std::to_string(m) + " Γ3 unknowns)");
  }
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
  schur_from_factor(LCC, m_S);
}

Condensation::~Condensation() = default;

Vec Condensation::solve(const Vec& b) const {
  if (m_y.size() == 0) throw Error("condensation: solve() before factorize()", EXIT_INTERNAL);
  return m_impl->solve(b);
}

Vec Condensation::solve_schur(const Vec& b) const {
  const Mat& L = m_impl->LCC;
  Vec x = L.triangularView<Eigen::Lower>().solve(b);
  L.transpose().triangularView<Eigen::Upper>().solveInPlace(x);
  return x;
}

Vec Condensation::recover(const Vec& x_C, double load_scale) const {
  // x = s y + K⁻¹ [0; S d], d = x_C − s y_C. With L Lᵀ = P K Pᵀ, P leaving the trailing block in
  // place (checked at the analysis), the forward half of that solve is known in closed form:
  // L w = [0; L_CC L_CCᵀ d] gives w = [0; L_CCᵀ d] (L_II w_I = 0). Only the backward half
  // z = L⁻ᵀ w and x = Pᵀ z are left: half the cost of a full solve (the polish recovers several
  // candidates per solve).
  const Index n = m_y.size(), m = this->m();
  Vec w = Vec::Zero(n);
  w.tail(m) = m_impl->LCC.triangularView<Eigen::Lower>().transpose() * (x_C - load_scale * m_y.tail(m));
  const Vec z = m_impl->solve(w, CHOLMOD_Lt);
  Vec x = m_impl->solve(z, CHOLMOD_Pt);
  x += load_scale * m_y;
  x.tail(m) = x_C;  // exact, not up to the solve's round-off
  return x;
}

}  // namespace hemicontact
