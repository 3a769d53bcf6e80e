#pragma once
/// @file friction_bound.hpp  Friction bound F_b(u_ν) of the friction law (6), assumptions (15), example (34).
///
/// Friction (6): \f$ |\sigma_\tau| \le F_b(u_\nu) \f$, and \f$ -\sigma_\tau = F_b(u_\nu)\, u_\tau/|u_\tau| \f$
/// where u_τ ≠ 0. The paper assumes (15):
/// \f[ \text{(a)}\ |F_b(r_1) - F_b(r_2)| \le L_{F_b} |r_1 - r_2|, \qquad
///     \text{(c)}\ F_b(r) = 0 \text{ for } r \le 0,\ F_b(r) \ge 0 \text{ for } r \ge 0 . \f]
/// The solver lags F_b: each outer pass freezes \f$ \lambda_i = F_b(u_{\nu,i}) \f$ (docs/model.md §2), so a
/// bound is only ever evaluated at a given u_ν, and uses the EXACT (unmollified) law.
/// L_Fb enters the smallness condition (21).

#include <hemicontact/contact/piecewise_linear_law.hpp>

#include <memory>
#include <string>

namespace hemicontact {

/// @brief Abstract friction bound F_b(r), r = u_ν.
class FrictionBound {
 public:
  /// @brief Virtual destructor: bounds are held through base pointers.
  virtual ~FrictionBound() = default;
  /// @brief The bound \f$ F_b(r) \f$. @param r normal displacement u_ν @return F_b(r) ≥ 0
  virtual double F(double r) const = 0;
  /// @brief Lipschitz constant L_Fb of (15a). @return L_Fb; +INF if F_b is discontinuous
  virtual double lipschitz() const = 0;
  /// @brief Whether F_b varies with u_ν. If false, λ is fixed and the outer fixed-point loop
  /// (docs/model.md §2) needs one pass only. @return true if F_b is not constant
  virtual bool depends_on_u_nu() const = 0;
  /// @brief One-line description for logs and the report. @return description
  virtual std::string describe() const = 0;
};

/// @brief Coulomb friction on the soft layer, (34): \f$ F_b(r) = \mu\, p_\nu(r) \f$.
///
/// p_ν is the exact PiecewiseLinearLaw (not the mollified one): the bound is evaluated at the
/// lagged u_ν, where no derivative of it is needed. (15c) is checked on construction.
class CoulombLayerBound : public FrictionBound {
 public:
  /// @brief Build and validate (15c) for μ p_ν.
  /// @param mu      friction coefficient μ ≥ 0 (finite)
  /// @param p       exact normal law p_ν (not null)
  /// @param context key path for errors, e.g. "contact.friction"
  /// @throws Error (EXIT_INPUT) naming context + ".mu", or context if μ p_ν violates (15c)
  CoulombLayerBound(double mu, std::shared_ptr<const PiecewiseLinearLaw> p,
                    const std::string& context = "contact.friction");
  /// @brief \f$ \mu\, p_\nu(r) \f$ (right limit at a jump of p_ν). @param r u_ν @return F_b(r)
  double F(double r) const override;
  /// @brief \f$ \mu \max_k |s_k| \f$ over the slopes of p_ν; +INF if p_ν jumps (and μ > 0).
  /// @return L_Fb
  double lipschitz() const override;
  /// @brief False only for μ = 0 (then F_b ≡ 0). @return μ > 0
  bool depends_on_u_nu() const override;
  /// @brief e.g. "coulomb_layer F_b = 0.2 p_nu(u_nu) (34), L_Fb = 80". @return description
  std::string describe() const override;
  /// @brief Friction coefficient. @return μ
  double mu() const { return m_mu; }
  /// @brief The normal law the bound is built on. @return exact p_ν
  const PiecewiseLinearLaw& law() const { return *m_law; }

 private:
  double m_mu;                                      ///< μ
  std::shared_ptr<const PiecewiseLinearLaw> m_law;  ///< exact p_ν
};

/// @brief Tresca friction: a given constant slip bound \f$ F_b \equiv g_\tau \f$.
///
/// Deliberately outside (15c): it does not vanish for r ≤ 0 (a separated node still resists
/// slip). It is accepted as the classical Tresca model; since it does not depend on u_ν,
/// one pass of the outer loop solves the problem exactly.
class TrescaBound : public FrictionBound {
 public:
  /// @brief @param bound the slip bound ≥ 0 (finite) @param context key path for errors
  /// @throws Error (EXIT_INPUT) naming context + ".bound" if bound < 0 or not finite
  explicit TrescaBound(double bound, const std::string& context = "contact.friction");
  /// @brief @param r u_ν (ignored) @return the constant bound
  double F(double r) const override;
  /// @brief @return 0 (constant)
  double lipschitz() const override;
  /// @brief @return false
  bool depends_on_u_nu() const override;
  /// @brief @return e.g. "tresca F_b = 1"
  std::string describe() const override;
  /// @brief The constant. @return slip bound
  double bound() const { return m_bound; }

 private:
  double m_bound;  ///< the slip bound
};

/// @brief F_b given as a piecewise-linear table (same table rules as PiecewiseLinearLaw).
class TableBound : public FrictionBound {
 public:
  /// @brief Build and validate (15c).
  /// @param table   F_b as a piecewise-linear function of u_ν
  /// @param context key path for errors, e.g. "contact.friction"
  /// @throws Error (EXIT_INPUT) naming context if the table violates (15c)
  explicit TableBound(PiecewiseLinearLaw table, const std::string& context = "contact.friction");
  /// @brief Table value (right limit at a jump). @param r u_ν @return F_b(r)
  double F(double r) const override;
  /// @brief max |slope|; +INF if the table jumps. @return L_Fb
  double lipschitz() const override;
  /// @brief False only if the table is identically zero. @return whether F_b varies
  bool depends_on_u_nu() const override;
  /// @brief @return "table F_b: " + the table's description
  std::string describe() const override;
  /// @brief The table. @return piecewise-linear F_b
  const PiecewiseLinearLaw& table() const { return m_table; }

 private:
  PiecewiseLinearLaw m_table;  ///< F_b
};

/// @brief Check (15c) for \f$ F_b = \text{scale}\cdot f \f$, f piecewise linear: F_b = 0 on r ≤ 0
/// (slope_left = 0, zero values at breakpoints ≤ 0 and on both sides of 0) and F_b ≥ 0 on r ≥ 0
/// (nonnegative one-sided values at breakpoints > 0, slope_right ≥ 0). Exact, since F_b is
/// linear between the checked points.
/// @param f       the piecewise-linear function
/// @param scale   factor (μ for (34), 1 for a table), ≥ 0
/// @param context key path in the message, e.g. "contact.friction"
/// @throws Error (EXIT_INPUT), e.g. "contact.friction: F_b(-0.1) = 0.3 but (15c) requires F_b(r) = 0 for r <= 0"
void check_friction_bound_15c(const PiecewiseLinearLaw& f, double scale, const std::string& context);

}  // namespace hemicontact
