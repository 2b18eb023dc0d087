"""``coastmesh formats``: the registry, listed; what each format holds."""

from __future__ import annotations

import pytest

from coastmesh.io import mesh_format, mesh_formats
from coastmesh.io.meshes._mesh_format import HOLDS, MeshFormat


def test_every_format_is_listed_with_what_it_holds(run_cli):
    result = run_cli("formats")
    assert result.exit_code == 0, result.output
    for name, fmt in mesh_formats().items():
        assert name in result.output
        assert fmt.model in result.output
    assert "+.cli" in result.output  # selafin's boundary file beside it
    table = run_cli("formats", "--markdown").output
    assert table.count("\n| `") == len(mesh_formats())


def test_the_registry_says_what_writers_of_cases_ask():
    assert "sphere_xyz" in mesh_format("msh2").holds
    assert "sphere_xyz" not in mesh_format("fort14").holds
    assert mesh_format("selafin").companions == (".cli",)
    assert mesh_format("mike").positive == "up" and mesh_format("msh4").positive is None
    for fmt in mesh_formats().values():
        assert fmt.holds <= set(HOLDS)
        # a format with depth has a sign, and its writer takes the option
        assert (fmt.positive is not None) == ("depth" in fmt.holds)
        if fmt.positive is not None and fmt.options is not None:
            assert "positive" in fmt.options or fmt.name in ("ugrid", "vtu", "gpkg")


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"holds": {"depth", "colour"}}, r"holds \['colour'\]"),
        ({"positive": "sideways"}, "positive = 'sideways'"),
        ({"companions": ("cli",)}, "companion 'cli' must start with '.'"),
    ],
)
def test_a_format_that_claims_what_no_format_holds_is_refused(kwargs, message):
    write = mesh_format("vtu").write
    with pytest.raises(ValueError, match=message):
        MeshFormat("x", (".x",), write, "x", **kwargs)
