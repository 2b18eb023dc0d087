"""The hard-coast cases of ``tests/data/coasts``: they parse, their data is there,
and they give the default keys only (what ``tests/e2e/test_model_ready.py``
builds).
"""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest

import coastmesh

COASTS = Path(__file__).parents[1] / "data" / "coasts"
CASES = sorted(COASTS.glob("*.toml"))

#: every key a case may give: what a stranger writes from docs/case-files.md
ALLOWED = {
    "case": {"name", "output"},
    "shorelines": {"path", "bbox"},
    "shoreline_sets": None,  # one set, below
    "domain": {"seed"},
    "open_boundaries": None,  # below
    "mesh_size": {"h_max", "gradations"},
    "bathymetry": {"path"},
}
#: the keys of an open boundary: its name, id and kind, and its line
BOUNDARY = {"name", "id", "kind"}
LINE = {
    "loxodrome": {"start", "bearing", "bearing_west", "end", "end_lat", "end_lon"},
    "great_circle": {"start", "end"},
    "blend": {"first", "second"},
    "polyline": {"points", "path", "layer"},
}
GRADATION = {"lines", "h_min", "d_grade"}


def test_there_are_three_coasts():
    assert [c.stem for c in CASES] == ["oresund", "shetland", "vestfjorden"]


@pytest.mark.parametrize("path", CASES, ids=lambda p: p.stem)
def test_the_case_parses_and_its_data_files_exist(path):
    case = coastmesh.read_case(path)
    assert isinstance(case, coastmesh.CaseConfig)
    assert case.name == path.stem
    for data in (case.shorelines.path, case.bathymetry.path):
        assert Path(data).is_file(), data
        assert Path(data).parent == COASTS
    assert case.shorelines.path.stat().st_size < 400_000
    assert case.bathymetry.path.stat().st_size < 50_000


@pytest.mark.parametrize("path", CASES, ids=lambda p: p.stem)
def test_the_case_gives_the_default_keys_only(path):
    toml = tomllib.loads(path.read_text(encoding="utf-8"))
    assert set(toml) == set(ALLOWED), set(toml) ^ set(ALLOWED)
    for table, keys in ALLOWED.items():
        if keys is not None:
            assert set(toml[table]) <= keys, (table, set(toml[table]) - keys)
    (name, coast), *others = toml["shoreline_sets"].items()
    assert not others and set(coast) == {"id"}
    for boundary in toml["open_boundaries"]:
        extra = set(boundary) - BOUNDARY - LINE[boundary["kind"]]
        assert not extra, (boundary["name"], extra)
    (gradation,) = toml["mesh_size"]["gradations"]
    assert set(gradation) == GRADATION and gradation["lines"] == [name]
