"""A frame with how it moves inside its topology interval: what live playback plays.

Between two consecutive vertex coordinates along the slicing axis every slice
has the same faces, and each of its vertices slides linearly along one
manifold edge. The core (``Slicer::interval_frame``, slice.hpp) cuts the frame
once and gives every vertex's rate; a frame anywhere in the interval is then a
multiply-add over the slice's vertices, with no slicing.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import TYPE_CHECKING, Iterable, Mapping

import numpy as np

from . import _core
from ._core import InputError

if TYPE_CHECKING:
    from .slices import Slice


@dataclass(frozen=True)
class IntervalFrame:
    """The frame `slice` with its topology interval (lo, hi) and rates.

    At any value v in the open interval the slice has `slice`'s faces,
    vertex_edges and face attributes, and is::

        vertices          = slice.vertices          + (v - slice.value) * rate
        vertex_attributes = slice.vertex_attributes + (v - slice.value) * attribute_rates
        edge_parameter    = slice.edge_parameter    + (v - slice.value) * parameter_rate

    which :meth:`at` computes. Rates of one-column attributes are vectors, as
    the attributes are.
    """

    slice: "Slice"
    interval: tuple[float, float]
    rate: np.ndarray  # (P, D-1)
    attribute_rates: Mapping[str, np.ndarray]
    parameter_rate: np.ndarray  # (P,)

    @property
    def value(self) -> float:
        return self.slice.value

    def at(self, value: float, attributes: Iterable[str] | None = None, normals: bool = True) -> "Slice":
        """The slice at `value` (in the interval). `attributes` names the vertex
        attributes to carry (default: all). The smooth normals, which are not
        linear in the value, are recomputed from the moved vertices: now, or with
        `normals=False` when first read (a caller that never reads them skips them)."""
        lo, hi = self.interval
        if not lo < value < hi:
            raise InputError(f"value {value} is not in the topology interval {self.interval} "
                             f"of the slice at {self.value}")
        dt = float(value) - self.value
        vertices = self.slice.vertices + dt * self.rate
        names = self.attribute_rates.keys() if attributes is None else attributes
        moved = {name: self.slice.vertex_attributes[name] + dt * self.attribute_rates[name]
                 for name in names if name in self.attribute_rates}
        return dataclasses.replace(
            self.slice, value=float(value), vertices=vertices, vertex_attributes=moved,
            normals=_core.frame_vertex_normals(vertices, self.slice.faces) if normals else None,
            edge_parameter=self.slice.edge_parameter + dt * self.parameter_rate)
