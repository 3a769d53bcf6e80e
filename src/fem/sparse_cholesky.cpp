#include <hemicontact/fem/sparse_cholesky.hpp>

#include <hemicontact/core/clock.hpp>
#include <hemicontact/core/error.hpp>

#include <Eigen/CholmodSupport>

#include <chrono>
#include <string>

namespace hemicontact {
namespace {

// Eigen's wrapper reports every CHOLMOD failure as NumericalIssue (and analyzePattern none at
// all: a null factor then crashed factorize). CHOLMOD's own status tells "out of memory" (and
// "problem too large": an integer overflow of the sizes) from "not positive definite".
void check_cholesky_status(const cholmod_common& c, const char* phase, Index n) {
  if (c.status == CHOLMOD_OUT_OF_MEMORY || c.status == CHOLMOD_TOO_LARGE)
    memory_error(std::string("the sparse Cholesky ") + phase + " (" + std::to_string(n) + " unknowns)");
  if (c.status < CHOLMOD_OK)
    throw Error(std::string("sparse Cholesky ") + phase + ": CHOLMOD failed with status " + std::to_string(c.status),
                EXIT_INTERNAL);
}

}  // namespace

struct SparseCholesky::Impl {
  // Supernodal LLᵀ: the BLAS-3 supernodes are what makes CHOLMOD fast with OpenBLAS.
  Eigen::CholmodSupernodalLLT<SpMat, Eigen::Lower> llt;
  double t_analyze = 0, t_factor = 0;
};

SparseCholesky::SparseCholesky() : m(std::make_unique<Impl>()) {
  // One ordering, nested dissection (NESDIS), instead of CHOLMOD's default of trying AMD and then
  // METIS: on FE meshes ND gives the least fill, and trying both doubled the analysis time
  // (31 s at 2.1M dofs). The same ordering as the condensation, so the yardstick is fair.
  cholmod_common& c = m->llt.cholmod();
  c.nmethods = 1;
  c.method[0].ordering = CHOLMOD_NESDIS;
}
SparseCholesky::~SparseCholesky() = default;

void SparseCholesky::analyze(const SpMat& A) {
  const auto t0 = std::chrono::steady_clock::now();
  m->llt.analyzePattern(A);
  check_cholesky_status(m->llt.cholmod(), "analysis", A.rows());
  m->t_analyze = since(t0);
}

void SparseCholesky::factorize(const SpMat& A) {
  const auto t0 = std::chrono::steady_clock::now();
  m->llt.factorize(A);
  m->t_factor = since(t0);
  check_cholesky_status(m->llt.cholmod(), "factorization", A.rows());
  if (m->llt.info() != Eigen::Success)
    throw Error("sparse Cholesky: the matrix is not positive definite (is the body clamped on Γ1?)",
                EXIT_NOT_CONVERGED);
}

void SparseCholesky::compute(const SpMat& A) {
  analyze(A);
  factorize(A);
}

Vec SparseCholesky::solve(const Vec& b) const {
  Vec x = m->llt.solve(b);
  // A failed cholmod_solve leaves x unset and says so only through info() and the status.
  check_cholesky_status(m->llt.cholmod(), "solve", b.size());
  if (m->llt.info() != Eigen::Success) throw Error("sparse Cholesky solve: CHOLMOD failed", EXIT_INTERNAL);
  return x;
}
double SparseCholesky::analyze_seconds() const { return m->t_analyze; }
double SparseCholesky::factorize_seconds() const { return m->t_factor; }

}  // namespace hemicontact
