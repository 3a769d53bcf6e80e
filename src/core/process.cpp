#include <hemicontact/core/process.hpp>

#include <dlfcn.h>
#include <malloc.h>

#include <cstdlib>

namespace hemicontact {

void configure_process_for_solves() {
  // glibc serves blocks above a dynamic threshold (128 KB at first, up to 32 MB) with mmap and
  // gives them back on free, and trims the heap top above 128 KB. A solve allocates and frees
  // arrays of MBs per phase (K, its reduction, workspaces, the VTU buffers), so each phase faulted
  // in fresh pages again, and on a virtual machine a page fault costs microseconds. A fixed 32 MB
  // threshold and a 128 MB trim threshold let the next phase reuse mapped pages: at h = 1/256,
  // 67.8k page faults -> 57.3k with the same peak (218 MB). Larger values saved 3k faults more
  // but raised the peak (229 MB at 256/512 MB, and 3.43 GB against 3.15 GB at h = 1/1024): blocks
  // above 32 MB (K and the factor at h = 1/1024) keep being mapped and unmapped on their own.
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 128 << 20);
  // CHOLMOD 3 (SuiteSparse 5.x, Debian's) is compiled with CHOLMOD_OMP_NUM_THREADS = 4: each
  // supernode of a numeric factorization opens an OpenMP team of 4 threads (to clear and scatter
  // into its block) whatever the machine has. On 2 cores, shared with other work, those teams spin
  // and wait for descheduled threads: the fig2 adaptive run to 1 % took 1.84 s of CPU instead of
  // 1.31 s. With dynamic adjustment (OpenMP's dyn-var) the runtime gives a team at most the idle
  // processors (libgomp: online processors minus the load average, at least 1). Only the team sizes
  // change, not the arithmetic (the parallel loops clear and copy entries; the BLAS is OpenBLAS's
  // own threads). An explicit OMP_DYNAMIC is left as the user set it.
  // libgomp is already loaded as CHOLMOD's dependency; looked up, so the build needs no OpenMP flags.
  if (!std::getenv("OMP_DYNAMIC"))
    if (auto* set_dynamic = reinterpret_cast<void (*)(int)>(dlsym(RTLD_DEFAULT, "omp_set_dynamic"))) set_dynamic(1);
}

}  // namespace hemicontact
