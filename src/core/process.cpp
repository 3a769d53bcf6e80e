#include <hemicontact/core/process.hpp>

#include <hemicontact/core/error.hpp>

#include <dlfcn.h>
#include <malloc.h>
#include <sys/mman.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <mutex>
#include <string>
#include <vector>

namespace hemicontact {

void hand_back_freed_memory(long unknowns) {
  if (unknowns >= MEMORY_BOUND_UNKNOWNS) malloc_trim(0);
}

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

namespace {

std::atomic<int> g_reserved{0};

// Whether a buffer of OpenBLAS's size can be mapped now, tried as OpenBLAS maps it (a private
// anonymous mapping, which RLIMIT_AS and the overcommit check count) and unmapped at once.
bool blas_buffer_fits() {
  const size_t bytes = static_cast<size_t>(OPENBLAS_BUFFER_BYTES) + (4 << 10);
  void* p = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (p == MAP_FAILED) return false;
  munmap(p, bytes);
  return true;
}

}  // namespace

void reserve_blas_buffers(int callers) {
  static std::mutex mutex;
  const std::lock_guard<std::mutex> lock(mutex);
  if (callers <= g_reserved.load()) return;  // the pool keeps its buffers: they are there still
  // OpenBLAS's own allocator (driver/others/memory.c): alloc takes the first free buffer of its
  // pool, mapping it where it has none; free returns it to the pool. Holding @p callers at once
  // leaves that many mapped, whatever other threads hold meanwhile. Looked up at run time: a build
  // against another BLAS has no such functions.
  using Alloc = void* (*)(int);
  using Free = void (*)(void*);
  auto* alloc = reinterpret_cast<Alloc>(dlsym(RTLD_DEFAULT, "blas_memory_alloc"));
  auto* release = reinterpret_cast<Free>(dlsym(RTLD_DEFAULT, "blas_memory_free"));
  if (alloc == nullptr || release == nullptr) return;
  std::vector<void*> held;
  for (int i = 0; i < callers; ++i) {
    // Any alloc may map a new buffer: it goes ahead only where one fits. Another thread may take
    // that room between the try and OpenBLAS's mapping, but only in those microseconds.
    if (!blas_buffer_fits()) {
      for (void* p : held) release(p);
      memory_error("OpenBLAS's work buffer (" + std::to_string(static_cast<long>(OPENBLAS_BUFFER_BYTES) >> 20) +
                   " MB for each thread that calls the BLAS, " + std::to_string(callers) + " at once)");
    }
    void* p = alloc(0);
    if (p == nullptr) break;  // beyond OpenBLAS's buffer table (it says so itself): nothing to hold
    held.push_back(p);
  }
  for (void* p : held) release(p);
  g_reserved = std::max(g_reserved.load(), static_cast<int>(held.size()));
}

int reserved_blas_buffers() { return g_reserved.load(); }

}  // namespace hemicontact
