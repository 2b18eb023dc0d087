"""A CaseConfig built in Python gets the checks and messages of the case-file reader."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from coastmesh.case import (
    BlendBoundary,
    CaseConfig,
    GradationConfig,
    GreatCircleBoundary,
    LoxodromeBoundary,
    LoxodromeConfig,
    PolylineBoundary,
    RegionConfig,
    ShorelinesConfig,
    ShorelineSetConfig,
    SizeConfig,
    dump_case,
    parse_case,
    read_case,
)
from coastmesh.case.boundaries import BOUNDARY_KINDS
from coastmesh.errors import ConfigError

TOML = """
[case]
name = "t"

[shorelines]
path = "/data/coast.gpkg"

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
bearing = 340
end_lat = 70.0

[mesh_size]
h_max = "1 km"

[[mesh_size.gradations]]
lines = ["full", "north"]
h_min = "500 m"
d_grade = "1 km"
"""


def python_case(**changes) -> CaseConfig:
    """The same case as TOML, built in Python."""
    fields = {
        "name": "t",
        "shorelines": ShorelinesConfig("/data/coast.gpkg"),
        "sets": [
            ShorelineSetConfig("full", 10),
            ShorelineSetConfig("coarse", 11, window=100, modes=1),
        ],
        "regions": [RegionConfig("full", box=[-3.5, 58.5, -3.0, 58.8])],
        "boundaries": [
            LoxodromeBoundary(
                "north", 2, start=[-15.0, 57.0], bearing=340, end_lat=70.0
            )
        ],
        "size": SizeConfig(
            h_max="1 km",
            gradations=[GradationConfig(["full", "north"], h_min=500, d_grade="1 km")],
        ),
    }
    return CaseConfig(**(fields | changes))


def test_python_and_toml_give_the_same_case():
    parsed = parse_case(TOML, "/cases/t.toml")
    built = python_case(output=Path("/cases/out/t"))
    assert dataclasses.replace(parsed, source=None, text="") == built
    # converted: units to metres, lists to tuples, strings to paths
    assert built.size.h_max == 1000.0
    assert built.size.gradations[0].lines == ("full", "north")
    assert built.regions[0].box == (-3.5, 58.5, -3.0, 58.8)
    assert built.shorelines.path == Path("/data/coast.gpkg")
    assert python_case().output == Path("out/t")
    assert python_case().label == "CaseConfig"


SIZE = '[mesh_size]\nh_max = "1 km"\n'


@pytest.mark.parametrize(
    ("toml_edit", "python_edit"),
    [
        (
            (SIZE, SIZE + "rate = -1\n"),
            lambda c: {"size": dataclasses.replace(c.size, rate=-1)},
        ),
        (
            ('h_max = "1 km"', 'h_max = "-2 km"'),
            lambda c: {"size": dataclasses.replace(c.size, h_max=-2000.0)},
        ),
        (
            ("modes = 1", "modes = 200"),
            lambda c: {"sets": [c.sets[0], dataclasses.replace(c.sets[1], modes=200)]},
        ),
        (
            ("id = 2", "id = 0"),
            lambda c: {
                "boundaries": [dataclasses.replace(c.boundaries[0], physical_id=0)]
            },
        ),
        (
            ("id = 11", "id = 10"),
            lambda c: {
                "sets": [c.sets[0], dataclasses.replace(c.sets[1], physical_id=10)]
            },
        ),
        (
            ('set = "full"', 'set = "ful"'),
            lambda c: {"regions": [dataclasses.replace(c.regions[0], set="ful")]},
        ),
        (
            ("bearing = 340", "bearing = 340\nend_lon = 3"),
            lambda c: {"boundaries": [dataclasses.replace(c.boundaries[0], end_lon=3)]},
        ),
        (
            ('lines = ["full", "north"]', 'lines = ["nrth"]'),
            lambda c: {
                "size": dataclasses.replace(
                    c.size,
                    gradations=[
                        dataclasses.replace(c.size.gradations[0], lines=["nrth"])
                    ],
                )
            },
        ),
        (
            ('h_min = "500 m"', 'h_min = "2 km"'),
            lambda c: {
                "size": dataclasses.replace(
                    c.size,
                    gradations=[
                        dataclasses.replace(c.size.gradations[0], h_min=2000.0)
                    ],
                )
            },
        ),
        (
            ("[mesh_size]", "[cleanup]\nmin_angle = 70\n[mesh_size]"),
            lambda c: {"cleanup": dataclasses.replace(c.cleanup, min_angle=70)},
        ),
        (
            ("[mesh_size]", "[output]\nformats = ['msh9']\n[mesh_size]"),
            lambda c: {"outputs": dataclasses.replace(c.outputs, formats=["msh9"])},
        ),
        (
            ("[mesh_size]", "[mesh]\nalgorithm = 'bogus'\n[mesh_size]"),
            lambda c: {"mesh": dataclasses.replace(c.mesh, algorithm="bogus")},
        ),
        (
            ("[mesh_size]", "[domain]\nseed = [1]\n[mesh_size]"),
            lambda c: {"domain": dataclasses.replace(c.domain, seed=[1])},
        ),
    ],
)
def test_a_bad_value_gets_the_same_message(toml_edit, python_edit):
    old, new = toml_edit
    assert old in TOML
    with pytest.raises(ConfigError) as from_file:
        parse_case(TOML.replace(old, new, 1), "/cases/t.toml")
    case = python_case()
    with pytest.raises(ConfigError) as from_python:
        CaseConfig(
            **{f.name: getattr(case, f.name) for f in dataclasses.fields(case)}
            | python_edit(case)
        )
    expected = str(from_file.value).replace("/cases/t.toml", "CaseConfig", 1)
    assert str(from_python.value) == expected
    assert str(from_python.value).startswith("CaseConfig: ")


def test_replace_checks_again():
    case = python_case()
    with pytest.raises(ConfigError, match=r"^CaseConfig: mesh_size.h_max = -1 m"):
        dataclasses.replace(case, size=SizeConfig(h_max=-1))
    with pytest.raises(
        ConfigError, match=r"shorelines = 'coast\.gpkg': expected a ShorelinesConfig"
    ):
        dataclasses.replace(case, shorelines="coast.gpkg")
    with pytest.raises(ConfigError, match=r"shoreline_sets = 'full': expected a list"):
        dataclasses.replace(case, sets="full")
    with pytest.raises(TypeError, match="shorelines"):
        CaseConfig(name="x", sets=[], size=SizeConfig(1000.0))  # no shorelines


def test_each_kind_of_boundary_is_a_class_with_its_keys():
    lox = LoxodromeConfig((-15.0, 57.0), 340, end_lat=70.0)
    kinds = {
        "loxodrome": LoxodromeBoundary(
            "north", 2, start=(-15.0, 57.0), bearing=340, end_lat=70.0
        ),
        "blend": BlendBoundary("north", 2, first=lox, second=lox),
        "great_circle": GreatCircleBoundary("north", 2, start=(0, 50), end=(1, 51)),
        "polyline": PolylineBoundary("north", 2, points=[(0, 50), (1, 51)]),
    }
    for kind, boundary in kinds.items():
        assert python_case(boundaries=[boundary]).boundaries[0].kind == kind
        assert BOUNDARY_KINDS[kind] is type(boundary)
    with pytest.raises(ConfigError, match=r"open_boundaries\[0\].points: give exactly"):
        python_case(boundaries=[PolylineBoundary("north", 2)])
    with pytest.raises(
        ConfigError, match=r"open_boundaries\[0\].second = 'x': expected a Loxo"
    ):
        python_case(boundaries=[BlendBoundary("north", 2, first=lox, second="x")])
    with pytest.raises(TypeError, match="second"):
        BlendBoundary("north", 2, first=lox)
    with pytest.raises(ConfigError, match=r"open_boundaries\[0\] = .*BoundaryConf"):
        python_case(boundaries=[lox])


def test_loxodrome_between_two_points():
    lox = LoxodromeConfig.between((-3.0, 58.0), (-4.0, 48.5))
    boundary = LoxodromeBoundary(
        "north", 2, start=lox.start, bearing=lox.bearing, end_lat=lox.end_lat
    )
    case = python_case(boundaries=[boundary])
    assert case.boundaries[0].bearing == pytest.approx(lox.bearing % 360)


@pytest.mark.parametrize(
    "path", sorted(Path(__file__).parents[2].glob("examples/*/*.toml")), ids=str
)
def test_dump_reads_back_equal(path, tmp_path):
    case = read_case(path)
    if not isinstance(case, CaseConfig):
        pytest.skip("a study case")
    again = parse_case(dump_case(case), tmp_path / "case.toml")
    assert dataclasses.replace(again, source=None, text="") == dataclasses.replace(
        case, source=None, text=""
    )


lengths = st.floats(1.0, 1e6, allow_nan=False, allow_infinity=False)


@settings(max_examples=60, deadline=None)
@given(
    h_max=lengths,
    fractions=st.lists(st.floats(0.01, 1.0), min_size=0, max_size=3),
    window=st.integers(2, 500),
    modes=st.integers(1, 500),
    rate=st.none() | st.floats(0.01, 10.0),
    box=st.tuples(st.floats(-180, 0), st.floats(-80, 0), st.floats(0.1, 180)),
    spacing=st.none() | lengths,
)
def test_dump_then_parse_is_the_identity(
    h_max, fractions, window, modes, rate, box, spacing
):
    modes = min(modes, window)
    case = python_case(
        output=Path("/cases/out/t"),
        sets=[
            ShorelineSetConfig("full", 10),
            ShorelineSetConfig("coarse", 11, window=window, modes=modes),
        ],
        regions=[RegionConfig("full", box=(box[0], box[1], box[2], box[2] / 2))],
        boundaries=[
            GreatCircleBoundary(
                "north", 2, start=(-3.0, 58.0), end=(-2, 59), spacing=spacing
            )
        ],
        size=SizeConfig(
            h_max=h_max,
            rate=rate,
            gradations=[
                GradationConfig(["full"], h_min=f * h_max, d_grade=h_max / f)
                for f in fractions
            ],
        ),
    )
    assert (
        dataclasses.replace(
            parse_case(dump_case(case), "/x/c.toml"), source=None, text=""
        )
        == case
    )
