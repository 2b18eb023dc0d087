"""The checks every model writer shares: one node-depth check, one kinds check."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from io_meshes import strip_mesh

from coastmesh.errors import CoastmeshWarning, ConfigError, FormatError
from coastmesh.io.meshes import _model, mike, telemac
from coastmesh.io.meshes.adcirc import _write, write_fort14, write_gr3
from coastmesh.io.meshes.mike import write_mike_mesh
from coastmesh.io.meshes.telemac import write_selafin
from coastmesh.types import Mesh

# writer, file name, what the format calls the value written at the nodes
WRITERS = [
    (write_fort14, "fort.14", "depth"),
    (write_gr3, "hgrid.gr3", "depth"),
    (write_mike_mesh, "grid.mesh", "z"),
    (write_selafin, "grid.slf", "BOTTOM"),
]


def without_depth(mesh: Mesh, **point_data) -> Mesh:
    return dataclasses.replace(mesh, point_data=point_data)


def test_one_check_for_all_writers():
    for module in (_write, mike, telemac):
        assert module.node_depth is _model.node_depth
        assert module.require_kinds is _model.require_kinds


@pytest.mark.parametrize(("writer", "name", "label"), WRITERS)
def test_missing_depth_warns_at_the_caller_and_names_the_file(
    tmp_path, writer, name, label
):
    mesh = without_depth(strip_mesh(4, 3))
    with pytest.warns(CoastmeshWarning, match=f"{name}: .*writing {label} 0") as caught:
        writer(tmp_path / name, mesh)
    assert len(caught) == 1 and caught[0].filename == __file__


@pytest.mark.parametrize(("writer", "name", "label"), WRITERS)
@pytest.mark.parametrize(
    ("depth", "match"),
    [
        (np.ones((12, 2)), r"has shape \(12, 2\).*expected \(12,\) numbers"),
        (np.array(["a"] * 12), "dtype <U1"),
        (np.where(np.arange(12) == 5, np.inf, 1.0), r"inf at node 5 \(1 nodes"),
    ],
)
def test_bad_depth_is_refused_naming_the_file(
    tmp_path, writer, name, label, depth, match
):
    mesh = without_depth(strip_mesh(4, 3), depth=depth)
    with pytest.raises(FormatError, match=f"{name}: point_data\\['depth'\\] .*{match}"):
        writer(tmp_path / name, mesh)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("positive", ["down", "up"])
def test_sign(positive):
    mesh = strip_mesh(4, 3)
    got = _model.node_depth(mesh, "m", positive=positive)
    sign = 1 if positive == "down" else -1
    np.testing.assert_array_equal(got, sign * mesh.point_data["depth"])
    with pytest.raises(ConfigError, match="m: positive='sideways'"):
        _model.node_depth(mesh, "m", positive="sideways")
    assert mesh.point_data["depth"][0] == 10.0  # the input is not changed


def test_missing_kinds_name_the_ids_and_the_hint():
    mesh = strip_mesh(4, 3, kinds={1: "shoreline"})
    with pytest.raises(FormatError, match=r"f: boundary id\(s\) 2 \('sea'\).*; try"):
        _model.require_kinds(mesh, "f", hint="; try this")
