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
  // CHOLMOD's LLᵀ, supernodal where its flops per factor entry make BLAS-3 pay (CHOLMOD_AUTO:
  // supernodes for 3D and large 2D meshes, simplicial for thin strips, whose factor is a band:
  // the fig2 strip 1000 × 1's ssn 19 → 10 ms).
  Eigen::CholmodDecomposition<SpMat, Eigen::Lower> llt;
  std::string ordering;
  double t_analyze = 0, t_factor = 0;
};

SparseCholesky::SparseCholesky(const std::string& ordering) : m(std::make_unique<Impl>()) {
  if (ordering != "auto" && ordering != "amd" && ordering != "metis" && ordering != "nesdis")
    throw Error("sparse Cholesky: unknown ordering '" + ordering + "' (expected auto, amd, metis or nesdis)",
                EXIT_INPUT);
  m->ordering = ordering;
  // LLᵀ in both modes (a simplicial LDLᵀ would accept an indefinite matrix: a body not clamped on
  // Γ1 must be refused, not solved).
  m->llt.setMode(Eigen::CholmodAuto);
  m->llt.cholmod().final_asis = 0;
  m->llt.cholmod().final_ll = 1;
  m->llt.cholmod().final_super = 1;
}
SparseCholesky::~SparseCholesky() = default;

void SparseCholesky::analyze(const SpMat& A) {
  const auto t0 = std::chrono::steady_clock::now();
  // One ordering, not CHOLMOD's default of trying AMD and then METIS (which doubled the analysis:
  // 31 s at 2.1M dofs); "auto" by the size (AMD_UP_TO).
  const std::string method = m->ordering != "auto" ? m->ordering : A.rows() <= AMD_UP_TO ? "amd" : "nesdis";
  cholmod_common& c = m->llt.cholmod();
  c.nmethods = 1;
  c.method[0].ordering = method == "amd" ? CHOLMOD_AMD : method == "metis" ? CHOLMOD_METIS : CHOLMOD_NESDIS;
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
