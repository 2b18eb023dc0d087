"""[[lines]] in a case: read, checked against the sea and the site, named."""

from __future__ import annotations

import pytest
import shapely
from conftest import EXAMPLE, coarse_example_text
from test_farms import SITE, _state

from coastmesh.case import parse_case
from coastmesh.case.pipeline.farms import site_features
from coastmesh.case.pipeline.lines import _check
from coastmesh.errors import ConfigError

CABLE = "[[-3.1350, 58.6545], [-3.1340, 58.6500], [-3.1345, 58.6460]]"
LINE = f"""
[[lines]]
name = "export"
id = 40
points = {CABLE}
h = "15 m"
"""


def _case(extra: str = LINE, site: str = SITE):
    return parse_case(coarse_example_text() + site + extra, EXAMPLE)


def test_lines_are_read_into_the_meshing_crs():
    site = site_features(_case(), _state(None))
    ((name, pid, line, h),) = site.lines
    assert (name, pid, h) == ("export", 40, 15.0)
    assert line.length == pytest.approx(960, rel=0.05)  # metres in UTM 30N
    inner = site.inner()
    assert [(pid, name) for _, pid, name in inner.lines] == [(40, "export")]
    assert site.smallest() <= 15.0


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ("[-3.1350, 58.6545]", "[-3.1350, 58.6575]", "crosses the outline of 'meygen'"),
        ("[-3.1345, 58.6460]", "[-3.1345, 58.55]", "crosses the coast or an open"),
        (CABLE, "[[-3.5, 58.8], [-3.4, 58.8]]", "lies on land or outside"),
        (
            CABLE,
            "[[-3.13, 58.65], [-3.12, 58.65], [-3.13, 58.64], [-3.12, 58.66]]",
            "crosses itself",
        ),
        ("id = 40", "id = 20", r"lines\[0\]: id 20 is also the id of 'meygen'"),
        ('name = "export"', 'name = "meygen"', "the name 'meygen' is used twice"),
    ],
)
def test_bad_lines_are_named(old, new, message):
    with pytest.raises(ConfigError, match=message):
        site_features(_case(LINE.replace(old, new, 1)), _state(None))


def test_a_line_touching_the_boundary_or_another_line_is_refused():
    sea = shapely.box(0, 0, 100, 100)
    touching = shapely.LineString([(50, 50), (50, 100)])
    with pytest.raises(ConfigError, match="'x': the line touches the domain's"):
        _check(touching, "'x'", sea, [], [])
    other = ("cable", 7, shapely.LineString([(20, 20), (80, 80)]), None)
    spur = shapely.LineString([(50, 50), (50, 90)])
    with pytest.raises(ConfigError, match="'x': the line crosses or touches line"):
        _check(spur, "'x'", sea, [], [other])
    _check(shapely.LineString([(10, 50), (30, 50)]), "'x'", sea, [], [other])
