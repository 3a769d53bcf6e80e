#pragma once
/// @file ipopt_tnlp.hpp  Ipopt TNLP adapter for a bound-constrained NlpProblem (private header).
///
/// The shape is Ipopt's hs071 example (Ipopt/examples/hs071_cpp): problem sizes in get_nlp_info,
/// bounds in get_bounds_info, the start in get_starting_point, and for each derivative callback
/// the *structure* when the values pointer is null and the *values* otherwise, in the same fixed
/// order. Differences from hs071:
///  - m = 0: the unilateral contact condition u_ν <= g is a variable bound (docs/model.md §2), so
///    eval_g/eval_jac_g are empty;
///  - the Hessian pattern comes from NlpObjective::hessian_pattern() (lower triangle, row >= col,
///    column-major order) and is walked in the same order for structure and values;
///  - results are not printed but kept in IpoptTnlp::Result, read by the backend after the solve.
///
/// Only src/nlp/ipopt_*.cpp include this header; it is compiled only when Ipopt was found.

#include <hemicontact/core/types.hpp>
#include <hemicontact/nlp/nlp_problem.hpp>

#include <IpTNLP.hpp>

namespace hemicontact {

/// @brief An NlpProblem seen through Ipopt's TNLP interface (hs071 shape, m = 0 constraints).
///
/// Owned by an Ipopt::SmartPtr (Ipopt's intrusive reference counting); non-copyable, like every
/// Ipopt ReferencedObject. It references the problem's objective and bounds, which must outlive it.
class IpoptTnlp final : public Ipopt::TNLP {
 public:
  /// What finalize_solution() and the callbacks recorded.
  struct Result {
    bool finalized = false;  ///< finalize_solution() was called (x, z, f below are valid)
    /// Ipopt's algorithm-level verdict (the backend maps the application-level one instead).
    Ipopt::SolverReturn status = Ipopt::INTERNAL_ERROR;
    Vec x;                  ///< final iterate
    Vec z_L;                ///< final lower-bound multipliers (0 where the bound is infinite)
    Vec z_U;                ///< final upper-bound multipliers (0 where the bound is infinite)
    double f = 0.0;         ///< final objective (unscaled)
    int callbacks = 0;      ///< intermediate_callback calls (iterations + 1, iteration 0 included)
    int f_evaluations = 0;  ///< eval_f calls that evaluated the objective
    int g_evaluations = 0;  ///< eval_grad_f calls that evaluated the gradient
    int h_evaluations = 0;  ///< eval_h calls that evaluated the Hessian
  };

  /// How a run starts: everything the backend decides before handing the problem to Ipopt.
  struct Setup {
    Vec x;                     ///< starting point, already projected onto [lower, upper], size n
    Vec z_L;                   ///< lower-bound multipliers for warm_start_init_point (empty: estimate)
    Vec z_U;                   ///< upper-bound multipliers for warm_start_init_point (empty: estimate)
    double obj_scaling = 1.0;  ///< objective factor for nlp_scaling_method = user-scaling
    double lower_inf = -1e19;  ///< value meaning "no lower bound" (Ipopt's nlp_lower_bound_inf)
    double upper_inf = 1e19;   ///< value meaning "no upper bound" (Ipopt's nlp_upper_bound_inf)
  };

  /// @brief Wrap a problem.
  /// @param problem objective and bounds (referenced, must outlive this object)
  /// @param setup   start, warm-start multipliers, scaling and Ipopt's infinity
  /// @throws Error (EXIT_INTERNAL) if the Hessian pattern is not n×n lower triangular.
  IpoptTnlp(const NlpProblem& problem, Setup setup);

  IpoptTnlp(const IpoptTnlp&) = delete;
  IpoptTnlp& operator=(const IpoptTnlp&) = delete;

  /// @return what the run recorded (valid after Ipopt returned).
  const Result& result() const { return m_result; }

  /// @name Ipopt::TNLP interface (see IpTNLP.hpp for the contract of each method)
  ///@{
  /// n unknowns, m = 0 constraints, nnz of the Hessian pattern, C-style (0-based) indices.
  bool get_nlp_info(Ipopt::Index& n, Ipopt::Index& m, Ipopt::Index& nnz_jac_g, Ipopt::Index& nnz_h_lag,
                    IndexStyleEnum& index_style) override;
  /// Variable bounds; ±INF become ∓/± the configured Ipopt infinity.
  bool get_bounds_info(Ipopt::Index n, Ipopt::Number* x_l, Ipopt::Number* x_u, Ipopt::Index m, Ipopt::Number* g_l,
                       Ipopt::Number* g_u) override;
  /// Objective scaling only (user-scaling); x is not scaled and there are no constraints.
  bool get_scaling_parameters(Ipopt::Number& obj_scaling, bool& use_x_scaling, Ipopt::Index n, Ipopt::Number* x_scaling,
                              bool& use_g_scaling, Ipopt::Index m, Ipopt::Number* g_scaling) override;
  /// The projected start; bound multipliers too when warm_start_init_point asks for them.
  bool get_starting_point(Ipopt::Index n, bool init_x, Ipopt::Number* x, bool init_z, Ipopt::Number* z_L,
                          Ipopt::Number* z_U, Ipopt::Index m, bool init_lambda, Ipopt::Number* lambda) override;
  /// f(x); false (an evaluation error Ipopt backtracks from) if it is not finite.
  bool eval_f(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Number& obj_value) override;
  /// ∇f(x); false if any entry is not finite.
  bool eval_grad_f(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Number* grad_f) override;
  /// No constraints (m = 0): nothing to evaluate.
  bool eval_g(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Index m, Ipopt::Number* g) override;
  /// No constraints (m = 0): an empty Jacobian.
  bool eval_jac_g(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Index m, Ipopt::Index nele_jac,
                  Ipopt::Index* iRow, Ipopt::Index* jCol, Ipopt::Number* values) override;
  /// Structure (values == nullptr) or obj_factor·∇²f(x) (lower triangle), same fixed order.
  bool eval_h(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Number obj_factor, Ipopt::Index m,
              const Ipopt::Number* lambda, bool new_lambda, Ipopt::Index nele_hess, Ipopt::Index* iRow,
              Ipopt::Index* jCol, Ipopt::Number* values) override;
  /// Copies x, z_L, z_U and f into result().
  void finalize_solution(Ipopt::SolverReturn status, Ipopt::Index n, const Ipopt::Number* x, const Ipopt::Number* z_L,
                         const Ipopt::Number* z_U, Ipopt::Index m, const Ipopt::Number* g, const Ipopt::Number* lambda,
                         Ipopt::Number obj_value, const Ipopt::IpoptData* ip_data,
                         Ipopt::IpoptCalculatedQuantities* ip_cq) override;
  /// One debug log line per iteration (iter, f, inf_du, mu, regularization); never stops Ipopt.
  bool intermediate_callback(Ipopt::AlgorithmMode mode, Ipopt::Index iter, Ipopt::Number obj_value,
                             Ipopt::Number inf_pr, Ipopt::Number inf_du, Ipopt::Number mu, Ipopt::Number d_norm,
                             Ipopt::Number regularization_size, Ipopt::Number alpha_du, Ipopt::Number alpha_pr,
                             Ipopt::Index ls_trials, const Ipopt::IpoptData* ip_data,
                             Ipopt::IpoptCalculatedQuantities* ip_cq) override;
  ///@}

 private:
  /// Copy Ipopt's x into m_x when it is new, dropping the cached value and gradient.
  void update_x(Ipopt::Index n, const Ipopt::Number* x, bool new_x);

  const NlpProblem& m_problem;  ///< objective and bounds (not owned)
  Setup m_setup;                ///< start, multipliers, scaling, infinity

  Vec m_x;                   ///< the point the caches below belong to
  bool m_have_x = false;     ///< m_x is set
  bool m_have_f = false;     ///< m_f is f(m_x)
  bool m_have_g = false;     ///< m_g is ∇f(m_x)
  double m_f = 0.0;          ///< cached f(m_x)
  Vec m_g;                   ///< cached ∇f(m_x)
  SpMat m_H;                 ///< Hessian values on the fixed pattern (storage reused)
  Ipopt::Index m_nnz_h = 0;  ///< nonzeros of the pattern

  Result m_result;
};

}  // namespace hemicontact
