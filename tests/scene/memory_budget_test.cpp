// The memory estimate's budget is the process's, not the machine's: the cgroup limit
// (v2 memory.max, v1 memory.limit_in_bytes, of the process's group and the groups above it) less
// its usage without the inactive page cache, read here from a folder laid out like / (cgroup_memory_budget's root).
#include <hemicontact/scene/build_model.hpp>

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace fs = std::filesystem;
using hemicontact::cgroup_memory_budget;

namespace {

class CgroupBudget : public ::testing::Test {
 protected:
  void SetUp() override {
    root = fs::temp_directory_path() / ("hemicontact_cgroup_" + std::to_string(::getpid()));
    fs::remove_all(root);
    fs::create_directories(root / "proc" / "self");
  }
  void TearDown() override { fs::remove_all(root); }
  void write(const fs::path& rel, const std::string& text) const {
    fs::create_directories((root / rel).parent_path());
    std::ofstream(root / rel) << text;
  }
  fs::path root;
};

}  // namespace

TEST_F(CgroupBudget, V2LimitOfTheGroupOrAGroupAboveIt) {
  write("proc/self/cgroup", "0::/user.slice/job\n");
  write("sys/fs/cgroup/user.slice/job/memory.max", "max\n");  // no limit of its own
  write("sys/fs/cgroup/user.slice/job/memory.current", "123\n");
  write("sys/fs/cgroup/user.slice/memory.max", "1000000000\n");
  write("sys/fs/cgroup/user.slice/memory.current", "300000000\n");
  const auto b = cgroup_memory_budget(root.string());
  EXPECT_DOUBLE_EQ(b.bytes, 7e8);
  write("sys/fs/cgroup/user.slice/memory.stat", "anon 1\ninactive_file 100000000\n");
  EXPECT_DOUBLE_EQ(cgroup_memory_budget(root.string()).bytes, 8e8);
  EXPECT_NE(b.limit.find("user.slice/memory.max"), std::string::npos) << b.limit;
  // The tighter of two limits wins.
  write("sys/fs/cgroup/user.slice/job/memory.max", "500000000\n");
  EXPECT_DOUBLE_EQ(cgroup_memory_budget(root.string()).bytes, 5e8 - 123);
}

TEST_F(CgroupBudget, V1MemoryControllerAndNoLimit) {
  write("proc/self/cgroup", "12:cpu,cpuacct:/x\n4:memory:/docker/abc\n");
  write("sys/fs/cgroup/memory/docker/abc/memory.limit_in_bytes", "2147483648\n");
  write("sys/fs/cgroup/memory/docker/abc/memory.usage_in_bytes", "147483648\n");
  EXPECT_DOUBLE_EQ(cgroup_memory_budget(root.string()).bytes, 2e9);
  // Reclaimable page cache is not usage.
  write("sys/fs/cgroup/memory/docker/abc/memory.stat", "cache 100\ntotal_inactive_file 47483648\nrss 5\n");
  EXPECT_DOUBLE_EQ(cgroup_memory_budget(root.string()).bytes, 2e9 + 47483648);
  // v1 writes "no limit" as a huge number: no budget at all (-1), not a huge one.
  write("sys/fs/cgroup/memory/docker/abc/memory.limit_in_bytes", "9223372036854771712\n");
  EXPECT_LT(cgroup_memory_budget(root.string()).bytes, 0);
  // Nothing to read: no budget.
  fs::remove(root / "proc" / "self" / "cgroup");
  EXPECT_LT(cgroup_memory_budget(root.string()).bytes, 0);
}

// A refusal said "needs about 1.1 GB ... 1.1 GB are available": the two amounts get the
// digits that tell them apart, and no more than two where two suffice.
TEST(MemoryRefusal, AmountsShowTheDigitsThatTellThemApart) {
  using hemicontact::distinct_gigabytes;
  EXPECT_EQ(distinct_gigabytes(1.14e9, 1.12e9), std::make_pair(std::string("1.14 GB"), std::string("1.12 GB")));
  EXPECT_EQ(distinct_gigabytes(1.1234e9, 1.1231e9), std::make_pair(std::string("1.1234 GB"), std::string("1.1231 GB")));
  EXPECT_EQ(distinct_gigabytes(2.1e9, 0.5e9), std::make_pair(std::string("2.1 GB"), std::string("0.5 GB")));
}
