"""Why the coast and open boundaries enclose no sea: what the error names.

Issue 48 (item 3): a DEM coast of British Columbia whose three open boundaries
cross in the sea (a meridian and two parallels, each overshooting the
crossings by 0.1 deg) built at 0 m and stopped at 0.5, 1, 2 and 10 m with
"enclose no sea", naming the four overshooting ends as 11.1 km from land and
the other open boundaries. Those ends never leave the water open: the domain
drops them as dangles at every level. What changes with the level is the
land: here a 0.1 deg grid whose two coasts are joined at 0 m by a sill 0.3 m
high, across a strait that runs out of the grid. Above 0.3 m the strait is
open, so the sea runs out through it; the error now says so, and names the
two pieces of land, not the crossings.
"""

from __future__ import annotations

import re

import numpy as np
import pytest
import shapely

from coastmesh.data import path as data_path
from coastmesh.errors import InputDataError
from coastmesh.geometry import Loxodrome, OpenBoundary, build_domain, land_from_grid
from coastmesh.io import read_raster

LEVELS = (0.0, 0.5, 1.0, 2.0, 10.0)
#: a window of the bundled ETOPO1 grid: Gotland and the Swedish coast
_BALTIC = (16.9, 56.16, 20.35, 58.42)


def _sill_coast() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Sea west of -127.45, land east of it (50 m), a strait along 50 N.

    The strait (20 m deep) runs east to the grid's edge; at -127.0 its bed is
    a sill 0.3 m above the datum, so the land is one piece at 0 m.
    """
    x = np.round(np.arange(-130.0, -125.95, 0.1), 1)
    y = np.round(np.arange(52.0, 47.95, -0.1), 1)
    lon, lat = np.meshgrid(x, y)
    height = np.where(lon < -127.45, -100.0, 50.0)
    strait = (np.abs(lat - 50.0) < 0.05) & (lon > -127.45)
    height[strait] = -20.0
    height[strait & (np.abs(lon + 127.0) < 0.05)] = 0.3
    return x, y, height


def _crossing_walls(east: float = -127.0) -> list[OpenBoundary]:
    """A meridian crossed by two parallels, every end 0.1 deg past a crossing."""
    return [
        OpenBoundary(
            Loxodrome((-128.6, 48.4), 0, end_lat=51.6).sample(1000), "west", 2
        ),
        OpenBoundary(
            Loxodrome((-128.7, 48.5), 90, end_lon=east).sample(1000), "south", 3
        ),
        OpenBoundary(
            Loxodrome((-128.7, 51.5), 90, end_lon=east).sample(1000), "north", 4
        ),
    ]


def test_a_flooded_sill_opens_the_sea_and_the_error_names_the_land():
    x, y, height = _sill_coast()
    walls = _crossing_walls()
    domain, report = build_domain(land_from_grid(x, y, height, 0.0), walls, crs=4326)
    # at 0 m: closed, the boundaries trimmed at their crossings
    assert shapely.bounds(domain.polygon)[[0, 1, 3]].tolist() == [-128.6, 48.5, 51.5]
    assert set(report.segments) == {"west", "south", "north", "shoreline"}
    for level in LEVELS[1:]:
        with pytest.raises(InputDataError, match="enclose no sea") as error:
            build_domain(land_from_grid(x, y, height, level), walls, crs=4326)
        message = str(error.value)
        assert "ends at" not in message, level  # no end is loose
        assert "the land they reach is 2 pieces that no coast joins" in message
        # where each parallel comes ashore: the coast between -127.5 and -127.4
        assert re.search(r"'south' at \(-127\.4[23]\d\d, 48\.5000\)", message)
        assert re.search(r"'north' at \(-127\.4[23]\d\d, 51\.5000\)", message)
        assert "(-128.6000, 48.4000)" not in message


def test_ends_past_a_crossing_are_not_named_ends_short_of_land_are():
    x, y, height = _sill_coast()
    land = land_from_grid(x, y, height, 0.0)
    walls = _crossing_walls(east=-127.6)  # the parallels stop short of the coast
    with pytest.raises(InputDataError) as error:
        build_domain(land, walls, crs=4326)
    message = str(error.value)
    # the meridian meets both parallels: its ends, 0.1 deg past the crossings,
    # are dangles; each parallel meets the meridian only, so both its ends are
    # free (which side is the sea's, the line alone cannot tell)
    assert "'west'" not in message
    assert message.count("ends at") == 4
    assert "'south' (id 3) ends at (-127.6000, 48.5000)" in message
    assert "'north' (id 4) ends at (-127.6000, 51.5000)" in message


def test_a_line_that_meets_one_thing_names_both_its_free_ends():
    x, y, height = _sill_coast()
    land = land_from_grid(x, y, height, 0.0)
    walls = _crossing_walls(east=-127.6)[:2]  # the meridian and one parallel
    with pytest.raises(InputDataError) as error:
        build_domain(land, walls, crs=4326)
    assert str(error.value).count("ends at") == 4


def test_land_of_no_area_is_no_sea():
    """ETOPO1 has a sample 2e-13 m high at 16.9 E 58.2 N: its land has no area.

    At 0 m its ring polygonized to a face of 5e-12 km2 outside the land, taken
    as the sea; the boundaries there (a meridian and two parallels that reach
    no land) close nothing at 0 m as at 0.5 m.
    """
    raster = read_raster(data_path("etopo1_0.1deg_nwshelf.tif"), bbox=_BALTIC)
    x, y, height = raster.x.values, raster.y.values, raster.values
    land = land_from_grid(x, y, height, 0.0)
    assert 0 < shapely.area(land).min() < 1e-27
    walls = [
        OpenBoundary(Loxodrome((17.2, 56.5), 0, end_lat=58.1).sample(1000), "w", 2),
        OpenBoundary(Loxodrome((17.1, 56.6), 90, end_lon=21.5).sample(1000), "s", 3),
        OpenBoundary(Loxodrome((17.1, 58.0), 90, end_lon=21.5).sample(1000), "n", 4),
    ]
    messages = []
    for level in (0.0, 0.5):
        with pytest.raises(InputDataError, match="enclose no sea") as error:
            build_domain(land_from_grid(x, y, height, level), walls, crs=4326)
        messages.append(str(error.value))
    assert messages[0] == messages[1]
