#pragma once
/// @file piecewise_linear_law.hpp  Exact piecewise-linear normal law p_ν (paper eq. (32)) from a table.
///
/// A table of points (r_k, p_k) with non-decreasing r defines p_ν by linear interpolation; a
/// repeated r (exactly two points) is a jump of p_ν there, and beyond the first/last point p_ν
/// continues with slope_left/slope_right. Internally p_ν is written as
/// \f[ p_\nu(r) = a + b\,r + \sum_k \Delta s_k\,(r-r_k)_+ + \sum_k J_k\,H(r-r_k), \f]
/// with \f$(x)_+ = \max(0,x)\f$, H the right-continuous Heaviside step, a + b r the affine
/// extension of the leftmost piece (b = slope_left), Δs_k the slope change and J_k the jump
/// at the k-th distinct breakpoint. The potential (33) is then exact in closed form:
/// \f[ j_\nu(r) = P(r) - P(0),\quad
///     P(r) = a r + \tfrac{b}{2} r^2 + \sum_k \tfrac{\Delta s_k}{2} (r-r_k)_+^2 + \sum_k J_k (r-r_k)_+ . \f]
/// MollifiedLaw (mollified_law.hpp) smooths exactly these ramps and steps.

#include <hemicontact/contact/normal_law.hpp>

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace hemicontact {

/// @brief Exact piecewise-linear normal law (kinks and jumps kept), e.g. the paper's (32).
///
/// j_ν is C¹ where p_ν is continuous and only Lipschitz at jumps; it is nonconvex wherever a
/// slope is negative (softening, c2 < 0 in (32)). Use it for the certificate (docs/model.md §4) and
/// for the lagged friction bound (34); the NLP sees MollifiedLaw.
class PiecewiseLinearLaw : public NormalLaw {
 public:
  /// A table point (r, p).
  using Point = std::array<double, 2>;

  /// @brief Build p_ν from a table and validate it.
  /// @param points       (r_k, p_k), r non-decreasing, ≥ 1 point, finite; a pair with equal r
  ///                     is a jump (first = left limit, second = right limit); 3+ equal r rejected
  /// @param slope_left   slope of p_ν left of the first point; nullopt → slope of the first
  ///                     segment (0 if all points share one r)
  /// @param slope_right  slope right of the last point; nullopt → slope of the last segment
  ///                     (0 if all points share one r)
  /// @param context      key path used in error messages, e.g. "contact.normal_law"
  /// @throws Error (EXIT_INPUT) naming context + ".points[k]" / ".slope_left" / ".slope_right"
  PiecewiseLinearLaw(std::vector<Point> points, std::optional<double> slope_left, std::optional<double> slope_right,
                     const std::string& context = "contact.normal_law");

  /// @brief The paper's law (32): p_ν = 0 for r ≤ 0, slope c1 on (0, r1], c2 on (r1, r2),
  /// c3 for r ≥ r2, continuous:
  /// \f[ p_\nu(r) = \begin{cases} 0 & r \le 0 \\ c_1 r & 0 < r \le r_1
  ///     \\ c_1 r_1 + c_2 (r - r_1) & r_1 < r < r_2
  ///     \\ c_1 r_1 + c_2 (r_2 - r_1) + c_3 (r - r_2) & r \ge r_2 \end{cases} \qquad (32) \f]
  /// i.e. the table (0,0), (r1, c1 r1), (r2, c1 r1 + c2 (r2 − r1)), slope_left 0, slope_right c3.
  /// @param c1 slope on (0, r1]   @param c2 slope on (r1, r2)   @param c3 slope on [r2, ∞)
  /// @param r1 first kink (> 0)   @param r2 second kink (> r1)
  /// @param context key path for error messages
  /// @return the law
  /// @throws Error (EXIT_INPUT) unless 0 < r1 < r2 and all values are finite
  static PiecewiseLinearLaw paper(double c1, double c2, double c3, double r1, double r2,
                                  const std::string& context = "contact.normal_law");

  /// @brief \f$ j_\nu(r) = P(r) - P(0) \f$, exact (see file comment). @param r u_ν @return j_ν(r)
  double j(double r) const override;
  /// @brief p_ν(r), right-continuous at jumps. @param r u_ν @return p_ν(r) = p_plus(r)
  double p(double r) const override;
  /// @brief Right slope of p_ν at r (jumps ignored: a.e. derivative). @param r u_ν @return p_ν′(r⁺)
  double dp(double r) const override;
  /// @brief [min, max] of p_minus(r), p_plus(r). @param r u_ν @return Clarke ∂j_ν(r)
  Interval subdifferential(double r) const override;
  /// @brief α_jν of (13)(d). @return max(0, −min slope), +INF if some J_k < 0
  double one_sided_lipschitz() const override;
  /// @brief Breakpoints, slopes and jumps in one line. @return description
  std::string describe() const override;

  /// @brief Left limit \f$ p_\nu(r^-) \f$. @param r u_ν @return p_ν(r⁻) (= p(r) off the jumps)
  double p_minus(double r) const;
  /// @brief Right limit \f$ p_\nu(r^+) \f$ (= p(r)). @param r u_ν @return p_ν(r⁺)
  double p_plus(double r) const;

  /// @brief The table as given (after validation). @return points (r_k, p_k)
  const std::vector<Point>& points() const { return m_points; }
  /// @brief Distinct breakpoints r_k, increasing. @return breakpoints
  const std::vector<double>& breakpoints() const { return m_r; }
  /// @brief Table value left of each breakpoint (p_minus at r_k, exact). @return one per breakpoint
  const std::vector<double>& values_left() const { return m_p_left; }
  /// @brief Table value right of each breakpoint (p_plus at r_k, exact). @return one per breakpoint
  const std::vector<double>& values_right() const { return m_p_right; }
  /// @brief Slopes of p_ν on the pieces: [slope_left, segment slopes…, slope_right].
  /// @return breakpoints().size() + 1 slopes
  const std::vector<double>& slopes() const { return m_slopes; }
  /// @brief Slope changes \f$ \Delta s_k \f$ at each breakpoint. @return one per breakpoint
  const std::vector<double>& slope_changes() const { return m_dslope; }
  /// @brief Jumps \f$ J_k = p_\nu(r_k^+) - p_\nu(r_k^-) \f$. @return one per breakpoint
  const std::vector<double>& jumps() const { return m_jump; }
  /// @brief Slope left of the first breakpoint (b in the file comment). @return slope_left
  double slope_left() const { return m_slopes.front(); }
  /// @brief Slope right of the last breakpoint. @return slope_right
  double slope_right() const { return m_slopes.back(); }
  /// @brief Value at r = 0 of the leftmost affine piece extended (a in the file comment).
  /// @return a
  double affine_intercept() const { return m_a; }
  /// @brief Whether p_ν has no jump (then j_ν is C¹). @return true if all J_k == 0
  bool is_continuous() const;

 private:
  /// Unnormalised antiderivative P(r) of p_ν (see file comment).
  double antiderivative(double r) const;
  /// Sum form of p_ν with Heaviside H(0) = @p h_at_zero (1: right limit, 0: left limit).
  double evaluate(double r, double h_at_zero) const;

  std::vector<Point> m_points;    ///< validated table
  std::vector<double> m_r;        ///< distinct breakpoints r_k
  std::vector<double> m_p_left;   ///< p_ν(r_k⁻) from the table
  std::vector<double> m_p_right;  ///< p_ν(r_k⁺) from the table
  std::vector<double> m_slopes;   ///< slope_left, segment slopes, slope_right
  std::vector<double> m_dslope;   ///< Δs_k
  std::vector<double> m_jump;     ///< J_k
  double m_a = 0.0;               ///< intercept of the leftmost affine piece
  double m_P0 = 0.0;              ///< P(0), so that j(0) = 0
  std::string m_origin;           ///< "" or a note such as "paper (32) c1=… "
};

}  // namespace hemicontact
