#pragma once
/// @file normal_law.hpp  Abstract normal-compliance law of the soft layer (paper eqs. (5), (13), (33)).
///
/// The soft layer reacts with ξ_ν ∈ ∂j_ν(u_ν) (Clarke subdifferential), where
/// \f[ j_\nu(r) = \int_0^r p_\nu(s)\,ds \qquad (33), \f]
/// so every law is described by its potential j_ν, the reaction p_ν = j_ν′ and its slope j_ν″.
/// Like ipc-toolkit's `Barrier`, a law is a 1-D object with closed-form derivatives; the nodal
/// energy kernels (energy/normal_compliance_energy) call it at r = u_ν,i.

#include <string>

namespace hemicontact {

/// @brief A closed interval [lo, hi] of reals (lo ≤ hi); a point when lo == hi.
struct Interval {
  double lo;  ///< lower end
  double hi;  ///< upper end
};

/// @brief Abstract normal law j_ν of the soft layer, with p_ν = j_ν′ and its slope.
///
/// Conventions shared by all implementations:
///  - \f$ j(0) = 0 \f$ (eq. (33));
///  - where p_ν jumps, p(r) is the right limit and dp(r) is the right slope (a.e. derivative);
///  - subdifferential(r) is Clarke's \f$\partial j_\nu(r) = [\min(p^-,p^+), \max(p^-,p^+)]\f$
///    (the one-sided limits of p_ν at r), a point where p_ν is continuous.
class NormalLaw {
 public:
  /// @brief Virtual destructor: laws are held through base pointers.
  virtual ~NormalLaw() = default;

  /// @brief Potential \f$ j_\nu(r) = \int_0^r p_\nu(s)\,ds \f$ (33).
  /// @param r normal displacement u_ν (positive = into the foundation)
  /// @return j_ν(r); j_ν(0) = 0
  virtual double j(double r) const = 0;

  /// @brief Layer reaction \f$ p_\nu(r) = j_\nu'(r) \f$ (right limit where p_ν jumps).
  /// @param r normal displacement u_ν
  /// @return p_ν(r)
  virtual double p(double r) const = 0;

  /// @brief Slope \f$ p_\nu'(r) = j_\nu''(r) \f$ (right slope at a kink; jumps contribute nothing).
  /// @param r normal displacement u_ν
  /// @return p_ν′(r)
  virtual double dp(double r) const = 0;

  /// @brief Clarke subdifferential ∂j_ν(r): the interval between the one-sided limits of p_ν.
  /// @param r normal displacement u_ν
  /// @return [lo, hi]; lo == hi == p(r) where p_ν is continuous
  virtual Interval subdifferential(double r) const = 0;

  /// @brief One-sided Lipschitz constant α_jν of ∂j_ν, assumption (13)(d):
  /// \f[ j_\nu^0(r_1; r_2-r_1) + j_\nu^0(r_2; r_1-r_2) \le \alpha_{j_\nu} |r_1-r_2|^2, \f]
  /// equivalently \f$(\xi_1-\xi_2)(r_2-r_1) \le \alpha |r_1-r_2|^2\f$ for \f$\xi_i \in \partial j_\nu(r_i)\f$.
  /// It enters the smallness condition (21).
  /// @return max(0, −(most negative slope of p_ν)); +INF if p_ν has a downward jump
  virtual double one_sided_lipschitz() const = 0;

  /// @brief One-line human-readable description (for logs and the JSON report).
  /// @return e.g. "piecewise-linear p_nu: breakpoints [0, 0.1, 0.15], slopes 0 | 100 | -100 | 400"
  virtual std::string describe() const = 0;
};

}  // namespace hemicontact
