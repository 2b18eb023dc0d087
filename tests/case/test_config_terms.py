"""``[mesh_size.channels]``, ``[mesh_size.courant]``, ``rate``, ``[cleanup] time_step``:
defaults, errors, round trip."""

from __future__ import annotations

import dataclasses

import pytest

from coastmesh.case import (
    BathymetryConfig,
    ChannelConfig,
    CourantConfig,
    NodeDepthConfig,
    dump_case,
    parse_case,
)
from coastmesh.case.config import TERMS, SizeConfig, term_key, terms_of
from coastmesh.case.terms import Courant
from coastmesh.errors import ConfigError
from coastmesh.sizing import DEFAULT_RATE

BASE = """
[case]
name = "t"

[shorelines]
path = "/data/coast.gpkg"

[shoreline_sets.full]
id = 10

[domain]
seed = [0.5, 0.5]

[mesh_size]
h_max = "1 km"
"""

DEPTH = """
[bathymetry]
path = "/data/depth.tif"
"""


def parsed(extra: str):
    return parse_case(BASE + extra, "/cases/t.toml")


def test_channels_are_on_by_default_with_three_elements_across():
    case = parsed("")
    assert case.size.channels == ChannelConfig(True, 3.0, "close")
    # the Courant term is on, with the time step worked out (dt = "auto")
    assert case.size.courant == CourantConfig(None, 0.5, None, 1.0, True)
    assert parsed('[mesh_size.courant]\ndt = "auto"').size.courant == (
        case.size.courant
    )


def test_auto_dt_needs_courant_max_alone_and_is_off_without_a_depth():
    with pytest.raises(ConfigError, match='dt = "auto" takes the time step'):
        parsed("[mesh_size.courant]\ncourant_min = 0.4\n" + DEPTH)
    # no bathymetry: a given dt is an error, the default is quietly off
    with pytest.raises(ConfigError, match="the Courant term needs the depth"):
        parsed('[mesh_size.courant]\ndt = "30 s"\n')
    assert parsed("").bathymetry is None


def test_channel_and_courant_tables_parse_with_units():
    case = parsed(
        '[mesh_size.channels]\nelements_across = 4\nnarrow = "close"\n'
        '[mesh_size.courant]\ndt = "30 s"\ncourant_min = 0.4\ncourant_max = 2\n'
        'velocity = "2 kn"\n' + DEPTH
    )
    assert case.size.channels == ChannelConfig(True, 4.0, "close")
    # a regional case switches the term on (unset, it is off in a global case)
    assert case.size.courant == CourantConfig(
        30.0, 2.0, 0.4, 2 * 1852 / 3600, enabled=True
    )


def test_dt_alone_gets_the_explicit_model_default():
    case = parsed('[mesh_size.courant]\ndt = "1 min"\n' + DEPTH)
    assert case.size.courant == CourantConfig(60.0, 0.5, None, 1.0, enabled=True)
    only_min = parsed('[mesh_size.courant]\ndt = "60 s"\ncourant_min = 0.9\n' + DEPTH)
    assert only_min.size.courant.courant_max is None


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (
            "[mesh_size.channels]\nelements_across = 0.5\n",
            r"/cases/t.toml: mesh_size.channels.elements_across = 0.5: must be at "
            r"least 1",
        ),
        (
            '[mesh_size.channels]\nnarrow = "fill"\n',
            r"mesh_size.channels.narrow = 'fill'",
        ),
        (
            '[mesh_size.courant]\ndt = "10 s"\n',
            r"/cases/t.toml: mesh_size.courant.dt = 10 s: the Courant term needs the "
            r"depth; add \[mesh_size.bathymetry\] or \[bathymetry\]",
        ),
        (
            '[mesh_size.courant]\ndt = "10 s"\ncourant_min = 0.5\ncourant_max = 0.5\n'
            + DEPTH,
            r"mesh_size.courant.courant_min = 0.5 is not below courant_max = 0.5",
        ),
        (
            '[mesh_size.courant]\ndt = "10 s"\ncourant_min = 0.8\ncourant_max = 0.2\n'
            + DEPTH,
            r"mesh_size.courant.courant_min = 0.8 is not below courant_max = 0.2",
        ),
        (
            "[mesh_size.courant]\ndt = 10\n" + DEPTH,
            r"mesh_size.courant.dt = 10: write a number and a unit",
        ),
        (
            '[mesh_size.courant]\ndt = "10 s"\nvelocity = "1 mph"\n' + DEPTH,
            r"mesh_size.courant.velocity = '1 mph'",
        ),
        (
            '[mesh_size.courant]\ndt = "-5 s"\n' + DEPTH,
            r"mesh_size.courant.dt = -5 s: must be > 0",
        ),
        (
            '[mesh_size.courant]\ndt = "5 s"\ncourant = 1\n' + DEPTH,
            r"mesh_size.courant.courant",
        ),
    ],
)
def test_bad_terms_name_the_key(extra, message):
    with pytest.raises(ConfigError, match=message):
        parsed(extra)


def test_python_configs_get_the_same_messages():
    case = parsed(DEPTH)
    with pytest.raises(
        ConfigError,
        match=r"CaseConfig: mesh_size.channels.elements_across = 0: must be at least 1",
    ):
        dataclasses.replace(
            case,
            source=None,
            size=dataclasses.replace(case.size, channels=ChannelConfig(True, 0)),
        )
    with pytest.raises(ConfigError, match=r"courant_min = 1 is not below"):
        dataclasses.replace(
            case,
            source=None,
            size=dataclasses.replace(
                case.size, courant=CourantConfig("10 s", courant_max=1, courant_min=1)
            ),
        )
    # a number is seconds / m/s in Python
    ok = dataclasses.replace(
        case,
        source=None,
        size=dataclasses.replace(case.size, courant=CourantConfig(12, velocity=0)),
    )
    assert ok.size.courant == CourantConfig(12.0, 0.5, None, 0.0, enabled=True)


@pytest.mark.parametrize(
    "size_change",
    [
        {"channels": ChannelConfig(False)},
        {"channels": ChannelConfig(True, 2.5, "close")},
        {"rate": None},
        {"rate": 0.2},
        {"courant": CourantConfig(7.5, 0.9, 0.1, 0.25)},
        {
            "courant": CourantConfig(20.0, None, 0.4, 1.0),
            "bathymetry": BathymetryConfig("/data/d.tif", per_wavelength=50),
        },
    ],
)
def test_terms_round_trip_through_the_case_file(size_change):
    case = dataclasses.replace(
        parsed(DEPTH), source=None, text="", bathymetry=NodeDepthConfig("/d.tif")
    )
    case = dataclasses.replace(case, size=dataclasses.replace(case.size, **size_change))
    again = dataclasses.replace(
        parse_case(dump_case(case), "/x/t.toml"), source=None, text=""
    )
    assert again == case


def test_the_gradation_limit_is_on_by_default_and_false_turns_it_off():
    assert parsed("").size.rate == DEFAULT_RATE == 0.7
    assert parsed("rate = 0.3\n").size.rate == 0.3
    assert parsed("rate = false\n").size.rate is None
    with pytest.raises(ConfigError, match=r"mesh_size.rate = true: give the limit"):
        parsed("rate = true\n")
    with pytest.raises(ConfigError, match=r"mesh_size.rate = -1: must be > 0"):
        parsed("rate = -1\n")
    # no limit is written as false: an absent key would mean the default
    case = dataclasses.replace(
        parsed(""),
        source=None,
        text="",
        size=dataclasses.replace(parsed("").size, rate=None),
    )
    assert "rate = false" in dump_case(case)


def test_time_step_relief_is_on_by_default_and_can_be_turned_off():
    assert parsed("").cleanup.time_step is True
    assert parsed("[cleanup]\ntime_step = false\n").cleanup.time_step is False
    with pytest.raises(ConfigError, match=r"cleanup.time_step = 'yes'"):
        parsed('[cleanup]\ntime_step = "yes"\n')


def test_mesh_parts_are_auto_by_default_or_a_count():
    assert parsed("").mesh.parts == "auto"
    assert parsed("[mesh]\nparts = 1\n").mesh.parts == 1
    assert parsed('[mesh]\nparts = "auto"\n').mesh.parts == "auto"
    assert parsed("[mesh]\nparts = 4\n").mesh.parts == 4
    for bad in ("0", "2.5", '"many"', "true"):
        with pytest.raises(ConfigError, match=r"mesh.parts = .*expected \"auto\""):
            parsed(f"[mesh]\nparts = {bad}\n")
    case = dataclasses.replace(parsed(""), source=None, text="")
    case = dataclasses.replace(case, mesh=dataclasses.replace(case.mesh, parts=3))
    again = dataclasses.replace(
        parse_case(dump_case(case), "/x/t.toml"), source=None, text=""
    )
    assert again.mesh.parts == 3


def test_sites_parse_and_become_one_area_in_the_mesh_crs():
    from pyproj import CRS

    from coastmesh.case.pipeline.domain import site_area

    case = parsed(
        '[[sites]]\nname = "a"\nbox = [-3.2, 58.6, -3.0, 58.7]\n'
        '[[sites]]\nname = "b"\npolygon = [[-2.9, 58.6], [-2.8, 58.6], [-2.8, 58.7]]\n'
    )
    assert [s.name for s in case.sites] == ["a", "b"]
    area = site_area(case, CRS.from_epsg(32630))
    # the box: 0.2 deg x 0.1 deg at 58.65 N, about 11.6 km x 11.1 km
    assert 120e6 < area.area < 140e6 + 70e6
    assert site_area(parsed(""), CRS.from_epsg(32630)) is None
    with pytest.raises(ConfigError, match=r"sites\[0\].box: give exactly one of"):
        parsed(
            '[[sites]]\nname = "a"\nbox = [0, 0, 1, 1]\n'
            "polygon = [[0, 0], [1, 0], [1, 1]]\n"
        )
    with pytest.raises(ConfigError, match=r"sites\[0\].polygon: needs at least"):
        parsed('[[sites]]\nname = "a"\npolygon = [[0, 0], [1, 0]]\n')


def test_keep_and_min_depth_together_are_refused():
    with pytest.raises(ConfigError, match=r"bathymetry\.min_depth: would raise"):
        parsed(
            '[bathymetry]\npath = "/data/depth.tif"\nland = "keep"\nmin_depth = "5 m"\n'
        )


def test_size_config_is_the_registry_of_the_terms():
    """SizeConfig's fields: the field's keys, then one term_key line per term.

    TERMS is read from them, in order; the defaults are the terms' own.
    """
    made = dataclasses.fields(SizeConfig)
    keys = ["gradations", "bathymetry", "channels", "courant", "fields"]
    assert [f.name for f in made] == ["h_max", "h_min", "cell", "rate", *keys]
    assert [t.key for t in TERMS] == keys
    assert [f.metadata["term"] for f in made[4:]] == list(TERMS)
    defaults = {f.name: f.default for f in made if f.default is not dataclasses.MISSING}
    assert defaults == {
        "h_min": None,
        "cell": None,
        "rate": DEFAULT_RATE,
        "gradations": (),
        "bathymetry": None,
        "fields": (),
    }
    made_anew = {
        f.name: f.default_factory()
        for f in made
        if f.default_factory is not dataclasses.MISSING
    }
    assert made_anew == {"channels": ChannelConfig(), "courant": CourantConfig()}


def test_a_term_under_another_name_or_reading_a_later_term_is_refused():
    @dataclasses.dataclass(frozen=True)
    class Misnamed(SizeConfig):
        other: CourantConfig | None = term_key(Courant())

    with pytest.raises(TypeError, match=r"Misnamed.other registers Courant, whose"):
        terms_of(Misnamed)

    class Early(Courant):
        key = "early"
        reads = ("courant", "later")

    @dataclasses.dataclass(frozen=True)
    class Reads(SizeConfig):
        early: CourantConfig | None = term_key(Early())

    with pytest.raises(TypeError, match=r"'early' reads \['later'\]: a term reads"):
        terms_of(Reads)


def test_what_is_on_by_default_and_the_cross_checks_are_the_terms_own(monkeypatch):
    """The reader asks each term of TERMS: no term named in the case reader."""
    by_key = {term.key: term for term in TERMS}
    assert {t.key for t in TERMS if t.on_by_default} == {"channels", "courant"}
    # a term not on by default keeps enabled unset
    monkeypatch.setattr(type(by_key["channels"]), "on_by_default", False)
    assert parsed("").size.channels.enabled is None
    monkeypatch.undo()
    # a term's check sees its table, the case's tables and the line names
    seen = {}

    def check(self, settings, case, *, label, lines):
        seen.update(settings=settings, bathymetry=case.bathymetry, lines=lines)
        raise ConfigError(f"{label}: refused by the term")

    monkeypatch.setattr(type(by_key["fields"]), "check", check)
    with pytest.raises(ConfigError, match=r"t\.toml: refused by the term"):
        parsed(DEPTH)
    assert seen["settings"] == () and seen["bathymetry"] is not None
    assert "full" in seen["lines"]
