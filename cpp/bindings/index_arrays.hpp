// Index arrays crossing into the core. The core takes int32 indices
// (types.hpp); left to itself numpy converts any other dtype silently, so an
// int64 index of 2^32 would wrap to 0 and a float index of 2.7 would become 2.
// The casters below refuse both with an InputError naming the entry, before
// anything is converted. int32 arrays still map without a copy.
//
// Included by bindings.hpp, so that every binding translation unit sees the
// same specialisations (they replace pybind11's Eigen and map casters for
// these exact types).
#pragma once

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <climits>
#include <memory>
#include <optional>
#include <string>

#include "animanifold/errors.hpp"
#include "animanifold/types.hpp"

namespace animanifold::bindings {

namespace py = pybind11;

// C-contiguous int32 inputs map onto these without a copy.
using SimplicesRef = Eigen::Ref<const SimplexMatrix>;
using IndicesRef = Eigen::Ref<const IndexVector>;

// Where entry `flat` of an array of `shape` sits, as "row r, column c".
inline std::string index_array_position(const py::array& a, py::ssize_t flat) {
  if (a.ndim() < 2) return "row " + std::to_string(flat);
  const py::ssize_t cols = a.shape(a.ndim() - 1);
  return "row " + std::to_string(flat / cols) + ", column " + std::to_string(flat % cols);
}

// Inputs:
//   src   what Python passed for an index array (ndarray, list, ...)
//   what  how the message names it ("an index array", "face attribute 'material'")
// Throws InputError when src holds values an int32 index cannot keep: a
// non-integer dtype (float, bool, object) or integers outside int32. Objects
// numpy cannot turn into an array are left to the caster (a TypeError).
inline void check_index_array(py::handle src, const std::string& what) {
  if (py::isinstance<py::array_t<Index>>(src)) return;
  py::array a = py::array::ensure(src);
  if (!a || a.size() == 0) return;
  const char kind = a.dtype().kind();
  if (kind != 'i' && kind != 'u')
    fail<InputError>(what, " has dtype ", py::str(a.dtype()).cast<std::string>(), ": indices must be integers");
  const py::int_ lowest(INT32_MIN), highest(INT32_MAX);
  const py::int_ lo(a.attr("min")()), hi(a.attr("max")());
  const bool low = lo < lowest, high = hi > highest;
  if (!low && !high) return;
  const auto flat = (low ? a.attr("argmin") : a.attr("argmax"))().cast<py::ssize_t>();
  fail<InputError>(what, " holds ", py::str(low ? lo : hi).cast<std::string>(), " at ",
                   index_array_position(a, flat), ", which does not fit a 32-bit index");
}

}  // namespace animanifold::bindings

namespace pybind11::detail {

// Loads Eigen::Ref<const M> (M of animanifold::Index) after check_index_array;
// what it cannot map it copies into an int32 array it keeps for the call.
template <class RefType>
struct checked_index_ref_caster {
  using Plain = typename RefType::PlainObject;
  using props = EigenProps<RefType>;
  using Array = array_t<animanifold::Index, array::c_style | array::forcecast>;

  bool load(handle src, bool convert) {
    if (!convert && !isinstance<Array>(src)) return false;
    if (convert) animanifold::bindings::check_index_array(src, "an index array");
    Array a = Array::ensure(src);
    if (!a) {
      PyErr_Clear();
      return false;
    }
    const auto fits = props::conformable(a);
    if (!fits) return false;
    array_ = std::move(a);
    map_ = std::make_unique<Eigen::Map<const Plain>>(array_.data(), fits.rows, fits.cols);
    ref_ = std::make_unique<RefType>(*map_);
    return true;
  }

  static constexpr auto name = props::descriptor;
  operator RefType*() { return ref_.get(); }
  operator RefType&() { return *ref_; }
  template <typename T>
  using cast_op_type = pybind11::detail::cast_op_type<T>;

 private:
  Array array_;
  std::unique_ptr<Eigen::Map<const Plain>> map_;
  std::unique_ptr<RefType> ref_;
};

template <>
struct type_caster<animanifold::bindings::SimplicesRef>
    : checked_index_ref_caster<animanifold::bindings::SimplicesRef> {};
template <>
struct type_caster<animanifold::bindings::IndicesRef> : checked_index_ref_caster<animanifold::bindings::IndicesRef> {};

// Integer attribute tables (material index, source face, ...) by name: each
// table is checked like an index array before pybind11's map caster converts it.
template <>
struct type_caster<animanifold::SimplexAttributes>
    : map_caster<animanifold::SimplexAttributes, std::string, animanifold::SimplexMatrix> {
  bool load(handle src, bool convert) {
    if (convert && isinstance<dict>(src))
      for (auto [key, table] : reinterpret_borrow<dict>(src))
        animanifold::bindings::check_index_array(table, "integer attribute '" + str(key).cast<std::string>() + "'");
    return map_caster::load(src, convert);
  }
};

// Optional index tables (subdivide_frame's crease_edges).
template <>
struct type_caster<std::optional<animanifold::SimplexMatrix>>
    : optional_caster<std::optional<animanifold::SimplexMatrix>> {
  bool load(handle src, bool convert) {
    if (convert && !src.is_none()) animanifold::bindings::check_index_array(src, "an index array");
    return optional_caster::load(src, convert);
  }
};

}  // namespace pybind11::detail
