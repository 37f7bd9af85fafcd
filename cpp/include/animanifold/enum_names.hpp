// Names of enumeration values, as the Python API, the CLI and the add-on spell
// them. Each public header that declares an `enum class` users choose from
// also declares its table of names (kLaplacianMethodNames, ...); the binding
// exposes that table as a py::enum_, and Python builds its validation, CLI
// choices and Blender items from the bound enum, so the table is the only list.
#pragma once

#include "animanifold/errors.hpp"

#include <array>
#include <cstddef>
#include <string>
#include <utility>

namespace animanifold {

// Each value with its name, in the order users see them (the first is the
// default where the API has one).
template <class Enum, std::size_t N>
using NameTable = std::array<std::pair<Enum, const char*>, N>;

// Inputs:
//   value  an enumeration value
//   names  its table (kLaplacianMethodNames, ...)
// Outputs: the name `value` has in `names`; "?" for a value missing from the table
// Throws: nothing
template <class Enum, std::size_t N>
constexpr const char* name_of(Enum value, const NameTable<Enum, N>& names) {
  for (const auto& [v, name] : names)
    if (v == value) return name;
  return "?";
}

// Inputs:
//   names  a table of names
// Outputs: its names quoted, in table order: "'a', 'b' or 'c'" (for error messages)
// Throws: nothing (beyond std::bad_alloc)
template <class Enum, std::size_t N>
std::string quoted_choices(const NameTable<Enum, N>& names) {
  std::string text;
  for (std::size_t i = 0; i < N; ++i) {
    if (i > 0) text += i + 1 == N ? " or " : ", ";
    text += "'" + std::string(names[i].second) + "'";
  }
  return text;
}

// Inputs:
//   name   a name as users spell it (exact, case-sensitive)
//   names  the table to look it up in
//   what   how the message names the choice ("Laplacian method")
// Outputs: the value named `name` in `names`
// Throws: InputError "unknown <what> '<name>': use <choices>" when no entry has that
//   name (<choices> as quoted_choices gives them)
template <class Enum, std::size_t N>
Enum parse_name(const std::string& name, const NameTable<Enum, N>& names, const char* what) {
  for (const auto& [value, known] : names)
    if (name == known) return value;
  fail<InputError>("unknown ", what, " '", name, "': use ", quoted_choices(names));
}

}  // namespace animanifold
