#include "mesh_file_check.hpp"

#include "animanifold/errors.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <vector>

namespace animanifold {

namespace {

// Fewest bytes an ASCII vertex ("0 0 0\n") and face ("3 0 1 2\n") take.
constexpr std::uint64_t kVertexBytes = 6, kFaceBytes = 8;
// A corner of a face is at least a digit and a separator.
constexpr std::uint64_t kCornerBytes = 2;
// PLY headers are a few hundred lines at most; this bounds reading a hostile one.
constexpr int kMaxHeaderLines = 10000;

// The count a token starts with, read as a C++ stream (and so CGAL's reader) reads it:
// the leading digits, whatever follows them ("32x" is 32); a number too large for 64 bits
// is the largest count, so that it is refused; nullopt without a leading digit.
std::optional<std::uint64_t> parse_count(const std::string& token) {
  std::uint64_t value = 0;
  const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (error == std::errc::result_out_of_range) return std::numeric_limits<std::uint64_t>::max();
  if (error != std::errc()) return std::nullopt;
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

// What a PLY header declares: enough to walk the body and find every list's length.
struct PlyProperty {
  bool list = false;
  int count_bytes = 0;  // a list's length field
  int value_bytes = 0;  // a scalar, or one list item
};
struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
};
struct PlyHeader {
  std::string format;  // ascii, binary_little_endian, binary_big_endian
  std::vector<PlyElement> elements;
  std::streamoff body = 0;
};

int ply_type_bytes(const std::string& type) {
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
  if (type == "int" || type == "uint" || type == "int32" || type == "uint32" || type == "float" || type == "float32")
    return 4;
  if (type == "double" || type == "float64") return 8;
  return 0;
}

// The header, with each element's count checked against the file's size
// (every property of every element takes a byte at least); nullopt when it
// is not one this check understands (CGAL then judges the file).
std::optional<PlyHeader> read_ply_header(std::ifstream& in, const std::string& path, std::uint64_t size) {
  std::string line;
  if (!std::getline(in, line) || line.rfind("ply", 0) != 0) return std::nullopt;
  PlyHeader header;
  std::uint64_t bytes = 0;
  for (int i = 0; i < kMaxHeaderLines && std::getline(in, line); ++i) {
    const auto t = tokens(line);
    if (t.empty()) continue;
    if (t[0] == "end_header") {
      header.body = in.tellg();
      return header;
    }
    if (t[0] == "format" && t.size() >= 2) header.format = t[1];
    if (t[0] == "element" && t.size() >= 3) {
      const auto declared = parse_count(t[2]);
      if (!declared) return std::nullopt;
      if (*declared > size)
        fail<IOError>("mesh file '", path, "' declares ", *declared, " ", t[1], " elements, more than its ", size,
                      " bytes can hold");
      header.elements.push_back({t[1], *declared, {}});
    } else if (t[0] == "property" && !header.elements.empty()) {
      const bool list = t.size() >= 5 && t[1] == "list";
      const PlyProperty p{list, list ? ply_type_bytes(t[2]) : 0, ply_type_bytes(list ? t[3] : t[1])};
      if (p.value_bytes == 0 || (list && p.count_bytes == 0)) return std::nullopt;
      header.elements.back().properties.push_back(p);
      bytes += header.elements.back().count;
      if (bytes > size)
        fail<IOError>("mesh file '", path, "' declares more element properties than its ", size, " bytes can hold");
    }
  }
  return std::nullopt;
}

[[noreturn]] void fail_list(const std::string& path, const PlyElement& e, std::uint64_t row, std::uint64_t length,
                            std::uint64_t size) {
  fail<IOError>("mesh file '", path, "': ", e.name, " ", row, " declares a list of ", length, " items, more than its ",
                size, " bytes can hold");
}

// ASCII bodies: every list item is at least a digit and a separator.
void check_ply_ascii_lists(std::ifstream& in, const PlyHeader& header, const std::string& path, std::uint64_t size) {
  std::string token;
  for (const PlyElement& e : header.elements)
    for (std::uint64_t row = 0; row < e.count; ++row)
      for (const PlyProperty& p : e.properties) {
        if (!(in >> token)) return;
        if (!p.list) continue;
        const auto length = parse_count(token);
        if (!length) return;
        if (*length > size / kCornerBytes) fail_list(path, e, row, *length, size);
        for (std::uint64_t i = 0; i < *length; ++i)
          if (!(in >> token)) return;
      }
}

std::uint64_t read_unsigned(std::ifstream& in, int bytes, bool big_endian) {
  unsigned char raw[8] = {};
  in.read(reinterpret_cast<char*>(raw), bytes);
  std::uint64_t value = 0;
  for (int i = 0; i < bytes; ++i) value |= std::uint64_t{raw[big_endian ? bytes - 1 - i : i]} << (8 * i);
  return value;
}

// Binary bodies: a list's items must fit in the bytes that remain.
void check_ply_binary_lists(std::ifstream& in, const PlyHeader& header, const std::string& path, std::uint64_t size) {
  const bool big_endian = header.format == "binary_big_endian";
  for (const PlyElement& e : header.elements)
    for (std::uint64_t row = 0; row < e.count; ++row)
      for (const PlyProperty& p : e.properties) {
        if (!p.list) {
          in.seekg(p.value_bytes, std::ios::cur);
        } else {
          const std::uint64_t length = read_unsigned(in, p.count_bytes, big_endian);
          if (!in) return;
          const std::uint64_t left = size - std::min<std::uint64_t>(size, static_cast<std::uint64_t>(in.tellg()));
          if (length > left / p.value_bytes) fail_list(path, e, row, length, size);
          in.seekg(static_cast<std::streamoff>(length * p.value_bytes), std::ios::cur);
        }
        if (!in) return;
      }
}

void check_ply(const std::string& path, std::uint64_t size) {
  std::ifstream in(path, std::ios::binary);
  const auto header = read_ply_header(in, path, size);
  if (!header) return;
  if (header->format == "ascii") check_ply_ascii_lists(in, *header, path, size);
  else if (header->format == "binary_little_endian" || header->format == "binary_big_endian")
    check_ply_binary_lists(in, *header, path, size);
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
