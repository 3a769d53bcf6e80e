// reserve_blas_buffers (core/process.hpp): OpenBLAS's work buffers mapped before the BLAS needs
// them, or the memory error where one does not fit; never OpenBLAS's own endless retry.
#include <hemicontact/core/error.hpp>
#include <hemicontact/core/process.hpp>

#include <gtest/gtest.h>

#include <dlfcn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <string>

namespace hemicontact {
namespace {

bool openblas_loaded() { return dlsym(RTLD_DEFAULT, "blas_memory_alloc") != nullptr; }

// The process's mapped address space (VmSize), in bytes.
double mapped_bytes() {
  std::ifstream in("/proc/self/status");
  for (std::string key; in >> key;) {
    if (key == "VmSize:") {
      double kb = 0;
      in >> kb;
      return kb * 1024;
    }
    in.ignore(1 << 10, '\n');
  }
  return -1;
}

TEST(BlasBuffers, ReservedBuffersAreMappedAndKept) {
  if (!openblas_loaded()) GTEST_SKIP() << "the BLAS is not OpenBLAS";
  const int before = reserved_blas_buffers();
  const double mapped = mapped_bytes();
  reserve_blas_buffers(before + 4);
  EXPECT_EQ(reserved_blas_buffers(), before + 4);
  // Four held at once: more than this process's single-threaded calls left in the pool, so some
  // were mapped, and OpenBLAS keeps them mapped for the process's life.
  EXPECT_GE(mapped_bytes() - mapped, OPENBLAS_BUFFER_BYTES);
  const double after = mapped_bytes();
  reserve_blas_buffers(before + 1);  // fewer than reserved: nothing to do
  EXPECT_EQ(reserved_blas_buffers(), before + 4);
  EXPECT_EQ(mapped_bytes(), after);
}

// Under an address-space limit that leaves 32 MB, a reservation of more buffers than the pool has is
// the memory error (in a child process: the limit stays there). Without the check OpenBLAS would
// retry its mapping for ever.
TEST(BlasBuffers, ABufferThatDoesNotFitIsTheMemoryError) {
#if defined(HEMICONTACT_SANITIZED)
  GTEST_SKIP() << "address-space limits cannot apply under AddressSanitizer: its shadow memory is reserved address space";
#endif
  if (!openblas_loaded()) GTEST_SKIP() << "the BLAS is not OpenBLAS";
  std::fflush(nullptr);
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    const auto limit = static_cast<rlim_t>(mapped_bytes() + 32.0 * (1 << 20));
    const rlimit rl{limit, limit};
    if (setrlimit(RLIMIT_AS, &rl) != 0) _exit(10);
    const int before = reserved_blas_buffers();
    try {
      reserve_blas_buffers(before + 8);
    } catch (const Error& e) {
      const bool named = std::string(e.what()).find("out of memory in OpenBLAS's work buffer") != std::string::npos;
      _exit(!named ? 11 : e.code() != EXIT_INPUT ? 12 : reserved_blas_buffers() != before ? 13 : 0);
    }
    _exit(14);  // reserved 8 buffers of 128 MB within 32 MB
  }
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status)) << "the child ended by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 0) << "10: no limit set, 11: another message, 12: another exit code, "
                                       "13: counted as reserved, 14: no error";
}

}  // namespace
}  // namespace hemicontact
