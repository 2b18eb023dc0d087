"""simplify_shorelines: flatten, kernel per contour, rebuild, repair."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest
import shapely

from coastmesh.data import path as data_path
from coastmesh.errors import ConfigError, InputDataError
from coastmesh.geometry import simplify_shorelines
from coastmesh.pca import simplify_contour


@pytest.fixture(scope="module")
def norway():
    text = data_path("norway_west_gshhg_f.geojson").read_text()
    features = json.loads(text)["features"]
    return np.array([shapely.from_geojson(json.dumps(f["geometry"])) for f in features])


def _circle(x, y, r, n):
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    return np.c_[x + r * np.cos(t), y + r * np.sin(t)]


def test_counts_and_validity_on_real_shoreline(norway):
    rings = shapely.get_rings(shapely.get_parts(norway))
    distinct = shapely.get_num_coordinates(rings) - 1
    out, report = simplify_shorelines(norway, 100, 1)
    assert report.contours_in == len(rings)
    assert report.contours_dropped == int((distinct < 100).sum())
    assert report.points_in == int(distinct.sum())
    alive = out[~shapely.is_missing(out)]
    assert len(alive) == report.features_in - report.features_dropped
    assert shapely.is_valid(alive).all()
    out_rings = shapely.get_rings(shapely.get_parts(alive))
    assert (shapely.get_num_coordinates(out_rings) - 1).sum() == report.points_out
    # repairs only add the crossing vertices of the few repaired features
    kept = int(distinct[distinct >= 100].sum())
    assert kept <= report.points_out <= kept + 20 * report.repaired
    assert "contours in" in report.summary()
    assert report.to_dict() == dataclasses.asdict(report)


def test_each_ring_is_the_kernel_result(norway):
    """Where the kernel's rings make a valid polygon, the output is that, to 1e-9.

    The layer goes through the batched kernel (small rings stacked), which agrees
    with the per-ring kernel to rounding, not bit for bit.
    """
    out, report = simplify_shorelines(norway, 100, 5)
    checked = 0
    for before, after in zip(norway, out, strict=True):
        parts = []
        for part in shapely.get_parts(before):
            rings = [
                simplify_contour(shapely.get_coordinates(r)[:-1], 100, 5, closed=True)
                for r in shapely.get_rings(part)
            ]
            if rings[0] is None:
                continue
            parts.append(
                shapely.Polygon(rings[0], [r for r in rings[1:] if r is not None])
            )
        if not parts:
            assert after is None
            continue
        expected = (
            parts[0] if before.geom_type == "Polygon" else shapely.MultiPolygon(parts)
        )
        if shapely.is_valid(expected):
            assert shapely.equals_exact(after, expected, tolerance=1e-9)
            checked += 1
        else:
            assert shapely.is_valid(after)
    assert checked == report.features_in - report.features_dropped - report.repaired


def test_holes_lines_and_types():
    shell = _circle(0, 0, 10, 400)
    hole = _circle(2, 0, 3, 200)
    tiny_hole = _circle(-5, 0, 0.5, 20)
    poly = shapely.Polygon(shell, [hole, tiny_hole])
    island = shapely.Polygon(_circle(30, 0, 1, 30))  # dropped as a whole
    multi = shapely.MultiPolygon(
        [
            shapely.Polygon(_circle(50, 0, 2, 150)),
            shapely.Polygon(_circle(60, 0, 2, 20)),
        ]
    )
    open_line = shapely.LineString(
        np.c_[np.linspace(0, 10, 120), np.sin(np.linspace(0, 10, 120))]
    )
    closed_line = shapely.LineString(np.vstack([_circle(0, 40, 3, 100), [[3, 40]]]))
    geoms = np.array([poly, island, multi, open_line, closed_line, None], dtype=object)
    out, report = simplify_shorelines(geoms, 50, 2)
    assert out[0].geom_type == "Polygon" and len(out[0].interiors) == 1
    assert out[1] is None and out[5] is None
    assert out[2].geom_type == "MultiPolygon" and len(out[2].geoms) == 1
    assert out[3].geom_type == "LineString"
    assert shapely.get_num_coordinates(out[3]) == 120
    assert out[4].geom_type == "LineString" and out[4].is_closed
    np.testing.assert_allclose(
        shapely.get_coordinates(out[4])[:-1],
        simplify_contour(_circle(0, 40, 3, 100), 50, 2, closed=True),
        atol=1e-12,
    )
    assert report.features_in == 5 and report.features_dropped == 1
    assert report.contours_in == 8 and report.contours_dropped == 3


def test_self_intersection_is_repaired():
    """A figure-of-eight ring (kept as it is by the full-rank approximation) is
    invalid; it comes out as a valid multipolygon of its two lobes."""
    t = np.linspace(0, 2 * np.pi, 200, endpoint=False)
    eight = np.c_[np.sin(2 * t), np.sin(t)]  # crosses itself at the origin
    geoms = np.array([shapely.Polygon(eight), shapely.Polygon(_circle(5, 0, 1, 60))])
    assert not shapely.is_valid(geoms[0])
    out, report = simplify_shorelines(geoms, 10, 10)
    assert report.repaired == 1
    assert shapely.is_valid(out[0]) and out[0].geom_type == "MultiPolygon"
    assert len(out[0].geoms) == 2
    lobe = shapely.Polygon(eight[:100]).area  # one lobe, traced on its own
    assert abs(out[0].area - 2 * lobe) < 1e-9
    assert out[1].geom_type == "Polygon"


def test_bad_input():
    bad = shapely.Polygon(_circle(0, 0, 1, 50))
    coords = shapely.get_coordinates(bad)
    coords[7] = np.nan
    with np.errstate(invalid="ignore"):
        nan_ring = shapely.LineString(coords)
    with pytest.raises(InputDataError, match="feature 1: vertex 7"):
        simplify_shorelines([shapely.Point(0, 0).buffer(1), nan_ring], 10, 1)
    with pytest.raises(InputDataError, match=r"feature 0.*Point"):
        simplify_shorelines([shapely.Point(0, 0)], 10, 1)
    with pytest.raises(ConfigError, match="modes = 11"):
        simplify_shorelines([bad], 10, 11)


def test_thread_count_does_not_change_the_layer(norway):
    """Same geometries bit for bit, same report, progress up to every kept point."""
    calls = []
    one, report_one = simplify_shorelines(norway, 30, 2, workers=1)
    two, report_two = simplify_shorelines(
        norway, 30, 2, workers=2, progress=lambda done, total: calls.append(done)
    )
    assert report_one == report_two and report_one.repaired > 0
    assert all(shapely.equals_exact(one, two, tolerance=0) | (one == two))
    rings = shapely.get_rings(shapely.get_parts(norway))
    distinct = shapely.get_num_coordinates(rings) - 1
    assert calls[-1] == distinct[distinct >= 30].sum()
    with pytest.raises(ConfigError, match="workers = 0"):
        simplify_shorelines(norway, 30, 2, workers=0)


@pytest.mark.parametrize(("window", "modes"), [(50, 2), (10, 10)])
def test_points_out_counts_every_output_vertex(window, modes):
    """Rings, holes, open and closed lines, multi-geometries and a repair."""
    poly = shapely.Polygon(_circle(0, 0, 10, 400), [_circle(2, 0, 3, 200)])
    t = np.linspace(0, 2 * np.pi, 200, endpoint=False)
    eight = shapely.Polygon(np.c_[np.sin(2 * t), np.sin(t)])
    line = shapely.LineString(np.c_[np.linspace(0, 10, 120), np.zeros(120)])
    loop = shapely.LineString(np.vstack([_circle(0, 40, 3, 100), [[3, 40]]]))
    geoms = np.array(
        [poly, eight, line, shapely.MultiLineString([line, loop]), None], dtype=object
    )
    out, report = simplify_shorelines(geoms, window, modes)
    parts = shapely.get_parts(out[~shapely.is_missing(out)])
    polygon = shapely.get_type_id(parts) == shapely.GeometryType.POLYGON
    rings = shapely.get_rings(parts[polygon])
    lines = parts[~polygon]
    expected = (
        (shapely.get_num_coordinates(rings) - 1).sum()
        + shapely.get_num_coordinates(lines).sum()
        - shapely.is_closed(lines).sum()
    )
    assert report.repaired == 1
    assert report.points_out == expected >= 400 + 200 + 2 * 120 + 100 + 200


def test_nothing_in_nothing_out():
    for geoms in ([], [None, shapely.Polygon()], [shapely.box(0, 0, 1, 1)]):
        out, report = simplify_shorelines(geoms, 10, 1)
        assert len(out) == len(geoms) and shapely.is_missing(out).all()
        assert report.points_out == 0


def test_valid_polygons_flattens_collections_inside_collections():
    """A repair can return a collection holding a multipolygon: no land is lost."""
    import shapely

    from coastmesh.geometry.layers import valid_polygons

    nested = shapely.GeometryCollection(
        [
            shapely.MultiPolygon([shapely.box(0, 0, 1, 1), shapely.box(2, 0, 3, 1)]),
            shapely.LineString([(0, 5), (1, 5)]),
        ]
    )
    parts = valid_polygons([nested, shapely.box(5, 5, 6, 6)])
    assert [p.bounds for p in parts] == [(0, 0, 1, 1), (2, 0, 3, 1), (5, 5, 6, 6)]
