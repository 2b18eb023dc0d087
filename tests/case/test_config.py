"""Case files: every key is checked and every error names the file and the key."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from coastmesh.case import parse_case, read_case
from coastmesh.errors import ConfigError

BASE = """
[case]
name = "t"

[shorelines]
path = "data/coast.gpkg"
min_area = "0.5 km2"

[shoreline_sets.full]
id = 10

[shoreline_sets.coarse]
id = 11
window = 100
modes = 1

[[regions]]
set = "full"
box = [-3.5, 58.5, -3.0, 58.8]

[[open_boundaries]]
name = "north"
id = 2
kind = "loxodrome"
start = [-15.0, 57.0]
bearing_west = 20
end_lat = 70.0

[[open_boundaries]]
name = "blend"
id = 3
kind = "blend"
first = { start = [-15.0, 57.0], bearing = 340, end_lat = 70 }
second = { start = [5.45, 62.0], bearing = 0, end_lat = 70 }

[mesh_size]
h_max = "1.5 deg"

[[mesh_size.gradations]]
lines = ["full", "north"]
h_min = "500 m"
d_hold = "0.05 deg"
d_grade = "1 deg"
"""


def parse(text: str = BASE):
    return parse_case(text, Path("/cases/t.toml"))


def test_a_full_case_parses():
    case = parse()
    assert case.shorelines.path == Path("/cases/data/coast.gpkg")
    assert case.output == Path("/cases/out/t")
    assert case.shorelines.min_area == 5e5
    assert [s.name for s in case.sets] == ["full", "coarse"]
    assert case.background_set.name == "coarse"
    assert case.sets[1].label == "PCA 1 mode / 100 points"
    north = case.boundaries[0]
    assert north.kind == "loxodrome"
    assert north.bearing == 340.0 and north.end_lat == 70.0
    assert case.boundaries[1].second.start == (5.45, 62.0)
    assert case.size.h_max == pytest.approx(1.5 * 111_195.08, rel=1e-6)
    assert case.size.gradations[0].d_hold == pytest.approx(0.05 * 111_195.08, rel=1e-6)
    assert case.outputs.formats == ("msh2",)


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ('name = "t"', 'name = "t"\nnmae = 1', r"unknown key 'case.nmae'"),
        ("modes = 1", "modes = 1\nwindw = 3", r"'shoreline_sets.coarse.windw'"),
        (
            "bearing_west = 20",
            "bearing_west = 20\nbearing = 3",
            r"open_boundaries\[0\]",
        ),
        ('h_min = "500 m"', "h_min = 500", r"gradations\[0\].h_min = 500: give a"),
        ('h_max = "1.5 deg"', 'h_max = "1.5 miles"', r"unknown unit 'miles'"),
        ('min_area = "0.5 km2"', 'min_area = "0.5 km"', r"shorelines.min_area"),
        ("id = 11", "id = 10", r"id 10 of 'coarse' is also the id of 'full'"),
        ('set = "full"', 'set = "ful"', r"regions\[0\].set = 'ful': no such"),
        (
            'lines = ["full", "north"]',
            'lines = ["nrth"]',
            "'nrth' is not a shoreline",
        ),
        ('kind = "blend"', 'kind = "spline"', r"open_boundaries\[1\].kind = 'spline'"),
        ("modes = 1", "modes = 200", r"modes = 200 is more than window = 100"),
        ("end_lat = 70.0\n", "", r"give exactly one of end_lat and end_lon"),
        ("[[regions]]", "[[regions]]\npolygon = [[0, 0], [1, 1]]", "exactly one of"),
        (
            "[mesh_size]",
            "[output]\nformats = ['msh9']\n[mesh_size]",
            r"'msh9': unknown",
        ),
        ('h_min = "500 m"', 'h_min = "2 deg"', r"h_min = .* larger than h_max"),
        (
            "start = [-15.0, 57.0]\nbearing_west",
            "start = [-15.0, 97.0]\nbearing_west",
            "latitude",
        ),
    ],
)
def test_errors_name_the_key(old, new, message):
    text = BASE.replace(old, new, 1)
    assert text != BASE
    with pytest.raises(ConfigError, match=message) as info:
        parse(text)
    assert str(info.value).startswith("/cases/t.toml")


def test_loxodrome_between_two_points():
    text = BASE.replace(
        "bearing_west = 20\nend_lat = 70.0", "end = [-4.0, 48.5]"
    ).replace("start = [-15.0, 57.0]\nend", "start = [-15.0, 57.0]\nend", 1)
    case = parse(text)
    from coastmesh.geometry import Loxodrome

    lox = case.boundaries[0]
    line = Loxodrome(lox.start, lox.bearing, end_lat=lox.end_lat)
    np.testing.assert_allclose(line.end, (-4.0, 48.5), atol=1e-9)
    with pytest.raises(ConfigError, match="either end or bearing"):
        parse(
            BASE.replace(
                "bearing_west = 20\nend_lat = 70.0", "end = [1, 2]\nbearing = 3"
            )
        )


def test_one_background_set():
    text = BASE + '\n[[regions]]\nset = "coarse"\nbox = [0, 0, 1, 1]\n'
    with pytest.raises(ConfigError, match="exactly one shoreline set must have no"):
        parse(text)


def test_missing_tables_and_bad_toml(tmp_path):
    with pytest.raises(ConfigError, match="case: is missing"):
        parse(BASE.replace("[case]", "[cas]"))
    with pytest.raises(ConfigError, match="not valid TOML"):
        parse("[case\n")
    with pytest.raises(ConfigError, match="no such case file"):
        read_case(tmp_path / "nope.toml")


def test_example_cases_parse():
    examples = sorted(Path(__file__).parents[2].glob("examples/*/*.toml"))
    assert examples
    from coastmesh.case import StudyCase

    for path in examples:
        case = read_case(path)
        if isinstance(case, StudyCase):
            assert case.study.path.exists(), path
            continue
        assert (case.shorelines.path or case.shorelines.raster).exists(), path


def test_packaged_demo_case_is_the_example():
    """coastmesh demo runs a copy of examples/orkney: they must not drift apart."""
    from coastmesh.data import path as data_path

    example = read_case(
        Path(__file__).parents[2] / "examples/orkney/pentland_firth.toml"
    )
    packaged = read_case(data_path("pentland_firth.toml"))
    # the installed package and the repository may be different folders: compare
    # the data files by name, everything else exactly
    from dataclasses import replace

    def without_paths(case):
        size = case.size
        bathymetry = replace(size.bathymetry, path=size.bathymetry.path.name)
        return replace(
            case,
            source=None,
            output=None,
            text="",
            shorelines=replace(case.shorelines, path=case.shorelines.path.name),
            size=replace(size, bathymetry=bathymetry),
            bathymetry=replace(case.bathymetry, path=case.bathymetry.path.name),
        )

    assert without_paths(packaged) == without_paths(example)
    assert packaged.bathymetry.window == 8


def test_case_kinds():
    with pytest.raises(ConfigError, match=r"case.kind = 'bogus'"):
        parse(BASE.replace('name = "t"', 'name = "t"\nkind = "bogus"'))
    study = '[case]\nname = "s"\nkind = "shorelines"\n'
    with pytest.raises(ConfigError, match=r"study: is missing"):
        parse(study)


def test_a_depth_sign_for_a_format_without_depth_is_refused():
    text = BASE.replace(
        "[mesh_size]", "[output]\npositive = { msh2 = 'up' }\n[mesh_size]"
    )
    with pytest.raises(ConfigError, match=r"output.positive.msh2: the msh2 format"):
        parse(text)
    ok = BASE.replace(
        "[mesh_size]", "[output]\npositive = { mike = 'down' }\n[mesh_size]"
    )
    assert parse(ok).outputs.positive == {"mike": "down"}
