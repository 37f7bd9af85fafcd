#include "animanifold/cgroup_memory.hpp"

#include <algorithm>
#include <charconv>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

namespace animanifold {

namespace {

namespace fs = std::filesystem;

// v1 writes "no limit" as the largest page-aligned 63-bit number; anything this large is none.
constexpr std::uint64_t kNoLimit = std::uint64_t{1} << 62;

std::optional<std::uint64_t> parse_bytes(const std::string& text) {
  std::uint64_t value = 0;
  const char* end = text.data() + text.size();
  const auto [stop, error] = std::from_chars(text.data(), end, value);
  if (error != std::errc() || stop != end) return std::nullopt;
  return value;
}

// The first line of a cgroup file, without surrounding white space; "" when unreadable.
std::string first_line(const fs::path& path) {
  std::ifstream file(path);
  std::string line;
  std::getline(file, line);
  const auto begin = line.find_first_not_of(" \t\r");
  if (begin == std::string::npos) return "";
  return line.substr(begin, line.find_last_not_of(" \t\r") - begin + 1);
}

// The value of `key` in a memory.stat file; 0 when absent.
std::uint64_t stat_value(const fs::path& path, const std::string& key) {
  std::ifstream file(path);
  std::string name;
  for (std::uint64_t value = 0; file >> name >> value;)
    if (name == key) return value;
  return 0;
}

// One hierarchy's file names.
struct Version {
  const char* limit;
  const char* usage;
  const char* inactive_file;  // the key in memory.stat
};
constexpr Version kV2{"memory.max", "memory.current", "inactive_file"};
constexpr Version kV1{"memory.limit_in_bytes", "memory.usage_in_bytes", "total_inactive_file"};

// The headroom left in one cgroup folder; nullopt when it sets no limit.
std::optional<std::uint64_t> folder_headroom(const fs::path& folder, const Version& version) {
  const auto limit = parse_bytes(first_line(folder / version.limit));  // v2's "max" parses as none
  if (!limit || *limit >= kNoLimit) return std::nullopt;
  const std::uint64_t usage = parse_bytes(first_line(folder / version.usage)).value_or(0);
  const std::uint64_t inactive = stat_value(folder / "memory.stat", version.inactive_file);
  const std::uint64_t working = usage - std::min(usage, inactive);
  return *limit - std::min(*limit, working);
}

// The least headroom from `mount` down to `mount`/`cgroup`: a parent's limit binds its
// children too. Folders of a cgroup path not visible under the mount (a container without
// its own cgroup namespace) have no files and set no limit.
std::optional<std::uint64_t> hierarchy_headroom(const fs::path& mount, const std::string& cgroup,
                                                const Version& version) {
  std::error_code error;
  if (!fs::is_directory(mount, error)) return std::nullopt;
  std::optional<std::uint64_t> least = folder_headroom(mount, version);
  fs::path folder = mount;
  for (const fs::path& part : fs::path(cgroup).relative_path()) {
    if (part.empty() || part == "." || part == "..") continue;  // the kernel writes neither
    folder /= part;
    if (const auto headroom = folder_headroom(folder, version)) least = std::min(least.value_or(*headroom), *headroom);
  }
  return least;
}

// True when `controllers` (a comma-separated list from /proc/self/cgroup) names memory.
bool names_memory(const std::string& controllers) {
  std::istringstream list(controllers);
  for (std::string name; std::getline(list, name, ',');)
    if (name == "memory") return true;
  return false;
}

}  // namespace

std::optional<std::uint64_t> cgroup_memory_headroom(const CgroupFiles& files) {
  std::ifstream self(files.self_cgroup);
  const fs::path root(files.root);
  std::optional<std::uint64_t> least;
  const auto take = [&least](std::optional<std::uint64_t> headroom) {
    if (headroom) least = std::min(least.value_or(*headroom), *headroom);
  };
  // Lines are "hierarchy-id:controllers:path"; v2's has no controllers.
  for (std::string line; std::getline(self, line);) {
    const auto first = line.find(':');
    if (first == std::string::npos) continue;
    const auto second = line.find(':', first + 1);
    if (second == std::string::npos) continue;
    const std::string controllers = line.substr(first + 1, second - first - 1), path = line.substr(second + 1);
    if (controllers.empty()) {
      std::error_code error;
      const bool unified = fs::exists(root / "cgroup.controllers", error);
      take(hierarchy_headroom(unified ? root : root / "unified", path, kV2));
    } else if (names_memory(controllers)) {
      take(hierarchy_headroom(root / "memory", path, kV1));
    }
  }
  return least;
}

}  // namespace animanifold
