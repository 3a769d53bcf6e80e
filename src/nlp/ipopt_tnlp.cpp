#include "nlp/ipopt_tnlp.hpp"

#include <hemicontact/core/error.hpp>
#include <hemicontact/core/interrupt.hpp>
#include <hemicontact/core/log.hpp>

#include <cmath>
#include <iomanip>
#include <string>
#include <utility>

namespace hemicontact {

IpoptTnlp::IpoptTnlp(const NlpProblem& problem, Setup setup) : m_problem(problem), m_setup(std::move(setup)) {
  const Index n = problem.f->size();
  const SpMat& pattern = problem.f->hessian_pattern();
  if (pattern.rows() != n || pattern.cols() != n)
    throw Error("ipopt: Hessian pattern is " + std::to_string(pattern.rows()) + "x" + std::to_string(pattern.cols()) +
                    ", expected " + std::to_string(n) + "x" + std::to_string(n),
                EXIT_INTERNAL);
  // Ipopt reads each symmetric entry once; a strictly-upper entry would be silently added to the
  // wrong half, so the lower-triangle contract is checked here rather than trusted.
  for (int k = 0; k < pattern.outerSize(); ++k)
    for (SpMat::InnerIterator it(pattern, k); it; ++it) {
      if (it.row() < it.col())
        throw Error("ipopt: Hessian pattern has an upper-triangle entry (" + std::to_string(it.row()) + ", " +
                        std::to_string(it.col()) + ")",
                    EXIT_INTERNAL);
      ++m_nnz_h;
    }
  m_H = pattern;  // the objective fills values in place on this exact pattern
  m_x.resize(n);
  m_g.resize(n);
}

void IpoptTnlp::update_x(Ipopt::Index n, const Ipopt::Number* x, bool new_x) {
  // new_x == false promises x equals the previous call's point (IpTNLP.hpp), so the copy and the
  // cached f/∇f stay valid; Ipopt asks for f and ∇f at the same point at almost every iterate.
  if (!new_x && m_have_x) return;
  m_x = Eigen::Map<const Vec>(x, n);
  m_have_x = true;
  m_have_f = m_have_g = false;
}

bool IpoptTnlp::get_nlp_info(Ipopt::Index& n, Ipopt::Index& m, Ipopt::Index& nnz_jac_g, Ipopt::Index& nnz_h_lag,
                             IndexStyleEnum& index_style) {
  n = static_cast<Ipopt::Index>(m_problem.f->size());
  m = 0;  // bounds only (docs/model.md §2)
  nnz_jac_g = 0;
  nnz_h_lag = m_nnz_h;
  index_style = TNLP::C_STYLE;  // 0-based, as Eigen
  return true;
}

bool IpoptTnlp::get_bounds_info(Ipopt::Index n, Ipopt::Number* x_l, Ipopt::Number* x_u, Ipopt::Index /*m*/,
                                Ipopt::Number* /*g_l*/, Ipopt::Number* /*g_u*/) {
  // Ipopt treats x_l <= nlp_lower_bound_inf (x_u >= nlp_upper_bound_inf) as "no bound"; passing
  // exactly the configured value keeps that true even if a user changed the option.
  for (Ipopt::Index i = 0; i < n; ++i) {
    const double lo = m_problem.lower[i], hi = m_problem.upper[i];
    x_l[i] = (std::isinf(lo) || lo <= m_setup.lower_inf) ? m_setup.lower_inf : lo;
    x_u[i] = (std::isinf(hi) || hi >= m_setup.upper_inf) ? m_setup.upper_inf : hi;
  }
  return true;
}

bool IpoptTnlp::get_scaling_parameters(Ipopt::Number& obj_scaling, bool& use_x_scaling, Ipopt::Index /*n*/,
                                       Ipopt::Number* /*x_scaling*/, bool& use_g_scaling, Ipopt::Index /*m*/,
                                       Ipopt::Number* /*g_scaling*/) {
  obj_scaling = m_setup.obj_scaling;
  use_x_scaling = false;
  use_g_scaling = false;
  return true;
}

bool IpoptTnlp::get_starting_point(Ipopt::Index n, bool init_x, Ipopt::Number* x, bool init_z, Ipopt::Number* z_L,
                                   Ipopt::Number* z_U, Ipopt::Index /*m*/, bool init_lambda,
                                   Ipopt::Number* /*lambda*/) {
  if (init_x) Eigen::Map<Vec>(x, n) = m_setup.x;
  if (init_z) {
    if (m_setup.z_L.size() == n && m_setup.z_U.size() == n) {
      Eigen::Map<Vec>(z_L, n) = m_setup.z_L;
      Eigen::Map<Vec>(z_U, n) = m_setup.z_U;
    } else {
      // No stored multipliers but a warm start was requested: stationarity ∇f = z_L − z_U with
      // z_L, z_U >= 0 suggests z_L = max(∇f, 0), z_U = max(−∇f, 0). Ipopt ignores entries of
      // infinite bounds and pushes the rest up to warm_start_mult_bound_push.
      Vec g;
      m_problem.f->gradient(m_setup.x, g);
      Eigen::Map<Vec>(z_L, n) = g.cwiseMax(0.0);
      Eigen::Map<Vec>(z_U, n) = (-g).cwiseMax(0.0);
    }
  }
  (void)init_lambda;  // m = 0: there are no constraint multipliers to initialise
  return true;
}

bool IpoptTnlp::eval_f(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Number& obj_value) {
  update_x(n, x, new_x);
  if (!m_have_f) {
    m_f = m_problem.f->value(m_x);
    m_have_f = true;
    ++m_result.f_evaluations;
  }
  obj_value = m_f;
  // false is an "evaluation error": in a line search Ipopt cuts the step back instead of failing.
  return std::isfinite(m_f);
}

bool IpoptTnlp::eval_grad_f(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Number* grad_f) {
  update_x(n, x, new_x);
  if (!m_have_g) {
    m_problem.f->gradient(m_x, m_g);
    m_have_g = true;
    ++m_result.g_evaluations;
  }
  Eigen::Map<Vec>(grad_f, n) = m_g;
  return m_g.allFinite();
}

bool IpoptTnlp::eval_g(Ipopt::Index /*n*/, const Ipopt::Number* /*x*/, bool /*new_x*/, Ipopt::Index /*m*/,
                       Ipopt::Number* /*g*/) {
  return true;
}

bool IpoptTnlp::eval_jac_g(Ipopt::Index /*n*/, const Ipopt::Number* /*x*/, bool /*new_x*/, Ipopt::Index /*m*/,
                           Ipopt::Index /*nele_jac*/, Ipopt::Index* /*iRow*/, Ipopt::Index* /*jCol*/,
                           Ipopt::Number* /*values*/) {
  return true;
}

bool IpoptTnlp::eval_h(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Number obj_factor, Ipopt::Index /*m*/,
                       const Ipopt::Number* /*lambda*/, bool /*new_lambda*/, Ipopt::Index nele_hess, Ipopt::Index* iRow,
                       Ipopt::Index* jCol, Ipopt::Number* values) {
  if (nele_hess != m_nnz_h) return false;
  if (values == nullptr) {
    // Structure (hs071: first call, values == nullptr): the pattern in column-major order.
    Ipopt::Index p = 0;
    for (int k = 0; k < m_H.outerSize(); ++k)
      for (SpMat::InnerIterator it(m_H, k); it; ++it, ++p) {
        iRow[p] = static_cast<Ipopt::Index>(it.row());
        jCol[p] = static_cast<Ipopt::Index>(it.col());
      }
    return true;
  }
  // Values, in the same column-major order. With m = 0 the Hessian of the Lagrangian is
  // obj_factor·∇²f (Ipopt's objective scaling arrives through obj_factor).
  update_x(n, x, new_x);
  m_problem.f->hessian(m_x, m_H, Psd::NONE);  // Ipopt corrects the inertia itself
  ++m_result.h_evaluations;
  if (m_H.nonZeros() != m_nnz_h)
    throw Error("ipopt: NlpObjective::hessian() changed the pattern (" + std::to_string(m_H.nonZeros()) +
                    " nonzeros, pattern has " + std::to_string(m_nnz_h) + ")",
                EXIT_INTERNAL);
  Ipopt::Index p = 0;
  for (int k = 0; k < m_H.outerSize(); ++k)
    for (SpMat::InnerIterator it(m_H, k); it; ++it, ++p) values[p] = obj_factor * it.value();
  return true;
}

void IpoptTnlp::finalize_solution(Ipopt::SolverReturn status, Ipopt::Index n, const Ipopt::Number* x,
                                  const Ipopt::Number* z_L, const Ipopt::Number* z_U, Ipopt::Index /*m*/,
                                  const Ipopt::Number* /*g*/, const Ipopt::Number* /*lambda*/, Ipopt::Number obj_value,
                                  const Ipopt::IpoptData* /*ip_data*/, Ipopt::IpoptCalculatedQuantities* /*ip_cq*/) {
  m_result.finalized = true;
  m_result.status = status;
  m_result.x = Eigen::Map<const Vec>(x, n);
  m_result.z_L = Eigen::Map<const Vec>(z_L, n);
  m_result.z_U = Eigen::Map<const Vec>(z_U, n);
  m_result.f = obj_value;
}

bool IpoptTnlp::intermediate_callback(Ipopt::AlgorithmMode mode, Ipopt::Index iter, Ipopt::Number obj_value,
                                      Ipopt::Number /*inf_pr*/, Ipopt::Number inf_du, Ipopt::Number mu,
                                      Ipopt::Number /*d_norm*/, Ipopt::Number regularization_size,
                                      Ipopt::Number alpha_du, Ipopt::Number alpha_pr, Ipopt::Index ls_trials,
                                      const Ipopt::IpoptData* /*ip_data*/,
                                      Ipopt::IpoptCalculatedQuantities* /*ip_cq*/) {
  ++m_result.callbacks;
  if (log_level() >= LogLevel::DEBUG) {  // skip the formatting when nobody reads it
    // inf_pr is omitted: with m = 0 and interior iterates it is always 0. The values are those of
    // Ipopt's own iteration table ('r' marks the restoration phase).
    log_debug() << "ipopt " << std::setw(4) << iter << (mode == Ipopt::RestorationPhaseMode ? "r" : " ")
                << std::scientific << std::setprecision(6) << " f=" << obj_value << std::setprecision(2)
                << " inf_du=" << inf_du << " mu=" << mu << " reg=" << regularization_size << " alpha_du=" << alpha_du
                << " alpha_pr=" << alpha_pr << " ls=" << ls_trials;
  }
  // Stop only for the host's interrupt (core/interrupt.hpp; the backend then throws Interrupted):
  // max_iter is Ipopt's business.
  return !interrupt_requested();
}

}  // namespace hemicontact
