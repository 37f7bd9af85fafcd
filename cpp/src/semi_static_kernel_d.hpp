// CGAL's dD kernel with its two Delaunay predicates first tried in double
// precision (certain_determinant.hpp): a Delaunay triangulation's traits for
// delaunay_exact(). Include only where CGAL's dD Triangulation is built.
//
// Epick_d answers Orientation_d and Side_of_oriented_sphere_d exactly, with
// interval arithmetic before exact arithmetic; here a double evaluation with
// an error bound answers first, and Epick_d's predicate wherever that bound
// leaves the sign open (cospherical points, nearly flat cells). The answers
// are the exact signs either way, so the triangulation is the one Epick_d
// builds (the same cells, the same ties broken by its symbolic perturbation).
#pragma once

#include "certain_determinant.hpp"

#include <CGAL/Epick_d.h>

#include <array>
#include <optional>

namespace animanifold {

template <int D>
struct SemiStaticKernel : CGAL::Epick_d<CGAL::Dimension_tag<D>> {
  using Exact = CGAL::Epick_d<CGAL::Dimension_tag<D>>;
  using Point_d = typename Exact::Point_d;

  // The sign of det(p_1 - p_0, ..., p_D - p_0) for the D + 1 points of [first, last).
  struct Orientation_d {
    typename Exact::Orientation_d exact;
    template <class Iter>
    CGAL::Orientation operator()(Iter first, Iter last) const {
      std::array<std::array<double, D>, D> m;
      const Point_d& origin = *first;
      Iter it = first;
      ++it;
      for (int row = 0; row < D; ++row, ++it) {
        const Point_d& p = *it;
        for (int c = 0; c < D; ++c) m[row][c] = p[c] - origin[c];
      }
      if (const std::optional<int> sign = certain_sign<D>(m, Columns::Differences)) return CGAL::Orientation(*sign);
      return exact(first, last);
    }
  };

  // Whether `query` lies inside (ON_POSITIVE_SIDE), on or outside the sphere
  // through the D + 1 points of [first, last) (positively oriented), as
  // Epick_d's: the sign of the lifted determinant of p_i - query, negated in
  // odd dimensions.
  struct Side_of_oriented_sphere_d {
    typename Exact::Side_of_oriented_sphere_d exact;
    template <class Iter>
    CGAL::Oriented_side operator()(Iter first, Iter last, const Point_d& query) const {
      std::array<std::array<double, D + 1>, D + 1> m;
      Iter it = first;
      for (int row = 0; row <= D; ++row, ++it) {
        const Point_d& p = *it;
        double lifted = 0;
        for (int c = 0; c < D; ++c) {
          m[row][c] = p[c] - query[c];
          lifted += m[row][c] * m[row][c];
        }
        m[row][D] = lifted;
      }
      if (const std::optional<int> sign = certain_sign<D + 1>(m, Columns::Lifted))
        return CGAL::Oriented_side(D % 2 ? -*sign : *sign);
      return exact(first, last, query);
    }
  };

  Orientation_d orientation_d_object() const { return {Exact::orientation_d_object()}; }
  Side_of_oriented_sphere_d side_of_oriented_sphere_d_object() const {
    return {Exact::side_of_oriented_sphere_d_object()};
  }
};

}  // namespace animanifold
