#include "engine_impl.hpp"

#include <hemicontact/core/error.hpp>

#include <petscsys.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cstdio>
#include <string>
#include <utility>

namespace hemicontact::petsc_engine {
namespace {

// PETSc's first error message of the current failure (error_handler), whether that failure is an
// allocation that failed, and the user's options.
std::string g_petsc_message;
bool g_petsc_out_of_memory = false;
std::string g_user_options;

// Whether PETSc's error starts in its allocator. Debian's PETSc 3.18 reports a failed PetscMalloc
// with codes such as 4008 and 10 and the caller's name as the message (measured under ulimit -v:
// "PETSc error 4008 ... MatSeqAIJSetPreallocation_SeqAIJ (in PetscMallocAlign)"), not with
// PETSC_ERR_MEM: the function the error starts in is what tells.
bool allocation_failed(PetscErrorCode n, const char* fun) {
  const std::string f = fun ? fun : "";
  return n == PETSC_ERR_MEM || f.rfind("PetscMalloc", 0) == 0 || f.rfind("PetscTrMalloc", 0) == 0;
}

// PETSc's default handler prints a traceback on every rank and, with some options, aborts the
// job; this one keeps the first message of a failure for petsc_failure's Error and returns the
// code, so the error ends as every other: one message, one exit code.
PetscErrorCode error_handler(MPI_Comm, int, const char* fun, const char*, PetscErrorCode n, PetscErrorType p,
                             const char* mess, void*) {
  if (p == PETSC_ERROR_INITIAL || g_petsc_message.empty()) {
    g_petsc_message = std::string(mess ? mess : "") + (fun ? std::string(" (in ") + fun + ")" : std::string());
    g_petsc_out_of_memory = allocation_failed(n, fun);
  }
  return n;
}

}  // namespace

void install_error_handler(const std::string& user_options) {
  g_user_options = user_options;
  PetscPushErrorHandler(error_handler, nullptr);
}

long current_rss_kb() {
  long pages = 0, resident = 0;
  if (FILE* f = std::fopen("/proc/self/statm", "r")) {
    if (std::fscanf(f, "%ld %ld", &pages, &resident) != 2) resident = 0;
    std::fclose(f);
  }
  return resident * (sysconf(_SC_PAGESIZE) / 1024);
}

std::string tao_type(const std::string& backend) {
  // solver.backend = auto: this engine's own, ssn, which reaches the cholmod engine's answers ~10x
  // faster than tao:bnls (docs/petsc-engine.md). A backend of the cholmod engine that is named
  // is refused below: a named backend runs, or the run stops saying why.
  if (petsc_engine_runs_ssn(backend)) return "ssn";  // not TAO: the engine's own semismooth Newton (run_ssn)
  for (const char* t : {"bnls", "bntr", "bntl"})
    if (backend == std::string("tao:") + t) return t;
  input_error("solver.backend = '" + backend +
              "': the petsc engine runs ssn (semismooth Newton on the unsmoothed statuses) or TAO's "
              "bounded Newton methods tao:bnls, tao:bntr, tao:bntl (other backends: solver.engine = cholmod)");
}

namespace detail {

void petsc_failure(PetscErrorCode ierr, const char* call) {
  const std::string first = std::exchange(g_petsc_message, std::string());
  if (ierr == PETSC_ERR_MEM || std::exchange(g_petsc_out_of_memory, false))
    memory_error(std::string("PETSc's ") + call + (first.empty() ? "" : " (" + first + ")"));
  std::string m = "PETSc error " + std::to_string(ierr) + " in " + call;
  if (!first.empty()) m += ": " + first;
  if (g_user_options.empty()) throw Error(m, EXIT_INTERNAL);
  throw Error(m + " (solver.petsc.options = '" + g_user_options + "' is set: check its options)", EXIT_INPUT);
}

double allreduce_max(double x, MPI_Comm comm) {
  double y = x;
  MPI_Allreduce(&x, &y, 1, MPI_DOUBLE, MPI_MAX, comm);
  return y;
}

double allreduce_sum(double x, MPI_Comm comm) {
  double y = x;
  MPI_Allreduce(&x, &y, 1, MPI_DOUBLE, MPI_SUM, comm);
  return y;
}

long peak_rss_kb() {
  struct rusage ru {};
  getrusage(RUSAGE_SELF, &ru);
  return ru.ru_maxrss;  // Linux: kilobytes
}

}  // namespace detail
}  // namespace hemicontact::petsc_engine
