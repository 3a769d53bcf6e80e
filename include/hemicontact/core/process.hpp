#pragma once
/// @file process.hpp  Process-wide settings that make solves faster, applied once by each program
/// that solves (the CLI's main, the Python module when it is imported).

namespace hemicontact {

/// @brief glibc's malloc thresholds (large arrays stay mapped between a solve's phases) and
/// OpenMP's dynamic team sizes (CHOLMOD's fixed teams of 4 threads spin on a 2-core machine); an
/// OMP_DYNAMIC in the environment is left as the user set it. The reasons and measurements are
/// in src/core/process.cpp.
void configure_process_for_solves();

/// The matrix size (unknowns) from which its factorization is set up for memory rather than for
/// speed: fig2 from n = 256 (131 584 unknowns). Below it, a few MB are not worth a heap walk or a
/// slower factorization (fem/condensation.cpp, hand_back_freed_memory).
inline constexpr long MEMORY_BOUND_UNKNOWNS = 100000;

/// @brief Where @p unknowns ≥ MEMORY_BOUND_UNKNOWNS: hands the heap's freed pages back to the system
/// (malloc_trim). The thresholds of configure_process_for_solves keep freed blocks below 32 MB
/// resident, which is right between a solve's phases but not just before the run's largest array
/// (the factor) is allocated: then they would count in the peak beside it. Each call walks the heap.
void hand_back_freed_memory(long unknowns);

/// OpenBLAS's work buffer (Debian's build): one per thread that calls the BLAS, mapped at its first
/// call and kept in OpenBLAS's pool for the process's life.
inline constexpr double OPENBLAS_BUFFER_BYTES = 128.0 * (1 << 20);

/// @brief Makes OpenBLAS's pool hold at least @p callers work buffers besides its worker threads',
/// mapping the missing ones now, each only after a mapping of its size was tried and fits.
/// OpenBLAS maps a buffer where a thread's BLAS call finds none free and, where the mapping fails
/// (ulimit -v), retries it for ever: a hang on one MPI rank, or in two threaded Python solves.
/// Call it before the solves that may call the BLAS at once start (@p callers of them). Does
/// nothing where the BLAS is not OpenBLAS (its entry points are looked up at run time).
/// @throw Error (exit code 2, the out-of-memory message) where a buffer does not fit.
void reserve_blas_buffers(int callers);

/// @return how many buffers reserve_blas_buffers has made sure of (0: none; memory_budget then
/// keeps room for the one the first BLAS call maps).
int reserved_blas_buffers();

}  // namespace hemicontact
