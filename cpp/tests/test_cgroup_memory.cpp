// The cgroups' memory headroom (cgroup_memory.hpp) and the available memory it bounds
// (memory_limit.hpp), read from stand-in cgroup trees in a temporary folder.
#include "animanifold/cgroup_memory.hpp"
#include "animanifold/memory_limit.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <optional>
#include <random>
#include <string>

using namespace animanifold;
namespace fs = std::filesystem;

namespace {

// A stand-in for /proc/self/cgroup, /proc/meminfo and /sys/fs/cgroup, removed after the test.
class CgroupMemory : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("animanifold-cgroup-" + std::to_string(std::random_device{}()));
    fs::create_directories(dir_ / "root");
    files_.self_cgroup = (dir_ / "self_cgroup").string();
    files_.root = (dir_ / "root").string();
  }
  void TearDown() override { fs::remove_all(dir_); }

  void write(const fs::path& relative, const std::string& text) const {
    const fs::path path = dir_ / relative;
    fs::create_directories(path.parent_path());
    std::ofstream(path) << text;
  }
  std::optional<std::uint64_t> headroom() const { return cgroup_memory_headroom(files_); }

  fs::path dir_;
  CgroupFiles files_;
};

constexpr std::uint64_t kMiB = 1024 * 1024;

}  // namespace

TEST_F(CgroupMemory, V2HeadroomIsTheLimitLessTheWorkingSetLeavingOutInactiveFileCache) {
  write("self_cgroup", "0::/user.slice/app.scope\n");
  write("root/cgroup.controllers", "cpu memory pids\n");
  write("root/user.slice/app.scope/memory.max", "1000000000\n");
  write("root/user.slice/app.scope/memory.current", "300000000\n");
  write("root/user.slice/app.scope/memory.stat", "anon 200000000\nfile 100000000\ninactive_file 50000000\n");
  EXPECT_EQ(headroom(), std::optional<std::uint64_t>(1000000000 - 250000000));
}

TEST_F(CgroupMemory, AParentsLimitBindsItsChildren) {
  write("self_cgroup", "0::/slice/app\n");
  write("root/cgroup.controllers", "memory\n");
  write("root/slice/memory.max", std::to_string(512 * kMiB));
  write("root/slice/memory.current", std::to_string(500 * kMiB));
  write("root/slice/app/memory.max", "max\n");
  write("root/slice/app/memory.current", std::to_string(400 * kMiB));
  EXPECT_EQ(headroom(), std::optional<std::uint64_t>(12 * kMiB));
  // The child's own, lower limit binds where it leaves less.
  write("root/slice/app/memory.max", std::to_string(404 * kMiB));
  EXPECT_EQ(headroom(), std::optional<std::uint64_t>(4 * kMiB));
}

TEST_F(CgroupMemory, V1MemoryControllerOfAHybridSystemIsRead) {
  write("self_cgroup", "9:name=systemd:/\n5:devices:/\n4:cpu,memory:/process_api/1234\n0::/\n");
  fs::create_directories(dir_ / "root/unified");  // v2 mounted beside v1, without the memory controller
  write("root/memory/memory.limit_in_bytes", "9223372036854771712\n");  // the root: no limit
  write("root/memory/process_api/1234/memory.limit_in_bytes", std::to_string(1024 * kMiB));
  write("root/memory/process_api/1234/memory.usage_in_bytes", std::to_string(300 * kMiB));
  write("root/memory/process_api/1234/memory.stat", "cache 0\ninactive_file 999\ntotal_inactive_file " +
                                                        std::to_string(100 * kMiB) + "\n");
  EXPECT_EQ(headroom(), std::optional<std::uint64_t>(824 * kMiB));
}

TEST_F(CgroupMemory, NoLimitMissingFilesAndGarbageGiveNoHeadroom) {
  EXPECT_EQ(headroom(), std::nullopt);  // no /proc/self/cgroup at all
  write("self_cgroup", "0::/a\n4:memory:/b\nnot a cgroup line\n");
  EXPECT_EQ(headroom(), std::nullopt);  // no hierarchies mounted
  write("root/cgroup.controllers", "memory\n");
  write("root/a/memory.max", "max\n");
  write("root/memory/b/memory.limit_in_bytes", "9223372036854771712\n");
  EXPECT_EQ(headroom(), std::nullopt);
  write("root/a/memory.max", "12abc\n");
  write("root/memory/b/memory.limit_in_bytes", "-5\n");
  EXPECT_EQ(headroom(), std::nullopt);
}

TEST_F(CgroupMemory, AWorkingSetAtOrBeyondTheLimitLeavesNothing) {
  write("self_cgroup", "0::/\n");
  write("root/cgroup.controllers", "memory\n");
  write("root/memory.max", "4096\n");
  write("root/memory.current", "8192\n");
  EXPECT_EQ(headroom(), std::optional<std::uint64_t>(0));
}

TEST_F(CgroupMemory, AvailableMemoryIsTheLowerOfMemAvailableAndTheCgroupsHeadroom) {
  MemoryFiles files{(dir_ / "meminfo").string(), files_};
  write("meminfo", "MemTotal:       4000000 kB\nMemFree:         100 kB\nMemAvailable:    2000000 kB\n");
  EXPECT_EQ(available_memory(files), 2000000u * 1024);  // no cgroup limit
  write("self_cgroup", "0::/box\n");
  write("root/cgroup.controllers", "memory\n");
  write("root/box/memory.max", std::to_string(1000 * kMiB));
  write("root/box/memory.current", std::to_string(100 * kMiB));
  EXPECT_EQ(available_memory(files), 900 * kMiB);
  write("root/box/memory.max", std::to_string(100000 * kMiB));  // looser than the machine
  EXPECT_EQ(available_memory(files), 2000000u * 1024);
}
