#include "animanifold/memory_limit.hpp"

#include "animanifold/errors.hpp"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

namespace animanifold {

namespace {

// 0 = the default (half of the available memory); a limit of 0 bytes cannot be set.
std::atomic<std::uint64_t> g_limit{0};

// 1.15 GiB, 3.2e+03 GiB, 12.5 MiB, 4 KiB.
std::string readable_bytes(double bytes) {
  static constexpr const char* kUnits[] = {"KiB", "MiB", "GiB"};
  int unit = 0;
  for (bytes /= 1024; unit < 2 && bytes >= 1024; ++unit) bytes /= 1024;
  char text[64];
  std::snprintf(text, sizeof text, "%.3g %s", bytes, kUnits[unit]);
  return text;
}

// "1,234,567,890 bytes (1.15 GiB)": exact and readable; beyond 64 bits readable only.
std::string bytes_text(double bytes) {
  if (bytes >= 1.8e19) return readable_bytes(bytes);
  std::string digits = std::to_string(static_cast<unsigned long long>(bytes));
  for (int i = static_cast<int>(digits.size()) - 3; i > 0; i -= 3) digits.insert(static_cast<std::size_t>(i), ",");
  return bytes < 1024 ? digits + " bytes" : digits + " bytes (" + readable_bytes(bytes) + ")";
}

}  // namespace

void set_memory_limit(std::optional<std::uint64_t> bytes) {
  if (bytes && *bytes == 0) fail<InputError>("the memory limit must be at least 1 byte, got 0");
  g_limit.store(bytes.value_or(0));
}

std::optional<std::uint64_t> memory_limit_setting() {
  const std::uint64_t limit = g_limit.load();
  return limit ? std::optional<std::uint64_t>(limit) : std::nullopt;
}

namespace {

std::uint64_t machine_available_memory(const std::string& meminfo_path) {
  std::ifstream meminfo(meminfo_path);
  for (std::string key; meminfo >> key;) {
    std::uint64_t kib = 0;
    if (key == "MemAvailable:" && meminfo >> kib) return kib * 1024;
    meminfo.ignore(1 << 10, '\n');
  }
  const long pages = sysconf(_SC_AVPHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  return pages > 0 && page > 0 ? static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page) : 0;
}

}  // namespace

std::uint64_t available_memory(const MemoryFiles& files) {
  const std::uint64_t machine = machine_available_memory(files.meminfo);
  const auto cgroups = cgroup_memory_headroom(files.cgroups);
  return cgroups ? std::min(machine, *cgroups) : machine;
}

std::uint64_t memory_limit() {
  const auto set = memory_limit_setting();
  return set ? *set : available_memory() / 2;
}

void check_memory(const std::string& doing, double bytes) {
  const std::uint64_t limit = memory_limit();
  // A limit of 0 means the system reported no memory at all: nothing to judge by.
  if (limit == 0 || !(bytes > static_cast<double>(limit))) return;
  const bool set = memory_limit_setting().has_value();
  fail<MemoryLimitError>(doing, " needs about ", bytes_text(bytes), ", more than the memory limit of ",
                         bytes_text(static_cast<double>(limit)),
                         set ? " (set by animanifold.set_memory_limit)"
                             : " (half the available memory; animanifold.set_memory_limit changes it)");
}

}  // namespace animanifold
