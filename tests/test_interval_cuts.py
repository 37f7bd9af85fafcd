"""Live playback's cuts (interval_cuts): a frame's arrays, and the corner UVs keys share."""

from __future__ import annotations

import dataclasses

import numpy as np

from animanifold import interval_cuts
from animanifold.slices import Slice
from helpers.cuts import cut


def test_a_frame_moves_each_vertex_and_uv_along_its_rate():
    c = cut()
    c.vertices[:] = np.arange(18).reshape(6, 3) / 8.0
    c.rate[:] = np.arange(18).reshape(6, 3) / -32.0
    c.uv[:, :2] = np.arange(12).reshape(6, 2) / 16.0
    c.uv_rate[:, :2] = np.arange(12).reshape(6, 2) / -64.0
    c.faces = np.array([[5, 0, 3], [1, 4, 2]], np.int32)
    f = interval_cuts.interval_frame(c, 8.0)
    assert f.value == 8.0 and f.positions.dtype == f.corner_uv.dtype == np.float32
    np.testing.assert_allclose(f.positions.reshape(-1, 3), c.vertices + 3.0 * c.rate, atol=1e-7)
    np.testing.assert_allclose(f.corner_uv.reshape(-1, 2), (c.uv[:, :2] + 3.0 * c.uv_rate[:, :2])[c.faces.reshape(-1)],
                               atol=1e-7)
    assert f.nbytes() == interval_cuts.frame_nbytes(c) == 4 * (18 + 12)
    own = interval_cuts.interval_frame(c, c.value)  # the cut's own arrays, not copies
    assert np.shares_memory(own.positions, c.vertices) and own.corner_uv is c.corner_uv
    c.uv_rate = None  # no UVs: positions only
    assert interval_cuts.interval_frame(c, 8.0).corner_uv is None and interval_cuts.frame_nbytes(c) == 4 * 18


def test_keys_sharing_unchangeable_faces_and_uvs_share_their_corner_uvs():
    faces = np.array([[0, 1, 2], [2, 1, 3]], np.int32)
    faces.flags.writeable = False
    uv = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])
    uv.flags.writeable = False
    key = Slice(axis=3, value=1.0, vertices=np.zeros((4, 3)), faces=faces, normals=None,
                vertex_attributes={"uv": uv})
    one, two = interval_cuts.vertex_time_cut(key), interval_cuts.vertex_time_cut(dataclasses.replace(key, value=2.0))
    assert one.faces is faces and two.faces is faces  # kept, not copied
    assert two.corner_uv is one.corner_uv
    np.testing.assert_array_equal(one.corner_uv.reshape(-1, 2), uv[faces.reshape(-1)])
    moving = uv + 0.5  # a writeable array may change: its corners are gathered again
    three = interval_cuts.vertex_time_cut(dataclasses.replace(key, vertex_attributes={"uv": moving}))
    np.testing.assert_array_equal(three.corner_uv.reshape(-1, 2), moving[faces.reshape(-1)])
    writeable = np.array(faces)
    assert interval_cuts.vertex_time_cut(dataclasses.replace(key, faces=writeable)).faces is not writeable
