"""The handle transform of Laplacian deformation: the motion of an Empty.

Its world matrix is recorded on the target object the first time it is used (custom
properties), and each run applies current · rest⁻¹ (in the object's local space; for a
manifold lifted to 5x5 with time left alone) and records the current matrix as the new
rest, so moving the Empty and running again continues from the result.
"""

from __future__ import annotations

import bpy
import numpy as np

from . import messages
from .reporting import OperatorError

REST_KEY = "animanifold_deform_rest"
REST_EMPTY_KEY = "animanifold_deform_empty"


def matrix(value) -> np.ndarray:
    """A Blender matrix as a numpy array."""
    return np.array([list(row) for row in value], dtype=np.float64)


def empty_for(obj, name: str, settings):
    """The Empty named `name`, or the panel's (`settings.empty`) when no name is given."""
    empty = bpy.data.objects.get(name) if name else settings.empty
    if name and empty is None:
        raise OperatorError(f"there is no object '{name}' to drive the handles")
    if empty is None:
        raise OperatorError(f"choose an Empty to drive the handles of '{obj.name}'")
    if empty.type != "EMPTY":
        raise OperatorError(f"'{empty.name}' is {messages.object_type(empty)}, not an Empty")
    return empty


def recorded_rest(obj, empty) -> np.ndarray | None:
    rest = obj.get(REST_KEY)
    if rest is None or obj.get(REST_EMPTY_KEY) != empty.name:
        return None
    return np.asarray(list(rest), dtype=np.float64).reshape(4, 4)


def record_rest(obj, empty) -> None:
    obj[REST_KEY] = [float(x) for x in matrix(empty.matrix_world).reshape(-1)]
    obj[REST_EMPTY_KEY] = empty.name


def local_transform(obj, empty, rest: np.ndarray, dimension: int) -> np.ndarray:
    """current · rest⁻¹ of the Empty, in `obj`'s local space; (D+1)x(D+1), time kept for D = 4."""
    O = matrix(obj.matrix_world)
    world = matrix(empty.matrix_world) @ np.linalg.inv(rest)
    M = np.linalg.inv(O) @ world @ O
    if dimension == 3:
        return M
    T = np.eye(5)
    T[:3, :3] = M[:3, :3]
    T[:3, 4] = M[:3, 3]
    return T
