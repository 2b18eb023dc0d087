"""The advice warnings a case gives after its mesh is measured."""

from __future__ import annotations

import warnings
from types import SimpleNamespace

import numpy as np
import pytest

from coastmesh.case.pipeline.advice import warn_spanning
from coastmesh.errors import CoastmeshWarning
from coastmesh.meshing import mesh_quality
from coastmesh.types import Mesh


def _strip(n: int = 6) -> Mesh:
    """A strip 1 wide: shoreline below (id 1), open boundary above (id 2).

    Every node is on the boundary, so every triangle spans the strip.
    """
    bottom = [[float(i), 0.0] for i in range(n)]
    top = [[float(i), 1.0] for i in range(n)]
    points = bottom + top
    tri = []
    for i in range(n - 1):
        tri += [[i, i + 1, n + i + 1], [i, n + i + 1, n + i]]
    edges = [[i, i + 1] for i in range(n - 1)] + [[n - 1, 2 * n - 1]]
    edges += [[n + i + 1, n + i] for i in range(n - 1)] + [[n, 0]]
    ids = [1] * (n - 1) + [1] + [2] * (n - 1) + [1]
    return Mesh(
        points,
        tri,
        edges,
        ids,
        1,
        None,
        boundary_names={1: "coast", 2: "north"},
        boundary_kinds={1: "shoreline", 2: "open"},
    )


def test_spanning_triangles_next_to_an_open_boundary_get_that_advice():
    mesh = _strip()
    quality = mesh_quality(mesh)
    spanning = quality.channel_spanning_triangles
    assert len(spanning) > 0  # the quality report finds them
    with pytest.warns(CoastmeshWarning) as caught:
        warn_spanning(quality, mesh, cell=0.5, h_min=1.0, narrow="keep")
    message = str(caught[0].message)
    assert message.startswith(f"{len(spanning):,} triangles span a channel")
    assert f"{len(spanning):,} of them lie between an open boundary" in message
    assert "(north: " in message and "move the open boundary off the coast" in message
    assert 'narrow = "close"' in message
    assert "size grid" not in message  # the grid is finer than h_min


def test_a_coarse_grid_and_closed_channels_get_their_own_advice():
    mesh = _strip()
    quality = SimpleNamespace(channel_spanning_triangles=np.array([0]))
    with pytest.warns(CoastmeshWarning, match=r"size grid \(3 m\) is coarser"):
        warn_spanning(quality, mesh, cell=3.0, h_min=1.0, narrow="close")
    # the same strip with shoreline all round: closed channels and a fine grid
    # leave only the advice to lower h_min
    far = Mesh(
        mesh.points,
        mesh.triangles,
        mesh.boundary_edges,
        np.ones(len(mesh.boundary_ids), dtype=np.int64),
        1,
        None,
        boundary_names={1: "coast"},
        boundary_kinds={1: "shoreline"},
    )
    with pytest.warns(CoastmeshWarning, match=r"lower h_min to resolve them"):
        warn_spanning(quality, far, cell=1.0, h_min=1.0, narrow="close")


def test_no_spanning_triangle_no_warning():
    mesh = _strip()
    quality = SimpleNamespace(channel_spanning_triangles=np.zeros(0, dtype=np.int64))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        warn_spanning(quality, mesh, cell=1.0, h_min=1.0, narrow="keep")
