#pragma once
/// @file status_equations.hpp  The conditions of (22) at one Γ3 node read as equations on a status
/// (docs/model.md §4), stated once for every method that solves them: the polishes on a fixed
/// status (solver/polish.cpp in 3D, the petsc engine's) and the semismooth Newton methods that read
/// the status at every step (ssn: solver/ssn.cpp with CHOLMOD, the petsc engine's with CG + AMG).
///
/// In the node's local frame (unknowns x = (x_ν, x_τ...), r = its rows of K x − f):
///   contact:                 x_ν = g                                         (eq. (5))
///   compliance / separated:  r_ν + w p_ν(x_ν) = 0,   block += w p_ν'(x_ν)    (eq. (32))
///   roller component:        x_τc = 0
///   frictionless here:       r_τ = 0                 (F_b = 0 on u_ν's branch)
///   stick:                   x_τ = 0
///   slip along t:            r_τ + w λ t = 0,        block += w λ (I − t tᵀ)/ρ   (eq. (6));
///                            in 2D t = ±τ is the status itself (slip±), in 3D t = x_τ/|x_τ|
/// with λ = F_b(x_ν); a pinned unknown's row is the pin alone.

#include <hemicontact/check/node_kernels.hpp>

#include <Eigen/Core>

#include <array>

namespace hemicontact {

/// What a node adds to the system: @c force to its rows of K x − f, @c block to its d×d diagonal
/// block of the Jacobian; the unknowns in @c pinned (bit c: local component c) are held at @c pin.
struct NodeRows {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  Eigen::Matrix3d block = Eigen::Matrix3d::Zero();
  unsigned pinned = 0;
  Eigen::Vector3d pin = Eigen::Vector3d::Zero();
  bool singular = false;  ///< a slipping node at x_τ = 0: t is undefined, the status is wrong
  /// @return whether local component @p c is pinned.
  bool is_pinned(int c) const { return (pinned >> c) & 1u; }
};

/// The local components of Γ3 node @p k held by a roller (bit c for τ_c), ContactNodes::fixed_local.
unsigned roller_components(const Model& md, Index k);

/// The rows on a fixed status @p st at the local unknowns @p x (a polish's Newton step).
/// @param frictionless F_b vanishes on the node's branch (node_rules.hpp's frictionless_at)
/// @param rollers roller_components @param delta F_b's slope probe (central difference; F_b is
/// piecewise linear, so this is exact up to round-off far from a kink)
/// @param coupling add the slip force's dependence on x_ν (w F_b'(x_ν) t, an unsymmetric column):
/// exact Newton for an LU solve; left out where CG needs a symmetric matrix
NodeRows status_rows(const NodeData& n, const Eigen::Vector3d& x, const NodeStatus& st, bool frictionless,
                     unsigned rollers, double delta, bool coupling);

/// ssn's reading of a node at an iterate: the statuses by the complementarity functions of the
/// primal-dual active-set method, with c = the node's diagonal of K so that forces and
/// displacements compare in one unit:
///   contact  iff  −(r_ν + w p(x_ν)) + c_ν (x_ν − g) > 0   (every node on the first step: x = 0
///                 has no reaction to read, and the free elastic solve would push Γ3 far through g)
///   stick    iff  |y| ≤ w λ,  y = −r_τ + c_τ x_τ          (or held at stick for one step after a
///                 reversal of its slip, ssn_reversed)
///   slip:    t = y/|y|, ρ = max(|x_τ|, (|y| − wλ)/c_τ) (= |x_τ| at a solution; positive where x_τ
///            is still 0, and no smaller than the slip this step reaches, so x_τ does not overshoot
///            through 0 and flip t every step)
struct SsnReading {
  NodeRows rows;
  /// bit 0 contact, bit 1 stick, 8/16 the 2D slip direction, 32·(the branch of p_ν): a change of
  /// this code between steps is a status change
  int code = 0;
  Eigen::Vector2d slip_dir = Eigen::Vector2d::Zero();  ///< t where the node slides (0 otherwise)
};
SsnReading ssn_reading(const NodeData& n, const Eigen::Vector3d& x, const Eigen::Vector3d& r,
                       const Eigen::Vector3d& diag, bool first_step, bool hold_stick, unsigned rollers);

/// The slip force's dependence on x_ν at a node ssn read as sliding along @p slip_dir with x_ν free:
/// the column w F_b'(x_ν) t on its τ rows (eq. (6) with λ = F_b(x_ν) not held), zero where the
/// node does not slide, x_ν is pinned (@p rd's rows) or F_b does not depend on u_ν. Unsymmetric:
/// ssn adds it only once its statuses cycle (solver/ssn.hpp, SsnCycleWatch), with a Krylov method
/// that takes it (GMRES). @param delta F_b's slope probe (central difference, as status_rows's)
/// @return the entries (τ rows; entry 0 is 0)
Eigen::Vector3d ssn_coupling(const NodeData& n, const Eigen::Vector3d& x, const SsnReading& rd, double delta);

/// The node's part of ssn's merit, the true semismooth residual its line search measures
/// (solver/ssn.hpp): the largest of |r_c + force_c| over the free components and
/// @p diag_scale · |pin_c − x_c| over the pinned ones, with the statuses read at @p x as a step
/// reads them (ssn_reading, not the first step, nothing held). @param r the node's rows of K x − f
double ssn_node_merit(const NodeData& n, const Eigen::Vector3d& x, const Eigen::Vector3d& r,
                      const Eigen::Vector3d& diag, unsigned rollers, double diag_scale);

/// ssn's reversal rule: a sliding node whose step carried x_τ through 0 (x_τ · t < 0: the friction
/// force it was given is more than equilibrium needs) is put at x_τ = 0 and held at stick for the
/// next step. @return true (and @p x's tangential part zeroed) when it reversed.
bool ssn_reversed(const Eigen::Vector2d& slip_dir, int d, Eigen::Vector3d& x);

}  // namespace hemicontact
