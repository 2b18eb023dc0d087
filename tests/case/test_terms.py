"""The size terms in the whole size field: order, reports, warnings.

Through :func:`coastmesh.case.domain_size_field`, the size stage of a case on a
domain built in Python, with the depth in memory.
"""

from __future__ import annotations

import math
import warnings
from typing import ClassVar

import numpy as np
import pytest
import shapely
import xarray as xr
from conftest import bay_with_inlet
from hypothesis import given, settings
from hypothesis import strategies as st
from pyproj import Transformer

from coastmesh.case import (
    ChannelConfig,
    CourantConfig,
    GradationConfig,
    NodeDepthConfig,
    SizeConfig,
    domain_size_field,
)
from coastmesh.case.terms import SizeTerm
from coastmesh.case.terms.courant import AUTO_PERCENTILE, AUTO_SHARE, auto_time_step
from coastmesh.errors import CoastmeshWarning, ConfigError
from coastmesh.geometry.earth import GRAVITY
from coastmesh.sizing import courant_bounds, domain_slots
from coastmesh.sizing.combine import TermSizes
from coastmesh.sizing.courant import round_step
from coastmesh.types import BoundarySegment, Domain


def _flat_raster(depth: float, crs: str = "EPSG:32631") -> xr.DataArray:
    """A raster of constant elevation ``-depth`` covering the test domains."""
    x = np.arange(-5_000.0, 40_001.0, 1000.0)
    y = np.arange(-5_000.0, 40_001.0, 1000.0)
    return xr.DataArray(
        np.full((len(y), len(x)), -depth),
        dims=("y", "x"),
        coords={"y": y, "x": x},
        attrs={"crs": crs},
    )


_bay = bay_with_inlet


GRADE = [GradationConfig(("coast",), h_min=400.0, d_grade=5000.0)]
#: the Courant term's depth: a case's [bathymetry] (read from ``depth`` here)
DEPTH = NodeDepthConfig(path="in_memory.tif")
OFF = ChannelConfig(enabled=False)
#: channels narrower than 2 h_min kept (a case closes them before the size field)
KEEP = ChannelConfig(narrow="keep")


def _sized(domain, depth=None, **size):
    """The size stage on ``domain`` in UTM 31N, with [mesh_size] ``size``.

    The Courant term (on by default, dt = "auto") only where a test gives it.
    """
    size.setdefault("courant", CourantConfig(enabled=False))
    size = SizeConfig(h_max=3000.0, gradations=GRADE, **size)
    return domain_size_field(
        domain, size, mesh_crs="EPSG:32631", bathymetry=DEPTH, depth=depth
    )


def _at(field: xr.DataArray, x: float, y: float) -> float:
    return float(field.sel(x=x, y=y, method="nearest"))


def test_the_channel_term_is_on_by_default_and_puts_elements_across():
    off = _sized(_bay(), channels=OFF, h_min=100.0, cell=50.0).field
    with pytest.warns(CoastmeshWarning, match="narrower than 2 elements") as caught:
        on = _sized(_bay(150.0), h_min=100.0, cell=50.0, channels=KEEP).field
    assert "kept" in str(caught[0].message)
    default = _sized(_bay(), h_min=100.0, cell=50.0).field
    # a 600 m inlet: 556 m from the gradation alone (300 m from the shore), at
    # most 200 m (3 across) with the term
    assert _at(off, 10_000, 23_000) == pytest.approx(400 + 300 * 2600 / 5000, rel=0.01)
    assert 550 / 1.15 / 3 <= _at(default, 10_000, 23_000) <= 200.0
    # a 150 m inlet cannot take 3 elements of 100 m: it takes the floor
    assert _at(on, 10_000, 23_000) == 100.0
    # in the open bay the term changes nothing
    assert _at(default, 10_000, 8_000) == _at(off, 10_000, 8_000)
    # land takes the term of the nearest water: beside the bay (3 km from its
    # shore, 4.7 km from the inlet) the bay's, graded from the inlet, beside the
    # inlet the inlet's size (land once took h_min = 100 m everywhere, and Gmsh
    # meshed every coast near h_min)
    assert _at(default, 5_000, 23_000) > 900.0
    assert _at(default, 9_500, 23_000) <= 200.0 < _at(off, 9_500, 23_000)


def test_the_channel_report_counts_narrow_channels_and_gives_their_place():
    with pytest.warns(CoastmeshWarning):
        sized = _sized(_bay(150.0), h_min=100.0, cell=25.0, channels=KEEP)
    ch = sized.report.channels
    assert ch.narrow_channels == 1 and ch.narrow == "keep"
    assert 9_000 < ch.worst[0].y < 26_000 and ch.worst[0].width_m < 200.0
    assert 0.5 < ch.narrow_km2 < 1.2  # the inlet: 150 m x 6 km
    lon, lat = Transformer.from_crs(32631, 4326, always_xy=True).transform(
        ch.worst[0].x, ch.worst[0].y
    )
    assert (ch.worst[0].lon, ch.worst[0].lat) == (round(lon, 6), round(lat, 6))
    assert 140.0 / 1.15 < ch.worst[0].width_m < 200.0
    assert sized.report.to_dict()["channels"]["narrow_channels"] == 1
    width = sized.layers["width"]
    assert np.isnan(width.sel(x=25_000, y=5_000, method="nearest"))  # off the sea
    assert "1 narrower than 2 x 100 m" in sized.report.summary()


def test_h_min_defaults_to_the_smallest_gradation_when_channels_are_on():
    sized = _sized(_bay(), cell=50.0)
    assert sized.report.h_min_m == 400.0
    # the default gradation limit adds rounding (1e-11 m) to sizes it leaves
    assert float(sized.field.min()) == pytest.approx(400.0, abs=1e-6)


def test_a_term_taken_away_by_the_default_floor_is_named():
    """No h_min, no gradations: the floor is h_max, so finer sizes are lost."""
    size = {"h_max": 3000.0, "channels": OFF, "cell": 500.0}
    courant = CourantConfig(dt=10.0, courant_min=0.5)  # a cap of about 650 m
    depth = _flat_raster(100.0)
    with pytest.warns(CoastmeshWarning, match=r"the courant term\(s\) cannot make"):
        floored = domain_size_field(
            _bay(),
            SizeConfig(**size, courant=courant),
            mesh_crs="EPSG:32631",
            bathymetry=DEPTH,
            depth=depth,
        )
    assert float(floored.field.min()) == pytest.approx(3000.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error", CoastmeshWarning)
        given_floor = domain_size_field(
            _bay(),
            SizeConfig(**size, h_min=100.0, courant=courant),
            mesh_crs="EPSG:32631",
            bathymetry=DEPTH,
            depth=depth,
        )
    cap = 10.0 * (np.sqrt(GRAVITY * 100.0) + 1.0) / 0.5
    assert float(given_floor.field.max()) == pytest.approx(cap, rel=1e-6)


@settings(max_examples=40, deadline=None)
@given(
    st.floats(0.0, 5000.0),
    st.floats(1.0, 120.0),
    st.floats(0.0, 3.0),
    st.floats(0.05, 0.9),
    st.one_of(st.none(), st.floats(0.01, 0.04)),
)
def test_courant_bounds_match_the_formula(depth, dt, u, cmax, cmin):
    floor, cap = courant_bounds(
        np.array([depth]), dt=dt, courant_max=cmax, courant_min=cmin, velocity=u
    )
    speed = math.sqrt(GRAVITY * max(depth, 1.0)) + u
    assert floor[0] == pytest.approx(dt * speed / cmax, rel=1e-12)
    if cmin is None:
        assert cap[0] == math.inf
    else:
        assert cap[0] == pytest.approx(dt * speed / cmin, rel=1e-12)
        # the Courant number at either bound is the bound
        assert dt * speed / floor[0] == pytest.approx(cmax)


def test_the_courant_floor_beats_h_min_and_the_channel_term_and_h_max_beats_it():
    # 100 m deep: c = 31.3 m/s + 1; dt 10 s, courant_max 1: floor 323 m
    c = CourantConfig(dt=10.0, courant_max=1.0, velocity=1.0)
    floor = 10.0 * (math.sqrt(GRAVITY * 100.0) + 1.0)
    sized = _sized(_bay(600.0), _flat_raster(100.0), h_min=100.0, cell=50.0, courant=c)
    # in the inlet the channel term asks for ~180 m; the Courant floor wins
    assert _at(sized.field, 10_000, 23_000) == pytest.approx(floor)
    assert sized.report.courant.raised_km2 > 3.0
    assert sized.report.courant.unmet_km2 == 0.0
    # a floor above h_max: h_max wins, with a warning giving the area
    # a floor above h_max on part of the sea (a deep half): h_max wins there,
    # with a warning giving the area; on all of it, an error (below)
    deep = CourantConfig(dt=60.0, courant_max=0.5)
    half = _flat_raster(10.0)
    half.values[:, half.x.values > 10_000] = -4000.0
    with pytest.warns(CoastmeshWarning, match=r"on \d+\.\d km2 of the domain"):
        capped = _sized(_bay(), half, cell=100.0, courant=deep)
    assert float(capped.field.max()) == 3000.0


def test_the_courant_cap_lowers_sizes_but_not_below_h_min():
    # shallow: 4 m, u = 0: c = 6.26 m/s; dt 30 s, courant_min 0.5: cap 376 m
    c = CourantConfig(dt=30.0, courant_min=0.5, velocity=0.0)
    cap = 30.0 * math.sqrt(GRAVITY * 4.0) / 0.5
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CoastmeshWarning)
        sized = _sized(_bay(), _flat_raster(4.0), h_min=100.0, cell=100.0, courant=c)
    assert float(sized.field.max()) == pytest.approx(cap)
    assert sized.report.courant.lowered_km2 > 300


@pytest.mark.parametrize(
    ("courant", "message"),
    [
        (CourantConfig(dt=0.0), r"mesh_size.courant.dt = 0 s: must be > 0"),
        (
            CourantConfig(dt=10.0, courant_max=0.3, courant_min=0.3),
            "courant.courant_min = 0.3 is not below",
        ),
        (CourantConfig(dt=10.0, velocity=-1.0), "courant.velocity = -1.0: must be"),
        (ChannelConfig(elements_across=0.5), "elements_across = 0.5: must be at"),
        (ChannelConfig(narrow="fill"), "channels.narrow = 'fill'"),
    ],
)
def test_bad_terms_name_the_key(courant, message):
    key = "courant" if isinstance(courant, CourantConfig) else "channels"
    with pytest.raises(ConfigError, match=message):
        _sized(_bay(), _flat_raster(10.0), cell=200.0, **{key: courant})


def test_domain_slots_are_closed_but_never_at_an_open_boundary():
    # a 20 km bay open to the south, with a 20 m slot in its north shore and
    # another reaching the open boundary
    ring = [
        (0, 0), (9_990, 0), (9_990, -3_000), (10_010, -3_000), (10_010, 0),
        (20_000, 0), (20_000, 20_000), (5_010, 20_000), (5_010, 22_000),
        (4_990, 22_000), (4_990, 20_000), (0, 20_000), (0, 0),
    ]  # fmt: skip
    domain = Domain(
        shapely.Polygon(ring),
        (
            BoundarySegment(ring[:2], "open", "south_a", 2),
            BoundarySegment(ring[1:5], "shoreline", "inlet", 1),
            BoundarySegment(ring[4:6], "open", "south_b", 3),
            BoundarySegment(ring[5:], "shoreline", "coast", 4),
        ),
        crs="EPSG:32631",
    )
    found = domain_slots(domain, "EPSG:32631", 50.0)
    assert len(found) == 1
    minx, _, maxx, maxy = found[0].bounds
    assert 4_980 < minx < 4_990 and 5_010 < maxx < 5_020 and maxy > 22_000
    assert len(domain_slots(domain, "EPSG:32631", 10.0)) == 0


def _auto_dt_loop(h, speed, courant_max):
    """dt = "auto", literally: sort the steps, walk the elements to the 1 %."""
    steps = sorted(
        (courant_max * hk / ck, 1.0 / hk**2) for hk, ck in zip(h, speed, strict=True)
    )
    total = sum(w for _, w in steps)
    seen = 0.0
    for step, w in steps:
        seen += w
        if seen >= AUTO_PERCENTILE / 100 * total:
            return round_step(AUTO_SHARE * step)
    return round_step(AUTO_SHARE * steps[-1][0])


@settings(max_examples=50, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 400))
def test_auto_time_step_is_the_element_weighted_first_percentile(seed, n):
    rng = np.random.default_rng(seed)
    h = rng.uniform(50.0, 5000.0, n)
    speed = rng.uniform(2.0, 200.0, n)
    sea = rng.random(n) < 0.9
    got = auto_time_step(h, speed, sea, 0.5)
    if not sea.any():
        assert got == math.inf
        return
    assert got == _auto_dt_loop(h[sea], speed[sea], 0.5)


def test_auto_dt_floors_the_slowest_percent_and_sites_keep_theirs():
    # a bay 10 m deep with a 1000 m hole (0.5 km2, a few of its ~1,000 elements)
    # by the north shore: there the waves are fast and the 400 m elements would
    # set the time step; dt = "auto" makes them larger
    hole = (slice(23, 25), slice(7, 9))  # rows y 18 to 19 km, cols x 2 to 3 km
    raster = _flat_raster(10.0)
    raster.values[hole] = -1000.0
    auto = CourantConfig()
    sized = _sized(_bay(600.0), raster, cell=100.0, courant=auto)
    report = sized.report.courant
    assert report.auto and report.raised_km2 > 0.2
    fast = math.sqrt(GRAVITY * 1000.0) + 1.0
    floor = report.dt * fast / (0.5 * AUTO_SHARE)
    # the step is the one worked out from the field without the floor
    off = _sized(_bay(600.0), raster, cell=100.0)
    # over the hole the floor (eased by the gradation limit next to the shore)
    assert _at(sized.field, 2_500, 19_000) > _at(off.field, 2_500, 19_000)
    assert _at(sized.field, 2_500, 19_000) == pytest.approx(floor, rel=0.02)
    assert _at(sized.field, 15_000, 19_900) == _at(off.field, 15_000, 19_900)
    speed = sized.grid.depth(raster)
    speed = np.sqrt(GRAVITY * np.maximum(speed, 1.0)) + 1.0
    assert report.dt == auto_time_step(off.field.values, speed, sized.grid.sea, 0.5)
    # the hole marked as a site keeps the gradation's 400 m
    sited = domain_size_field(
        _bay(600.0),
        SizeConfig(h_max=3000.0, gradations=GRADE, cell=100.0, courant=auto),
        mesh_crs="EPSG:32631",
        bathymetry=DEPTH,
        depth=raster,
        sites=shapely.box(1_500, 17_500, 3_500, 20_000),
    )
    assert _at(sited.field, 2_500, 19_000) == _at(off.field, 2_500, 19_000) < floor


def test_a_narrow_channel_in_a_site_gets_two_elements_across_below_the_floor():
    inlet = shapely.box(9_000, 19_000, 11_000, 26_500)  # the inlet and its mouth
    size = SizeConfig(
        h_max=3000.0,
        gradations=GRADE,
        h_min=100.0,
        cell=25.0,
        courant=CourantConfig(enabled=False),
    )
    with warnings.catch_warnings():
        warnings.simplefilter("error", CoastmeshWarning)  # nothing narrow is left
        sized = domain_size_field(
            _bay(150.0), size, mesh_crs="EPSG:32631", bathymetry=DEPTH, sites=inlet
        )
    # a 150 m inlet: 3 elements of 50 m across (widths err narrow by up to a
    # cell and 15 %), below h_min = 100 m
    assert 150.0 / 1.15 / 3 - 25.0 <= _at(sized.field, 10_000, 23_000) <= 50.0
    assert sized.report.channels.narrow_channels == 0
    # outside the site the floor holds
    assert float(sized.field.values[:, :100].min()) >= 100.0 - 1e-9


def test_a_dt_no_element_can_meet_names_the_depth_and_the_size():
    # 100 m deep: c = 32.3 m/s; dt 600 s at courant_max 0.5 needs 38.8 km
    c = CourantConfig(dt=600.0)
    speed = math.sqrt(GRAVITY * 100.0) + 1.0
    with pytest.raises(ConfigError, match="no element of the sea can meet it") as e:
        _sized(_bay(), _flat_raster(100.0), cell=500.0, courant=c)
    assert "(100.0 m deep)" in str(e.value)
    assert f"at least {600.0 * speed / 0.5:,.0f} m, above h_max = 3000 m" in str(
        e.value
    )


def test_closing_every_channel_is_refused_with_a_clear_message():
    from types import SimpleNamespace

    from coastmesh.case.pipeline.closing import _refuse_closing_all

    inlet = _bay(100.0)
    state = SimpleNamespace(domain=inlet, mesh_crs=inlet.crs)
    config = SimpleNamespace(label="t.toml")
    sea = inlet.polygon.area / 1e6
    few = SimpleNamespace(narrow_km2=0.5 * sea, h_min=300.0)
    _refuse_closing_all(state, config, few)  # some channels: fine
    every = SimpleNamespace(narrow_km2=0.95 * sea, h_min=300.0)
    with pytest.raises(ConfigError, match=r"would leave no sea.*\[\[sites\]\]"):
        _refuse_closing_all(state, config, every)


class _HalfConfig:
    """The table of a term kept outside the package (a test's plug-in)."""


class _Half(SizeTerm[object]):
    """Half the gradations' sizes: a term that reads another term's field."""

    key, config, default = "half", _HalfConfig, _HalfConfig()
    reads = ("gradations",)
    seen: ClassVar[list[TermSizes | None]] = []

    def sizes(self, grid, case):
        graded = case.sizes_of("gradations")
        self.seen.append(graded)
        return TermSizes(upper=graded.upper / 2.0, history="half")


class _Peeks(_Half):
    """Reads a term's field it does not declare."""

    key = "peeks"

    def sizes(self, grid, case):
        case.sizes_of("courant")


def test_a_term_reads_the_field_of_a_term_it_declares():
    """A SizeConfig subclass adds a term (one line); it reads the gradations.

    Its field is the gradations' own sizes, not a copy made anew, and the field
    follows it; a term reading one it does not declare is stopped by name.
    """
    import dataclasses

    from coastmesh.case.config import term_key

    @dataclasses.dataclass(frozen=True)
    class WithHalf(SizeConfig):
        half: object = term_key(_Half())

    def sized(size, threads=1):
        from coastmesh.case.pipeline.size import size_field
        from coastmesh.case.terms.base import SizeCase, SizeTables
        from coastmesh.sizing.grid import PlaneGrid

        domain = _bay()
        grid = PlaneGrid.around(domain, "EPSG:32631", spacing=200.0, smallest=400.0)
        case = SizeCase(SizeTables(size), domain, 200.0, read_depth=None)
        return size_field(grid, case, threads=threads)

    plain = {"h_max": 3000.0, "h_min": 200.0, "gradations": GRADE, "rate": None}
    off = {"channels": OFF, "courant": CourantConfig(enabled=False)}
    base = sized(SizeConfig(**plain, **off))
    for threads in (1, 4):
        _Half.seen.clear()
        halved = sized(WithHalf(**plain, **off), threads)
        (graded,) = _Half.seen
        assert graded is not None and graded.upper is not None
        expected = np.clip(graded.upper / 2.0, 200.0, 3000.0)
        np.testing.assert_allclose(halved.field.values, expected)
        assert (halved.field.values <= base.field.values).all()
        assert (halved.field.values < base.field.values).any()

    @dataclasses.dataclass(frozen=True)
    class WithPeeks(SizeConfig):
        peeks: object = term_key(_Peeks())

    with pytest.raises(KeyError, match="'peeks' reads the field of 'courant' but"):
        sized(WithPeeks(**plain, **off))
