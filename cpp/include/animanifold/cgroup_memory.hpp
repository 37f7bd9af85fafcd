// How much more memory the process's control groups let it take. A container or a systemd
// slice may allow far less than the machine's free memory (MemAvailable); the default
// memory limit (memory_limit.hpp) takes the lower of the two.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace animanifold {

// Where the cgroup figures are read from; tests substitute stand-in files.
struct CgroupFiles {
  std::string self_cgroup = "/proc/self/cgroup";  // the process's cgroup in each hierarchy
  std::string root = "/sys/fs/cgroup";            // where the hierarchies are mounted
};

// Inputs:
//   files  the process's cgroup list and the mount point of the hierarchies:
//          cgroup v2 at root (or root/unified on a hybrid system), v1's memory
//          controller at root/memory
// Outputs: the least headroom over the process's cgroup and its ancestors, in either
//   version: the limit (v2 memory.max, v1 memory.limit_in_bytes) minus the working set
//   (memory.current or memory.usage_in_bytes, less the inactive file cache in memory.stat,
//   which the kernel reclaims before it fails an allocation), 0 when the working set is at
//   the limit already; nullopt when no cgroup sets a limit or the files are missing or
//   unreadable (the machine's memory then is the only bound)
// Throws: nothing: a missing, unreadable or malformed file counts as setting no limit
std::optional<std::uint64_t> cgroup_memory_headroom(const CgroupFiles& files = {});

}  // namespace animanifold
