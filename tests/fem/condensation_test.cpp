#include <hemicontact/fem/condensation.hpp>
#include <hemicontact/fem/sparse_cholesky.hpp>

#include <hemicontact/core/error.hpp>
#include "../support/expect_error.hpp"

#include <gtest/gtest.h>

// The test target does not see CHOLMOD's include folder (a private dependency of the library).
#if __has_include(<SuiteSparse_config.h>)
#include <SuiteSparse_config.h>
#else
#include <suitesparse/SuiteSparse_config.h>
#endif

#include <cmath>
#include <cstdlib>
#include <random>
#include <string>

using namespace hemicontact;

namespace {
// SPD 2D Laplacian-like matrix (5-point stencil + shift) with random couplings: a sparse SPD matrix
// with the fill structure of a mesh.
SpMat test_matrix(int nx, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(0.5, 1.5);
  const int n = nx * nx;
  Triplets t;
  for (int j = 0; j < nx; ++j)
    for (int i = 0; i < nx; ++i) {
      const int a = j * nx + i;
      double diag = 0.1;
      const auto link = [&](int b) {
        const double w = U(rng);
        t.emplace_back(a, b, -w);
        t.emplace_back(b, a, -w);
        t.emplace_back(b, b, w);
        diag += w;
      };
      if (i + 1 < nx) link(a + 1);
      if (j + 1 < nx) link(a + nx);
      t.emplace_back(a, a, diag);
    }
  SpMat K(n, n);
  K.setFromTriplets(t.begin(), t.end());
  return K;
}
}  // namespace

// S from the factor's trailing block must equal the textbook K_CC − K_CI K_II⁻¹ K_IC (computed
// densely here), y = K⁻¹ f, and recover() must give the constrained minimizer: interior rows of
// K x − f vanish. Round-off of a Cholesky solve is ~ cond·ε; with cond ~ 1e3 here, 1e-10 is safe.
TEST(Condensation, SchurComplementFromTrailingBlock) {
  const SpMat K = test_matrix(12, 3);
  const Index n = K.rows(), m = 17;
  Vec f = Vec::LinSpaced(n, -1.0, 2.0);
  Condensation cond(K, f, m);
  const Mat Kd = Mat(K);
  const Index nI = n - m;
  const Mat S_ref = Kd.bottomRightCorner(m, m) -
                    Kd.bottomLeftCorner(m, nI) * Kd.topLeftCorner(nI, nI).ldlt().solve(Kd.topRightCorner(nI, m));
  EXPECT_LE((cond.S() - S_ref).cwiseAbs().maxCoeff(), 1e-10 * S_ref.cwiseAbs().maxCoeff());
  const Vec y_ref = Kd.ldlt().solve(f);
  EXPECT_LE((cond.y() - y_ref).cwiseAbs().maxCoeff(), 1e-10 * y_ref.cwiseAbs().maxCoeff());

  const Vec xC = Vec::LinSpaced(m, 0.3, -0.7);
  const Vec x = cond.recover(xC);
  const Vec r = K * x - f;
  EXPECT_LE(r.head(nI).cwiseAbs().maxCoeff(), 1e-10 * f.cwiseAbs().maxCoeff());
  // The trailing residual is the condensed gradient S (x_C − y_C).
  const Vec g = cond.S() * (xC - cond.y_C());
  EXPECT_LE((r.tail(m) - g).cwiseAbs().maxCoeff(), 1e-10 * g.cwiseAbs().maxCoeff());
  // Energy identity: ½xᵀKx − fᵀx = ½dᵀSd − ½fᵀy.
  const double e_full = 0.5 * x.dot(K * x) - f.dot(x);
  const Vec d = xC - cond.y_C();
  EXPECT_NEAR(e_full, 0.5 * d.dot(cond.S() * d) + cond.constant(), 1e-10 * std::abs(e_full));
}

// The ordering changes the factor, never S or y: amd (constrained AMD on the whole graph, the
// condensed unknowns last), metis and nesdis (on the interior's graph) agree to round-off, with a
// boundary row condensed (a grid's last nx unknowns: Γ3 along one side, as on a strip).
TEST(Condensation, EveryOrderingGivesTheSameSchurComplement) {
  const int nx = 14;
  const SpMat K = test_matrix(nx, 5);
  const Vec f = Vec::LinSpaced(K.rows(), 2.0, -1.0);
  const Condensation ref(K, f, nx, "amd");
  EXPECT_EQ(ref.ordering(), "amd");
  EXPECT_GT(ref.predicted_flops(), 0.0);
  for (const char* ordering : {"metis", "nesdis", "auto"}) {
    SCOPED_TRACE(ordering);
    const Condensation other(K, f, nx, ordering);
    EXPECT_LE((other.S() - ref.S()).cwiseAbs().maxCoeff(), 1e-10 * ref.S().cwiseAbs().maxCoeff());
    EXPECT_LE((other.y() - ref.y()).cwiseAbs().maxCoeff(), 1e-10 * ref.y().cwiseAbs().maxCoeff());
  }
}

TEST(Condensation, AllCondensedAndNotPositiveDefinite) {
  const SpMat K = test_matrix(4, 1);
  Condensation all(K, Vec::Ones(K.rows()), K.rows());
  EXPECT_LE((all.S() - Mat(K)).cwiseAbs().maxCoeff(), 1e-12 * Mat(K).cwiseAbs().maxCoeff());
  SpMat bad = K;
  bad.coeffRef(0, 0) = -1.0;
  EXPECT_THROW(Condensation(bad, Vec::Ones(K.rows()), 3), std::exception);
}

// An out-of-memory status of CHOLMOD was once not checked (the Schur complement's copy then
// read a null factor: SIGSEGV). Every allocation CHOLMOD makes goes through SuiteSparse_config's
// functions; here the k-th one fails, for every k until a run needs no failure: each run either
// succeeds or throws the memory Error (exit code 2), and never crashes.
namespace {
long g_allocations_left = -1;  // < 0: never fail
bool allow_one() { return g_allocations_left < 0 || g_allocations_left-- > 0; }
void* failing_malloc(size_t n) { return allow_one() ? std::malloc(n) : nullptr; }
void* failing_calloc(size_t n, size_t m) { return allow_one() ? std::calloc(n, m) : nullptr; }
void* failing_realloc(void* p, size_t n) { return allow_one() ? std::realloc(p, n) : nullptr; }

// Runs @p work with the k-th CHOLMOD allocation failing, k = 0, 1, ...; @return how many runs failed.
template <class Work>
int fail_each_allocation(Work work) {
  auto& cfg = SuiteSparse_config;
  const auto saved_malloc = cfg.malloc_func;
  const auto saved_calloc = cfg.calloc_func;
  const auto saved_realloc = cfg.realloc_func;
  const auto saved_printf = cfg.printf_func;
  cfg.printf_func = nullptr;  // CHOLMOD's own "out of memory" lines: hundreds of them
  cfg.malloc_func = failing_malloc;
  cfg.calloc_func = failing_calloc;
  cfg.realloc_func = failing_realloc;
  int failed = 0;
  for (long k = 0; k < 1000; ++k) {
    g_allocations_left = k;
    bool ok = true;
    try {
      work();
    } catch (const Error& e) {
      ok = false;
      EXPECT_EQ(e.code(), EXIT_INPUT) << "allocation " << k << ": " << e.what();
      EXPECT_NE(std::string(e.what()).find("out of memory in"), std::string::npos) << e.what();
    }
    if (ok) break;  // this run needed fewer than k + 1 allocations: all were tried
    ++failed;
  }
  g_allocations_left = -1;
  cfg.malloc_func = saved_malloc;
  cfg.calloc_func = saved_calloc;
  cfg.realloc_func = saved_realloc;
  cfg.printf_func = saved_printf;
  return failed;
}
}  // namespace

TEST(Condensation, OutOfMemoryIsAnErrorNeverACrash) {
  const SpMat K = test_matrix(10, 5);
  const Vec f = Vec::Ones(K.rows());
  for (const char* ordering : {"amd", "auto"}) {
    SCOPED_TRACE(ordering);
    const int failed = fail_each_allocation([&] {
      Condensation cond(K, f, 12, ordering);
      EXPECT_EQ(cond.recover(cond.y_C()).size(), K.rows());
    });
    EXPECT_GE(failed, 3);  // the ordering, the analysis and the factorization each allocate
  }
}

TEST(SparseCholesky, OutOfMemoryIsAnErrorNeverACrash) {
  const SpMat K = test_matrix(10, 6);
  const int failed = fail_each_allocation([&] {
    SparseCholesky llt;
    llt.compute(K);
    EXPECT_EQ(llt.solve(Vec::Ones(K.rows())).size(), K.rows());
  });
  EXPECT_GE(failed, 3);
}

// Every ordering and both of CHOLMOD's modes (simplicial for a small sparse matrix, supernodal
// for a dense one: CHOLMOD_AUTO's flop rule) solve an SPD system to round-off and refuse an
// indefinite one (the negated graph Laplacian's last diagonal entry): an LLᵀ factor in both
// modes, never an LDLᵀ that would accept it.
TEST(SparseCholesky, EveryOrderingSolvesAndAnIndefiniteMatrixIsRefused) {
  SpMat dense(100, 100);  // dense: flops / nnz(L) ≈ 66 ≥ 40, CHOLMOD takes supernodes
  Triplets t;
  for (int i = 0; i < 100; ++i)
    for (int j = 0; j < 100; ++j) t.emplace_back(i, j, i == j ? 101.0 : 1.0 / (1 + std::abs(i - j)));
  dense.setFromTriplets(t.begin(), t.end());
  for (const SpMat& K : {test_matrix(30, 7), dense}) {
    const Vec b = Vec::LinSpaced(K.rows(), -1.0, 2.0);
    for (const char* ordering : {"auto", "amd", "metis", "nesdis"}) {
      SCOPED_TRACE(ordering);
      SparseCholesky llt(ordering);
      llt.compute(K);
      // Backward error at round-off: cond(K) ≤ ~1e3 here.
      EXPECT_LE((K * llt.solve(b) - b).cwiseAbs().maxCoeff(), 1e-12 * b.cwiseAbs().maxCoeff());
      SpMat bad = K;
      bad.coeffRef(K.rows() - 1, K.rows() - 1) = -1.0;
      SparseCholesky refuse(ordering);
      try {
        refuse.compute(bad);
        ADD_FAILURE() << "an indefinite matrix was factorized";
      } catch (const Error& e) {
        EXPECT_EQ(e.code(), EXIT_NOT_CONVERGED);
        EXPECT_CONTAINS(e.what(), "not positive definite");
      }
    }
  }
  test::expect_input_error([] { SparseCholesky("colamd"); }, {"unknown ordering 'colamd'"});
}
