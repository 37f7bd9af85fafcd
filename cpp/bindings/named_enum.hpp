// A core enumeration as a py::enum_ whose values are its table's names
// (animanifold/enum_names.hpp), lower case as users type them.
#pragma once

#include "animanifold/enum_names.hpp"
#include "bindings.hpp"

namespace animanifold::bindings {

// Binds `Enum` as `type` with the values of `names`, in their order (so
// `__members__` lists the choices as users see them). A str of one of the
// names converts to it ("dual" for LaplacianMethod.dual), so every binding
// that takes the enum also takes the string the API documents; an unknown
// string raises InputError naming it and the choices.
template <class Enum, std::size_t N>
py::enum_<Enum> bind_named_enum(py::module_& m, const char* type, const char* what, const NameTable<Enum, N>& names,
                                const char* doc) {
  py::enum_<Enum> e(m, type, doc);
  for (const auto& [value, name] : names) e.value(name, value);
  e.def(py::init([names, what](const std::string& name) { return parse_name(name, names, what); }),
        py::arg("name"), "The value named `name`.");
  py::implicitly_convertible<std::string, Enum>();
  return e;
}

}  // namespace animanifold::bindings
