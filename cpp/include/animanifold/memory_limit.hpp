// How much memory one core call may ask for. Calls whose output size follows from their
// input (stitch, manifold and frame subdivision, refine: memory_estimates.hpp) estimate
// what they will allocate before they allocate it and refuse beyond the limit, so that a
// hostile or mistaken input (twelve levels of subdivision, a million keyframes) fails at
// once with a message instead of the machine swapping or the kernel killing the process.
//
// The limit is process-wide. By default it is half of the memory available when the call
// starts (/proc/meminfo's MemAvailable, else the free physical pages, or what the process's
// cgroups still allow where that is less), read afresh on every check; set_memory_limit()
// fixes it (Python: animanifold.set_memory_limit).
#pragma once

#include "animanifold/cgroup_memory.hpp"
#include "animanifold/errors.hpp"

#include <cstdint>
#include <optional>
#include <string>

namespace animanifold {

// Inputs:
//   bytes  the limit to apply from now on; nullopt returns to the default (half of
//          the available memory)
// Throws: InputError when bytes is 0
void set_memory_limit(std::optional<std::uint64_t> bytes);

// Outputs: the limit set by set_memory_limit(), nullopt when the default applies
// Throws: nothing
std::optional<std::uint64_t> memory_limit_setting();

// Where the available memory is read from; tests substitute stand-in files.
struct MemoryFiles {
  std::string meminfo = "/proc/meminfo";
  CgroupFiles cgroups;
};

// Inputs:
//   files  /proc/meminfo and the cgroup files (the real ones by default)
// Outputs: the memory the system can give without swapping, in bytes: MemAvailable (the
//   free physical pages where meminfo is missing), or the headroom the process's cgroups
//   leave (cgroup_memory_headroom) where that is lower
// Throws: nothing: an unreadable file gives no figure (0 when neither meminfo nor the
//   free-page count gives one; check_memory() then refuses nothing)
std::uint64_t available_memory(const MemoryFiles& files = {});

// Outputs: the limit in force now: the one set, else half of available_memory()
// Throws: nothing
std::uint64_t memory_limit();

// What a call is about to do and how much memory it will take at its peak.
struct MemoryEstimate {
  std::string doing;  // with its sizes, for the message: "stitching 10 keyframes of ..."
  double bytes = 0;   // a double: estimates of hostile inputs overflow 64 bits
};

// Inputs:
//   doing  what the call is about to do, with its sizes ("stitching 10 keyframes of 5000
//          vertices and 9996 faces"), for the message
//   bytes  the call's estimated peak allocation (memory_estimates.hpp)
// Throws:
//   MemoryLimitError naming `doing`, the estimate and the limit, when bytes exceeds
//   memory_limit()
void check_memory(const std::string& doing, double bytes);

// Inputs:
//   estimate  what a call is about to do and its peak (memory_estimates.hpp)
// Throws: MemoryLimitError as check_memory(doing, bytes)
inline void check_memory(const MemoryEstimate& estimate) { check_memory(estimate.doing, estimate.bytes); }

}  // namespace animanifold
