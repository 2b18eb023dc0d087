"""Stitching shoreline sets by region, checked against shapely set algebra."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from coastmesh.errors import ConfigError
from coastmesh.geometry import OpenBoundary, build_domain
from coastmesh.geometry.stitch import ShorelineSet, stitch_shorelines


def _coast(offset: float) -> shapely.Polygon:
    """Land south of a wavy coast y = 1 + 0.3 sin(x) + offset, 0 <= x <= 20."""
    x = np.linspace(0, 20, 401)
    y = 1 + 0.3 * np.sin(x) + offset
    return shapely.Polygon(np.vstack([np.column_stack([x, y]), [[20, -5], [0, -5]]]))


REGION = shapely.box(5, -10, 12, 10)


@pytest.fixture(scope="module")
def fine_in_coarse():
    """A fine coast in REGION and a coarse one elsewhere, and their stitch."""
    fine, coarse = _coast(0.05), _coast(0.0)
    sets = [
        ShorelineSet("fine", [fine], 10, REGION),
        ShorelineSet("coarse", [coarse], 11),
    ]
    return fine, coarse, stitch_shorelines(sets, crs="EPSG:3857")


def test_land_is_each_set_in_its_region(fine_in_coarse):
    fine, coarse, (land, regions, report) = fine_in_coarse
    union = shapely.union_all(land)
    expected = shapely.union(
        shapely.intersection(fine, REGION), shapely.difference(coarse, REGION)
    )
    assert union.is_valid
    assert shapely.symmetric_difference(union, expected).area < 1e-6  # snap grid
    assert len(land) == 1  # one piece: no gap at the seams
    assert [r[0] for r in regions] == ["fine", "coarse"]
    assert report.polygons == {"fine": 1, "coarse": 2}  # either side
    assert report.to_dict()["polygons"] == report.polygons
    assert report.to_dict()["seam_length"] == pytest.approx(54.0)  # REGION.length
    assert "fine: 1, coarse: 2" in report.summary()


def test_earlier_sets_win_where_regions_overlap():
    a = ShorelineSet("a", [shapely.box(0, 0, 10, 1)], 1, shapely.box(0, -1, 6, 2))
    b = ShorelineSet("b", [shapely.box(0, 0, 10, 2)], 2, shapely.box(4, -1, 10, 3))
    c = ShorelineSet("c", [], 3)
    land, regions, _ = stitch_shorelines([a, b, c], crs="EPSG:3857")
    assert shapely.union_all(land).area == pytest.approx(6 * 1 + 4 * 2)
    expected_b = shapely.difference(shapely.box(4, -1, 10, 3), shapely.box(0, -1, 6, 2))
    assert regions[1][2].equals(expected_b)


def test_boundary_is_tagged_by_region(fine_in_coarse):
    _, _, (land, regions, _) = fine_in_coarse
    walls = [OpenBoundary([(0.5, -1), (0.5, 4), (19.5, 4), (19.5, -1)], "open", 2)]
    domain, _ = build_domain(land, walls, crs="EPSG:3857", shorelines=regions)
    names = {s.name for s in domain.segments}
    assert names == {"fine", "coarse", "open"}
    for s in domain.segments:
        mid = shapely.LineString(s.coords).interpolate(0.5, normalized=True)
        if s.name == "fine":
            assert REGION.buffer(1e-6).contains(mid)
            assert s.physical_id == 10
        elif s.name == "coarse":
            assert not REGION.buffer(-1e-6).contains(mid)


def test_seam_slivers_are_cleaned():
    # the fine region's edge runs along the coast: a thin strip of sea between the
    # two versions of the coast opens along the seam
    fine = shapely.box(0, 0, 20, 1.0)
    coarse = shapely.box(0, 0, 20, 1.02)
    region = shapely.box(-1, -1, 21, 1.01)  # the seam runs between the two coasts
    sets = [
        ShorelineSet("fine", [fine], 10, region),
        ShorelineSet("coarse", [coarse], 11),
    ]
    raw, _, _ = stitch_shorelines(sets, crs="EPSG:3857")
    clean, _, report = stitch_shorelines(sets, crs="EPSG:3857", tolerance=0.05)
    # without cleanup the land has a 0.01-wide notch (coarse land above the seam)
    assert shapely.union_all(raw).area == pytest.approx(20 * 1.0 + 20 * 0.01)
    assert report.land_slivers_removed + report.sea_slivers_filled >= 1
    thin = shapely.union_all(clean)
    # the strip is gone: nothing of the land is narrower than the tolerance
    opened = thin.buffer(-0.049).buffer(0.049)
    assert thin.symmetric_difference(opened).area < 0.01 * 0.05 * 20 * 0.2
    assert thin.is_valid


def test_errors_name_the_problem():
    with pytest.raises(ConfigError, match="exactly one set must have no region"):
        stitch_shorelines(
            [ShorelineSet("a", [], 1, shapely.box(0, 0, 1, 1))], crs="EPSG:3857"
        )
    with pytest.raises(ConfigError, match="names repeat"):
        stitch_shorelines(
            [ShorelineSet("a", [], 1), ShorelineSet("a", [], 2)], crs="EPSG:3857"
        )
    with pytest.raises(ConfigError, match="physical_id"):
        ShorelineSet("a", [], 0)


@settings(max_examples=30, deadline=None)
@given(st.floats(0.01, 0.2), st.floats(1, 9), st.floats(11, 19), st.floats(-0.1, 0.1))
def test_stitch_matches_set_algebra(offset, x0, x1, shift):
    fine, coarse = _coast(offset), _coast(shift)
    region = shapely.box(x0, -10, x1, 10)
    land, _, _ = stitch_shorelines(
        [ShorelineSet("f", [fine], 1, region), ShorelineSet("c", [coarse], 2)],
        crs="EPSG:3857",
    )
    union = shapely.union_all(land)
    expected = shapely.union(
        shapely.intersection(fine, region), shapely.difference(coarse, region)
    )
    assert union.is_valid
    assert shapely.symmetric_difference(union, expected).area < 1e-6
