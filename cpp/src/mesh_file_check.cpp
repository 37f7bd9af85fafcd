#include "mesh_file_check.hpp"

#include "animanifold/errors.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
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
// The bytes searched for a binary OFF file's BINARY line (blank lines and comments included).
constexpr std::uint64_t kMaxBinaryOffHeader = 4096;

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

// What an OFF keyword ([ST][C][N][4][n]OFF) says each vertex line carries.
struct OffLayout {
  bool textures = false, colours = false, normals = false, homogeneous = false, dimensional = false;
  // A vertex line's coordinates and normal come first, then its colour, then its texture coordinates.
  std::size_t colour_at() const {
    const std::size_t h = homogeneous ? 1 : 0;
    return (3 + h) + (normals ? 3 + h : 0);
  }
  std::size_t vertex_entries() const { return colour_at() + (textures ? 2 + (homogeneous ? 1 : 0) : 0); }
};

std::optional<OffLayout> off_layout(const std::string& keyword) {
  if (keyword.size() < 3 || keyword.compare(keyword.size() - 3, 3, "OFF") != 0) return std::nullopt;
  OffLayout layout;
  std::size_t i = 0;
  const auto take = [&](const char* prefix) {
    const std::size_t n = std::char_traits<char>::length(prefix);
    if (keyword.compare(i, n, prefix) != 0 || i + n > keyword.size() - 3) return false;
    i += n;
    return true;
  };
  layout.textures = take("ST");
  layout.colours = take("C");
  layout.normals = take("N");
  layout.homogeneous = take("4");
  layout.dimensional = take("n");
  return layout;
}

// The numbers a line starts with, as CGAL's OFF scanner reads them: up to a '#' comment,
// stopping at the first token that does not start with a number.
std::vector<double> leading_numbers(const std::vector<std::string>& line) {
  std::string text;
  for (const std::string& t : line) text += t + " ";
  text = text.substr(0, text.find('#'));
  std::istringstream in(text);
  std::vector<double> out;
  for (double d; in >> d;) out.push_back(d);
  return out;
}

// CGAL 5.5's ASCII OFF scanner indexes a line's entries by what the keyword promises without
// checking the line holds them: a colour of 2 entries, a colour-map index outside its 149
// entries, or a line shorter than its coordinates reads out of bounds (a crash, found by
// fuzzing). So a colour must be 0, 3 or 4 numbers, or 1 whole number that names a map
// entry, the same count on every line (the scanner keeps the first line's decision).
//   fixed      how many numbers the line holds besides its colour
//   colour_at  where its colour starts
void check_off_colour(const std::string& path, const char* what, std::uint64_t row, const std::vector<double>& entries,
                      std::size_t fixed, std::size_t colour_at, std::optional<std::size_t>& count) {
  constexpr double kColourMapEntries = 149;
  const std::size_t first = fixed;
  const std::size_t colour = entries.size() - first;
  if (entries.size() < first || (colour != 0 && colour != 1 && colour != 3 && colour != 4))
    fail<IOError>("mesh file '", path, "': ", what, " ", row, " has ", entries.size(), " numbers, which leaves ",
                  entries.size() < first ? 0 : colour, " for its colour (expected 0, 1, 3 or 4 after ", first, ")");
  const double index = colour == 1 ? entries[colour_at] : 0;
  if (!(index >= 0 && index < kColourMapEntries && index == std::floor(index)))
    fail<IOError>("mesh file '", path, "': ", what, " ", row, " names colour-map entry ", index,
                  ", not one of 0..148");
  if (count && *count != colour)
    fail<IOError>("mesh file '", path, "': ", what, " ", row, " has a colour of ", colour, " numbers where the first had ",
                  *count);
  count = colour;
}

void check_off_vertices(std::istream& in, const std::string& path, const OffLayout& layout, std::uint64_t vertices) {
  std::optional<std::size_t> colour;
  for (std::uint64_t v = 0; v < vertices; ++v) {
    const auto line = next_content_line(in);
    if (!line) return;
    if (!layout.colours) continue;  // CGAL checks the lengths it reads
    const auto entries = leading_numbers(*line);
    if (layout.colours) {
      check_off_colour(path, "vertex", v, entries, layout.vertex_entries(), layout.colour_at(), colour);
    }
  }
}

void check_off_faces(std::istream& in, const std::string& path, const OffLayout& layout, std::uint64_t faces,
                     std::uint64_t size) {
  std::optional<std::size_t> colour;
  for (std::uint64_t f = 0; f < faces; ++f) {
    const auto face = next_content_line(in);
    if (!face) return;
    const auto corners = parse_count((*face)[0]);
    if (corners && *corners > size / kCornerBytes)
      fail<IOError>("mesh file '", path, "': face ", f, " declares ", *corners, " corners, more than its ", size,
                    " bytes can hold");
    if (!layout.colours) continue;
    const auto entries = leading_numbers(*face);
    if (entries.empty() || !(entries[0] >= 0 && entries[0] <= static_cast<double>(size)))
      fail<IOError>("mesh file '", path, "': face ", f, " does not start with a corner count");
    const auto fixed = static_cast<std::size_t>(entries[0]) + 1;
    check_off_colour(path, "face", f, entries, fixed, fixed, colour);
  }
}

// Where an OFF file's binary body starts, found as CGAL 5.5's header reader finds it: blanks
// and '#' comment lines, the keyword (and the character that ends it), blanks and comments
// again, then the word BINARY and the rest of its line. nullopt for an ASCII file, or when
// `head` (the file's first bytes) ends first.
std::optional<std::uint64_t> off_binary_body(const std::string& head) {
  std::size_t p = 0;
  const auto skip_blanks_and_comments = [&] {
    while (p < head.size()) {
      if (std::isspace(static_cast<unsigned char>(head[p]))) ++p;
      else if (head[p] == '#') p = std::min(head.find('\n', p), head.size());
      else return true;
    }
    return false;
  };
  // A word: its first character and the letters and digits after it; the character that
  // ends it is read too. Returns that character (or '\0' at the end of `head`).
  const auto word = [&](std::string& out) {
    out.assign(1, head[p++]);
    while (p < head.size() && std::isalnum(static_cast<unsigned char>(head[p]))) out += head[p++];
    return p < head.size() ? head[p++] : '\0';
  };
  std::string keyword, binary;
  if (!skip_blanks_and_comments()) return std::nullopt;
  word(keyword);
  if (!skip_blanks_and_comments()) return std::nullopt;
  const char end = word(binary);
  if (binary != "BINARY") return std::nullopt;
  if (end != '\n') {
    p = head.find('\n', p);
    if (p == std::string::npos) return std::nullopt;
    ++p;
  }
  return p;
}

std::int64_t read_int32_big_endian(std::istream& in) {
  unsigned char raw[4] = {};
  in.read(reinterpret_cast<char*>(raw), 4);
  const std::uint32_t bits = std::uint32_t{raw[0]} << 24 | std::uint32_t{raw[1]} << 16 | std::uint32_t{raw[2]} << 8 | raw[3];
  return static_cast<std::int32_t>(bits);
}

// Binary OFF: big-endian int32 counts ([dimension,] vertices, faces, edges), then each
// vertex's float32 coordinates (and normal, texture coordinates), then each face as an int32
// corner count and as many int32 indices (CGAL reads no colours in binary files). Counts
// are refused when the bytes left cannot hold them; a negative count CGAL would take as a
// size_t near 2^64.
void check_off_binary(std::istream& in, const std::string& path, const OffLayout& layout, std::uint64_t body,
                      std::uint64_t size) {
  const std::uint64_t header = layout.dimensional ? 16 : 12;
  if (body + header > size) return;  // CGAL fails to read the counts
  in.clear();
  in.seekg(static_cast<std::streamoff>(body));
  if (layout.dimensional) read_int32_big_endian(in);
  const std::int64_t vertices = read_int32_big_endian(in), faces = read_int32_big_endian(in);
  read_int32_big_endian(in);  // edges
  const std::uint64_t left = size - body - header;
  // A vertex's floats: coordinates, normal, texture coordinates (each one more when
  // homogeneous); n-dimensional vertices take at least one.
  const std::uint64_t h = layout.homogeneous ? 1 : 0;
  const std::uint64_t vertex_bytes =
      layout.dimensional ? 4 : 4 * ((3 + h) + (layout.normals ? 3 + h : 0) + (layout.textures ? 2 + h : 0));
  constexpr std::uint64_t kBinaryFaceBytes = 4;  // its corner count
  if (vertices < 0 || faces < 0 || static_cast<std::uint64_t>(vertices) > left / vertex_bytes ||
      static_cast<std::uint64_t>(vertices) * vertex_bytes + static_cast<std::uint64_t>(faces) * kBinaryFaceBytes > left)
    fail<IOError>("mesh file '", path, "' (binary OFF) declares ", vertices, " vertices and ", faces,
                  " faces, more than its ", size, " bytes can hold");
  if (layout.dimensional) return;  // their vertices' size is not known here
  in.seekg(static_cast<std::streamoff>(vertices) * static_cast<std::streamoff>(vertex_bytes), std::ios::cur);
  for (std::int64_t f = 0; f < faces; ++f) {
    const std::int64_t corners = read_int32_big_endian(in);
    if (!in) return;
    const std::uint64_t after = size - std::min<std::uint64_t>(size, static_cast<std::uint64_t>(in.tellg()));
    if (corners < 0 || static_cast<std::uint64_t>(corners) > after / 4)
      fail<IOError>("mesh file '", path, "' (binary OFF): face ", f, " declares ", corners, " corners, more than its ",
                    size, " bytes can hold");
    in.seekg(static_cast<std::streamoff>(corners) * 4, std::ios::cur);
  }
}

void check_off(const std::string& path, std::uint64_t size) {
  std::ifstream in(path, std::ios::binary);
  auto header = next_content_line(in);
  if (!header) return;
  // CGAL's keyword is the line's first character and the letters and digits after it.
  const std::string& first = (*header)[0];
  const auto keyword_end = std::find_if(first.begin() + 1, first.end(), [](unsigned char c) { return !std::isalnum(c); });
  const auto layout = off_layout(std::string(first.begin(), keyword_end));
  if (!layout) return;
  std::string head(static_cast<std::size_t>(std::min<std::uint64_t>(size, kMaxBinaryOffHeader)), '\0');
  in.clear();
  in.seekg(0);
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  if (const auto body = off_binary_body(head)) return check_off_binary(in, path, *layout, *body, size);
  in.clear();
  in.seekg(0);
  next_content_line(in);  // the keyword's line again
  if (std::find(header->begin(), header->end(), "BINARY") != header->end()) return;  // beyond `head`: CGAL judges it
  // CGAL 5.5 finds a vertex's texture coordinates behind its colour, reading uninitialised
  // positions when the file has none; n-dimensional lines are not laid out as checked here.
  if ((layout->textures && !layout->colours) || (layout->dimensional && layout->colours))
    fail<IOError>("mesh file '", path, "': '", (*header)[0],
                  "' files are not supported (texture coordinates without colours, or n-dimensional with colours)");
  // The counts follow the keyword on its line, or on the next one.
  std::vector<std::string> counts(header->begin() + 1, header->end());
  if (counts.empty()) counts = next_content_line(in).value_or(std::vector<std::string>{});
  if (counts.size() < 2) return;
  const auto vertices = parse_count(counts[0]), faces = parse_count(counts[1]);
  if (!vertices || !faces) return;
  check_counts_fit(path, size, *vertices, *faces);
  if (layout->colours && counts.size() < 3)
    fail<IOError>("mesh file '", path, "': the counts line of a '", (*header)[0],
                  "' file must hold the vertex, face and edge counts");
  check_off_vertices(in, path, *layout, *vertices);
  check_off_faces(in, path, *layout, *faces, size);
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
      if (t.size() < 3) return std::nullopt;  // no type and name: CGAL judges it
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

// Binary STL: an 80-byte header, a little-endian uint32 triangle count, 50 bytes per
// triangle. CGAL 5.5 reads a file that starts (after blanks) with "solid" and a blank as
// ASCII, any other as binary; its binary reader reads triangle by triangle, so a count beyond
// the file fails late with CGAL's words: refused here with the count.
void check_stl(const std::string& path, std::uint64_t size) {
  constexpr std::uint64_t kHeader = 84, kTriangle = 50;
  std::ifstream in(path, std::ios::binary);
  std::string head(static_cast<std::size_t>(std::min<std::uint64_t>(size, kMaxBinaryOffHeader)), '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  const std::size_t first = head.find_first_not_of(" \t\n\v\f\r");
  if (first == std::string::npos) return;  // blank (as far as read): nothing to count
  const bool ascii = head.compare(first, 5, "solid") == 0 && first + 5 < head.size() &&
                     (head[first + 5] == ' ' || head[first + 5] == '\n' || head[first + 5] == '\r');
  if (ascii || size < kHeader) return;
  std::uint64_t triangles = 0;
  for (int i = 3; i >= 0; --i) triangles = triangles << 8 | static_cast<unsigned char>(head[80 + i]);
  if (kHeader + triangles * kTriangle > size)
    fail<IOError>("mesh file '", path, "' (binary STL: it does not start with 'solid') declares ", triangles,
                  " triangles, more than its ", size, " bytes can hold (84 + 50 per triangle)");
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
  else if (ext == ".stl") check_stl(path, size);
}

}  // namespace animanifold
