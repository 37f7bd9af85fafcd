#include "mesh_file_check.hpp"

#include "animanifold/errors.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <vector>

namespace animanifold {

namespace {

// Fewest bytes an ASCII vertex ("0 0 0\n") and face ("3 0 1 2\n") take.
constexpr std::uint64_t kVertexBytes = 6, kFaceBytes = 8;
// A corner of a face is at least a digit and a separator.
constexpr std::uint64_t kCornerBytes = 2;
// PLY headers are a few hundred bytes; this bounds reading a hostile one.
constexpr int kMaxHeaderLines = 10000;

std::optional<std::uint64_t> parse_count(const std::string& token) {
  std::uint64_t value = 0;
  const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (error != std::errc() || end != token.data() + token.size()) return std::nullopt;
  return value;
}

std::vector<std::string> tokens(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> out;
  for (std::string t; in >> t;) out.push_back(t);
  return out;
}

// The next line with content, skipping blank lines and '#' comments as
// CGAL's OFF scanner does; nullopt at the end of the file.
std::optional<std::vector<std::string>> next_content_line(std::istream& in) {
  for (std::string line; std::getline(in, line);) {
    auto t = tokens(line);
    if (!t.empty() && t[0][0] != '#') return t;
  }
  return std::nullopt;
}

void check_counts_fit(const std::string& path, std::uint64_t size, std::uint64_t vertices, std::uint64_t faces) {
  // Each count alone is below the size first, so that the sum cannot overflow.
  if (vertices > size || faces > size || vertices * kVertexBytes + faces * kFaceBytes > size + 1)
    fail<IOError>("mesh file '", path, "' declares ", vertices, " vertices and ", faces, " faces, more than its ",
                  size, " bytes can hold");
}

void check_off(const std::string& path, std::uint64_t size) {
  std::ifstream in(path, std::ios::binary);
  auto header = next_content_line(in);
  if (!header || (*header)[0].size() < 3 || (*header)[0].compare((*header)[0].size() - 3, 3, "OFF") != 0) return;
  if (std::find(header->begin(), header->end(), "BINARY") != header->end()) return;  // no ASCII counts to check
  // The counts follow the keyword on its line, or on the next one.
  std::vector<std::string> counts(header->begin() + 1, header->end());
  if (counts.empty()) counts = next_content_line(in).value_or(std::vector<std::string>{});
  if (counts.size() < 2) return;
  const auto vertices = parse_count(counts[0]), faces = parse_count(counts[1]);
  if (!vertices || !faces) return;
  check_counts_fit(path, size, *vertices, *faces);
  for (std::uint64_t v = 0; v < *vertices; ++v)
    if (!next_content_line(in)) return;
  for (std::uint64_t f = 0; f < *faces; ++f) {
    const auto face = next_content_line(in);
    if (!face) return;
    const auto corners = parse_count((*face)[0]);
    if (corners && *corners > size / kCornerBytes)
      fail<IOError>("mesh file '", path, "': face ", f, " declares ", *corners, " corners, more than its ", size,
                    " bytes can hold");
  }
}

void check_ply(const std::string& path, std::uint64_t size) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  if (!std::getline(in, line) || line.rfind("ply", 0) != 0) return;
  // Every property of every element takes at least one byte in any PLY format.
  std::uint64_t bytes = 0, count = 0;
  for (int i = 0; i < kMaxHeaderLines && std::getline(in, line); ++i) {
    const auto t = tokens(line);
    if (t.empty()) continue;
    if (t[0] == "end_header") return;
    if (t[0] == "element" && t.size() >= 3) {
      const auto declared = parse_count(t[2]);
      if (!declared) return;
      if (*declared > size)
        fail<IOError>("mesh file '", path, "' declares ", *declared, " ", t[1], " elements, more than its ", size,
                      " bytes can hold");
      count = *declared;
    } else if (t[0] == "property") {
      bytes += count;
      if (bytes > size)
        fail<IOError>("mesh file '", path, "' declares more element properties than its ", size, " bytes can hold");
    }
  }
}

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

}  // namespace

void check_mesh_file(const std::string& path) {
  std::error_code error;
  const auto status = std::filesystem::status(path, error);
  if (!std::filesystem::exists(status)) fail<IOError>("mesh file '", path, "' does not exist");
  if (!std::filesystem::is_regular_file(status))
    fail<InputError>("mesh file '", path, "' is not a regular file (a directory, device or pipe)");
  const std::uint64_t size = std::filesystem::file_size(path, error);
  if (error) fail<IOError>("could not read mesh file '", path, "': ", error.message());
  const std::string ext = lower_extension(path);
  if (ext == ".off") check_off(path, size);
  else if (ext == ".ply") check_ply(path, size);
}

}  // namespace animanifold
