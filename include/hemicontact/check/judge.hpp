#pragma once
/// @file judge.hpp  The one judge of an answer: the certificate (docs/model.md §4), the statuses
/// (§3), the Γ3 energy terms and the status counts, as the node kernels (check/node_kernels.hpp)
/// reduced over the nodes and free components one process owns.
///
/// Two passes, each "local parts, then a reduction": the scales (U, F, w̄, max λ, max |ξ|), then the
/// verdict (each residual's max and where, the energy sums, the counts, max u_ν). The reduction is
/// the only thing an engine supplies: none on one process (SerialReduction), MPI_Allreduce on the
/// ranks of the petsc engine (src/petsc). The same judge serves the cholmod engine, every petsc
/// layout, both polishes and the studies.

#include <hemicontact/check/node_kernels.hpp>
#include <hemicontact/problem/reports.hpp>

#include <functional>
#include <vector>

namespace hemicontact {

/// What one process judges of a model: its Γ3 nodes and its free components, and where a
/// residual found there is reported (CertificateResidual::worst).
struct JudgeScope {
  std::vector<Index> nodes;               ///< Γ3 nodes (md.contact indices) this process owns
  std::function<bool(Index v)> owns;      ///< mesh node v is this process's (scales, equilibrium)
  std::function<Index(Index k)> node_at;  ///< where Γ3 node k's residual is reported
  std::function<Index(Index c)> dof_at;   ///< where full component c's residual is reported
};

/// @return the scope of a whole model on one process (every node; residuals at node k, dof c).
JudgeScope whole_model_scope(const Model& md);

/// The first pass's local parts: maxima and sums over the scope.
struct ScaleParts {
  double u_max = 0, f_max = 0, h_max = 0;  ///< max nodal |u|, |f|; the longest edge
  double w_sum = 0, count = 0;             ///< Σ w_i and the number of Γ3 nodes
  double traction_max = 0;                 ///< max(|λ_i|, |ξ_i|)
};

/// The second pass's local parts.
struct VerdictParts {
  std::vector<CertificateResidual> residuals;  ///< feasibility .. equilibrium (certificate.hpp's order)
  double j = 0, friction = 0;                  ///< Σ w j_ν(u_ν), Σ w F_b(u_ν)|u_τ| over the scope
  double u_nu_max = -INF;                      ///< max u_ν over the scope (−∞: no Γ3 node)
  StatusCounts counts{};                       ///< the scope's statuses
};

/// How the parts of all processes are combined. Each call is collective where it is distributed.
struct Reduction {
  virtual ~Reduction() = default;
  virtual void reduce(ScaleParts& p) const = 0;
  virtual void reduce(VerdictParts& p) const = 0;
};
/// One process: the parts are the whole.
struct SerialReduction final : Reduction {
  void reduce(ScaleParts&) const override {}
  void reduce(VerdictParts&) const override {}
};

/// The reduction's rules, for two parts (what MPI_Allreduce does over ranks): max of maxima,
/// sum of sums; a residual's place from the larger value (on a tie the smaller place).
void combine(ScaleParts& into, const ScaleParts& other);
void combine(VerdictParts& into, const VerdictParts& other);

/// The first pass over the scope: @p u full displacement, @p state its Γ3 state.
ScaleParts scale_parts(const Model& md, const Vec& u, const ContactState& state, const JudgeScope& scope);
/// The scales from the reduced parts, into the certificate's scale fields; @return them.
JudgeScales judge_scales(const ScaleParts& all, CertificateReport& r);
/// The second pass over the scope: node terms, equilibrium on the owned free components away from
/// Γ3 (|R_c|/F), energies and counts (statuses from @p status, one per Γ3 node of the model).
VerdictParts verdict_parts(const Model& md, const ContactState& state, const std::vector<NodeStatus>& status,
                           const JudgeScales& sc, double status_tol, const JudgeScope& scope);

/// @return every Γ3 node's status (one per node of @p state) at the scales @p sc.
std::vector<NodeStatus> node_statuses(const Model& md, const ContactState& state, const JudgeScales& sc,
                                      double status_tol);

/// The judgement of a displacement.
struct Judgement {
  CertificateReport certificate;
  std::vector<NodeStatus> status;  ///< every Γ3 node of the state's model
  double j_term = 0, friction_term = 0, max_u_nu = 0;
  StatusCounts counts{};  ///< over all processes
};

/// Both passes with @p reduce: the certificate at @p tol, statuses at @p status_tol.
Judgement judge(const Model& md, const Vec& u, const ContactState& state, const JudgeScope& scope,
                const Reduction& reduce, double tol, double status_tol);

/// The certificate from reduced verdict parts (its scales already set by judge_scales).
void close_certificate(const VerdictParts& all, double tol, CertificateReport& r);

}  // namespace hemicontact
