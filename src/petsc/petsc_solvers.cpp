#include "engine_impl.hpp"

#include <initializer_list>
#include <string>
#include <utility>

namespace hemicontact::petsc_engine::detail {

// A PETSc option's default: set only where the user set nothing (solver.petsc.options,
// PETSC_OPTIONS), so that theirs still wins.
void option_default(const std::string& name, const char* value) {
  PetscBool set = PETSC_FALSE;
  HC_PETSC(PetscOptionsHasName(nullptr, nullptr, name.c_str(), &set));
  if (!set) HC_PETSC(PetscOptionsSetValue(nullptr, name.c_str(), value));
}

namespace {

// Option defaults for a KSP's preconditioner of type @p type, set under the PC's final prefix
// (after the KSP read its options) and read again, only where the user set nothing: the user's
// own options (solver.petsc.options, PETSC_OPTIONS) still win.
void pc_defaults(KSP ksp, PCType type, const std::string& stem,
                 std::initializer_list<std::pair<const char*, const char*>> values) {
  PC pc;
  HC_PETSC(KSPGetPC(ksp, &pc));
  PetscBool same = PETSC_FALSE;
  HC_PETSC(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(pc), type, &same));
  if (!same) return;
  const char* prefix = nullptr;
  HC_PETSC(PCGetOptionsPrefix(pc, &prefix));
  const std::string pre = std::string("-") + (prefix ? prefix : "") + stem;
  for (const auto& [name, value] : values) option_default(pre + name, value);
  HC_PETSC(PCSetFromOptions(pc));
}

}  // namespace

// BoomerAMG for elasticity in 3D: HMIS coarsening, ext+i interpolation truncated to 4 entries, one
// level of aggressive coarsening and strong threshold 0.5 (hypre's recommendation for 3D; the
// defaults, tuned for 2D scalar problems, gave a grid complexity ~2 and 5x the time of a TAO solve
// here).
void hypre_defaults(KSP ksp) {
  pc_defaults(ksp, PCHYPRE, "pc_hypre_boomeramg_",
              {{"coarsen_type", "HMIS"}, {"interp_type", "ext+i"}, {"P_max", "4"}, {"agg_nl", "1"},
               {"strong_threshold", "0.5"}});
}

// GAMG with its own eigenvalue estimate for the Chebyshev smoothers on every set-up: PETSc 3.18
// passes the estimate of the prolongator smoothing to them by default (pc_gamg_use_sa_esteig),
// and on a hierarchy rebuilt for a matrix with Γ3 rows fixed (contact, stick) that made the
// preconditioner indefinite (CG: DIVERGED_INDEFINITE_PC at the first rebuild; measured on the 3D
// scene at n = 32, 48, 70). Set on every KSP that may run GAMG: ssn's steps, the elastic solve and
// the polish (create_cg), and TAO's Newton steps (newton_pc = gamg).
void gamg_defaults(KSP ksp) { pc_defaults(ksp, PCGAMG, "pc_gamg_", {{"use_sa_esteig", "false"}}); }

namespace {

// GAMG for TAO's Newton steps (newton_pc = gamg), whose matrix is the Hessian on the inactive set:
// its size changes from step to step, and PETSc 3.18's GAMG keeps its levels' operators through a
// reset and then refuses the new size ("Cannot change local size of Amat after use", exit 3 of
// every tao:* run with gamg before). A shell preconditioner therefore makes a fresh GAMG at every
// set-up (TAO's matrix is new at every step, so BoomerAMG's hierarchy is rebuilt just as often).
struct FreshGamg {
  PC inner = nullptr;
  std::string prefix;  // TAO's KSP's, so -tao_pc_gamg_... options reach the inner GAMG
};

PetscErrorCode fresh_gamg_setup(PC pc) {
  FreshGamg* s = nullptr;
  PetscCall(PCShellGetContext(pc, &s));
  ::Mat A, P;
  PetscCall(PCGetOperators(pc, &A, &P));
  PetscCall(PCDestroy(&s->inner));
  PetscCall(PCCreate(PetscObjectComm(reinterpret_cast<PetscObject>(pc)), &s->inner));
  PetscCall(PCSetOptionsPrefix(s->inner, s->prefix.c_str()));
  PetscCall(PCSetType(s->inner, PCGAMG));
  PetscCall(PCSetOperators(s->inner, A, P));
  PetscBool set = PETSC_FALSE;
  const std::string esteig = "-" + s->prefix + "pc_gamg_use_sa_esteig";
  PetscCall(PetscOptionsHasName(nullptr, nullptr, esteig.c_str(), &set));
  if (!set) PetscCall(PetscOptionsSetValue(nullptr, esteig.c_str(), "false"));
  PetscCall(PCSetFromOptions(s->inner));
  PetscCall(PCSetUp(s->inner));
  return 0;
}

PetscErrorCode fresh_gamg_apply(PC pc, ::Vec x, ::Vec y) {
  FreshGamg* s = nullptr;
  PetscCall(PCShellGetContext(pc, &s));
  PetscCall(PCApply(s->inner, x, y));
  return 0;
}

PetscErrorCode fresh_gamg_destroy(PC pc) {
  FreshGamg* s = nullptr;
  PetscCall(PCShellGetContext(pc, &s));
  PetscCall(PCDestroy(&s->inner));
  delete s;
  return 0;
}

}  // namespace

void fresh_gamg(KSP ksp) {
  PC pc;
  HC_PETSC(KSPGetPC(ksp, &pc));
  PetscBool gamg = PETSC_FALSE;
  HC_PETSC(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(pc), PCGAMG, &gamg));
  if (!gamg) return;  // the user's -tao_pc_type won
  const char* prefix = nullptr;
  HC_PETSC(KSPGetOptionsPrefix(ksp, &prefix));
  HC_PETSC(PCSetType(pc, PCSHELL));
  auto* s = new FreshGamg;
  s->prefix = prefix ? prefix : "";
  HC_PETSC(PCShellSetContext(pc, s));
  HC_PETSC(PCShellSetSetUp(pc, fresh_gamg_setup));
  HC_PETSC(PCShellSetApply(pc, fresh_gamg_apply));
  HC_PETSC(PCShellSetDestroy(pc, fresh_gamg_destroy));
  HC_PETSC(PCShellSetName(pc, "GAMG, made anew for each Newton step"));
}

void Engine::set_pc(KSP ksp, const std::string& type) const {
  PC pc;
  HC_PETSC(KSPGetPC(ksp, &pc));
  if (type == "hypre") {
    HC_PETSC(PCSetType(pc, PCHYPRE));
    HC_PETSC(PCHYPRESetType(pc, "boomeramg"));
  } else {
    HC_PETSC(PCSetType(pc, PCGAMG));
  }
}

// CG with the full-size preconditioner (solver.petsc.pc) at ksp_rtol, under the options prefix
// @p prefix: the elastic solve, the polish and ssn's steps. The user's PETSc options, read last,
// win over these settings.
void Engine::create_cg(PKsp& ksp, const char* prefix, KSPNormType norm) const {
  HC_PETSC(KSPCreate(comm, &ksp.k));
  HC_PETSC(KSPSetType(ksp.k, KSPCG));
  HC_PETSC(KSPSetOptionsPrefix(ksp.k, prefix));
  if (norm != KSP_NORM_DEFAULT) HC_PETSC(KSPSetNormType(ksp.k, norm));
  set_pc(ksp.k, opt.petsc.pc);
  HC_PETSC(KSPSetTolerances(ksp.k, opt.petsc.ksp_rtol, PETSC_DEFAULT, PETSC_DEFAULT, opt.petsc.ksp_max_it));
  HC_PETSC(KSPSetFromOptions(ksp.k));
  hypre_defaults(ksp.k);
  gamg_defaults(ksp.k);
}

// A Krylov solve that did not converge stops the run with PETSc's reason (EXIT_NOT_CONVERGED):
// every rank sees the same reason, so every rank throws the same error.
void Engine::ksp_check(KSP ksp, const std::string& what) const {
  KSPConvergedReason reason;
  PetscInt its;
  HC_PETSC(KSPGetConvergedReason(ksp, &reason));
  HC_PETSC(KSPGetIterationNumber(ksp, &its));
  if (reason < 0)
    throw Error(what + ": CG did not converge: " + KSPConvergedReasons[reason] + " after " + std::to_string(its) +
                    " iterations (solver.petsc.ksp_max_it = " + std::to_string(opt.petsc.ksp_max_it) +
                    ", ksp_rtol = " + short_number(opt.petsc.ksp_rtol) + ", pc = " + opt.petsc.pc + ")",
                EXIT_NOT_CONVERGED);
}

}  // namespace hemicontact::petsc_engine::detail
