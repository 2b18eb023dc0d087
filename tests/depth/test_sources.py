"""Several bathymetry sources: priority, blending, coverage, against a literal loop."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from coastmesh.depth import DepthSource, DepthSources
from coastmesh.errors import ConfigError, InputDataError
from coastmesh.geometry.earth import METRES_PER_DEGREE, earth_centred
from coastmesh.io import read_raster


def _grid(values, x0, y0, step, crs="EPSG:4326"):
    ny, nx = np.shape(values)
    return xr.DataArray(
        np.asarray(values, dtype=float),
        dims=("y", "x"),
        coords={"y": y0 + step * np.arange(ny), "x": x0 + step * np.arange(nx)},
        attrs={"crs": crs},
    )


# --- the literal reference -------------------------------------------------------


def _ref_bilinear(raster, px, py):
    x, y, v = raster.x.values, raster.y.values, raster.values
    if not (x[0] <= px <= x[-1] and y[0] <= py <= y[-1]):
        return np.nan
    i = min(int(np.searchsorted(x, px, side="right")) - 1, len(x) - 2)
    j = min(int(np.searchsorted(y, py, side="right")) - 1, len(y) - 2)
    tx = (px - x[i]) / (x[i + 1] - x[i])
    ty = (py - y[j]) / (y[j + 1] - y[j])
    corners = [v[j, i], v[j, i + 1], v[j + 1, i], v[j + 1, i + 1]]
    weights = [(1 - tx) * (1 - ty), tx * (1 - ty), (1 - tx) * ty, tx * ty]
    used = [c for c, w in zip(corners, weights, strict=True) if w > 0]
    if any(np.isnan(c) for c in used):
        return np.nan
    return sum(c * w for c, w in zip(corners, weights, strict=True) if w > 0)


def _ref_edge_cells(raster):
    v = raster.values
    ny, nx = v.shape
    cells = []
    for j in range(ny):
        for i in range(nx):
            if np.isnan(v[j, i]):
                continue
            edge = j in (0, ny - 1) or i in (0, nx - 1)
            for dj in (-1, 0, 1):
                for di in (-1, 0, 1):
                    jj, ii = j + dj, i + di
                    if 0 <= jj < ny and 0 <= ii < nx and np.isnan(v[jj, ii]):
                        edge = True
            if edge:
                cells.append((raster.x.values[i], raster.y.values[j], v[j, i]))
    return cells


def _ref_sample(stack, sign, blends, px, py):
    """Depth and source, lowest priority first, one lon/lat point at a time."""
    from pyproj import CRS, Transformer

    depth, source = np.nan, -1
    p = earth_centred([[px, py]], "EPSG:4326")[0]
    for k in range(len(stack) - 1, -1, -1):
        raster = stack[k].sortby("y").sortby("x")
        crs = CRS.from_user_input(raster.attrs["crs"])
        rx, ry = Transformer.from_crs("EPSG:4326", crs, always_xy=True).transform(
            px, py
        )
        z = sign[k] * _ref_bilinear(raster, rx, ry)
        if np.isnan(z):
            continue
        w = 1.0
        dx = raster.x.values[1] - raster.x.values[0]
        dy = raster.y.values[1] - raster.y.values[0]
        if crs.is_geographic:
            lat = np.min(np.abs(raster.y.values))
            dx, dy = (
                dx * METRES_PER_DEGREE * np.cos(np.radians(lat)),
                dy * METRES_PER_DEGREE,
            )
        delta = 0.5 * max(dx, dy)
        blend = max(blends[k], delta) if blends[k] > 0 else 0.0
        if blend > 0 and not np.isnan(depth):
            cells = _ref_edge_cells(raster)
            xyz = earth_centred([c[:2] for c in cells], crs)
            d = np.min(np.linalg.norm(xyz - p, axis=1))
            t = min(max((d - delta) / max(blend - delta, 1e-6), 0.0), 1.0)
            w = t * t * (3 - 2 * t)
        depth = z if np.isnan(depth) else w * z + (1 - w) * depth
        if w > 0:
            source = k
    return depth, source


@st.composite
def stacks(draw):
    """Two or three small lon/lat rasters over one area, holes, blends, signs."""
    n = draw(st.integers(2, 3))
    rasters, signs, blends = [], [], []
    for _ in range(n):
        ny, nx = draw(st.integers(3, 7)), draw(st.integers(3, 7))
        step = draw(st.sampled_from([0.05, 0.1, 0.2]))
        x0 = draw(st.floats(-0.4, 0.2))
        y0 = draw(st.floats(55.6, 56.2))
        seed = draw(st.integers(0, 2**16))
        rng = np.random.default_rng(seed)
        values = rng.uniform(-200, 50, (ny, nx))
        values[rng.random((ny, nx)) < 0.15] = np.nan
        if np.isnan(values).all():
            values[0, 0] = -10.0
        rasters.append(_grid(values, x0, y0, step))
        signs.append(draw(st.sampled_from([-1.0, 1.0])))
        blends.append(draw(st.sampled_from([0.0, 2e3, 8e3, 15e3])))
    points = draw(
        st.lists(
            st.tuples(st.floats(-0.5, 1.5), st.floats(55.5, 57.5)),
            min_size=1,
            max_size=12,
        )
    )
    return rasters, signs, blends, np.array(points)


def _stack(rasters, signs, blends):
    return DepthSources(
        [
            DepthSource(r, "up" if s < 0 else "down", b, name=f"s{k}")
            for k, (r, s, b) in enumerate(zip(rasters, signs, blends, strict=True))
        ]
    )


def _edge_case():
    """A point on a cell-centre line whose cells beyond the line are missing."""
    a = _grid([[-164.6, 17.5], [-0.8, np.nan]], 0.0, 55.775, 0.05)
    b = _grid([[-195.9, 3.3], [-48.3, -17.6]], 0.0, 55.725, 0.1)
    return [a, b], [-1.0, -1.0], [0.0, 0.0], np.array([[0.0, 55.8125], [0.0, 55.775]])


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(stacks())
@example(_edge_case())
def test_stack_matches_the_literal_reference(case):
    rasters, signs, blends, points = case
    try:
        stack = _stack(rasters, signs, blends)
    except ConfigError:  # a blend at least half a source's extent
        return
    sample = stack.sample(points, "EPSG:4326")
    for k, (px, py) in enumerate(points):
        depth, source = _ref_sample(rasters, signs, blends, px, py)
        if source >= 0 or not np.isnan(depth):
            assert not sample.snapped[k]
            assert sample.depth[k] == pytest.approx(depth, abs=1e-9, rel=1e-12)
            assert sample.source[k] == source
        elif not sample.snapped[k]:
            assert sample.source[k] == -1 and np.isnan(sample.depth[k])


def _two_overlapping(blend):
    """A fine 'survey' (0.01 deg, depths down) inside a coarse grid (elevations)."""
    lon = np.arange(-3.0, -1.0 + 1e-9, 0.1)
    lat = np.arange(58.0, 59.0 + 1e-9, 0.1)
    coarse = -(40 + 20 * np.sin(lon)[None, :] + 30 * np.cos(lat)[:, None])
    fine_lon = np.arange(-2.5, -1.5 + 1e-9, 0.01)
    fine_lat = np.arange(58.3, 58.7 + 1e-9, 0.01)
    fine = 55 + 10 * np.sin(5 * fine_lon)[None, :] + 8 * np.cos(7 * fine_lat)[:, None]
    survey = DepthSource(_grid(fine, -2.5, 58.3, 0.01), "down", blend, "survey")
    base = DepthSource(_grid(coarse, -3.0, 58.0, 0.1), "up", 0.0, "base")
    return DepthSources([survey, base]), survey, base


def test_interior_is_the_source_and_the_blend_has_no_step():
    blend = 5e3
    stack, survey, base = _two_overlapping(blend)
    # a line across the survey's west edge (-2.5), densely sampled
    lon = np.linspace(-2.8, -2.0, 4001)
    pts = np.column_stack([lon, np.full_like(lon, 58.5)])
    s = stack.sample(pts, "EPSG:4326")
    own = DepthSources([survey]).sample(pts, "EPSG:4326").depth
    under = DepthSources([base]).sample(pts, "EPSG:4326").depth
    # beyond the blend inside the survey: exactly its bilinear value
    metres_in = (lon + 2.5) * METRES_PER_DEGREE * np.cos(np.radians(58.5))
    interior = metres_in > blend + 1e3
    np.testing.assert_array_equal(s.depth[interior], own[interior])
    assert (s.source[interior] == 0).all()
    # in the blend zone: between the two sources, never beyond their difference
    zone = np.isfinite(own) & ~interior
    lo, hi = np.minimum(own, under), np.maximum(own, under)
    assert (
        (s.depth[zone] >= lo[zone] - 1e-9) & (s.depth[zone] <= hi[zone] + 1e-9)
    ).all()
    assert s.blended.sum() > 100
    # no step: neighbouring samples differ by no more than the two fields' own
    # changes plus the ramp's steepest change (1.5 x their difference / width)
    h = (lon[1] - lon[0]) * METRES_PER_DEGREE * np.cos(np.radians(58.5))
    jump = np.abs(np.diff(s.depth)).max()
    slope = np.nanmax(np.abs(np.diff(own))) + np.abs(np.diff(under)).max()
    delta = stack._prepared[0].delta  # half the survey cell: w is 0 there
    ramp = 1.5 * np.nanmax(np.abs(own - under)[zone]) * h / (blend - delta)
    assert jump <= slope + ramp
    # a hard seam does step, by the sources' difference at the edge
    hard, _, _ = _two_overlapping(0.0)
    steps = np.abs(np.diff(hard.sample(pts, "EPSG:4326").depth)).max()
    assert steps > 10 * (slope + ramp)


def test_source_in_another_crs_and_resolution_on_real_data(orkney_tif):
    """ETOPO (lon/lat, 0.1 deg) under a UTM 'survey' made from it at 1 km."""
    from rasterio.warp import Resampling, reproject

    etopo = read_raster(orkney_tif)
    x = np.arange(440e3, 560e3, 1e3)
    y = np.arange(6.57e6, 6.45e6, -1e3)
    utm = np.full((len(y), len(x)), np.nan)
    reproject(
        etopo.values,
        utm,
        src_transform=etopo.attrs["transform"],
        src_crs="EPSG:4326",
        dst_transform=[1e3, 0, x[0] - 500, 0, -1e3, y[0] + 500],
        dst_crs="EPSG:32630",
        resampling=Resampling.bilinear,
        dst_nodata=np.nan,
    )
    utm -= 3.0  # a datum offset, so the two differ
    survey = xr.DataArray(
        utm, dims=("y", "x"), coords={"y": y, "x": x}, attrs={"crs": "EPSG:32630"}
    )
    stack = DepthSources(
        [DepthSource(survey, "up", 4e3, "utm"), DepthSource(etopo, "up", 0.0, "etopo")]
    )
    rng = np.random.default_rng(1)
    pts = np.column_stack(
        [rng.uniform(-4.5, -1.0, 3000), rng.uniform(58.0, 59.5, 3000)]
    )
    s = stack.sample(pts, "EPSG:4326")
    for k in rng.choice(len(pts), 40, replace=False):  # the reference is slow
        ref, src = _ref_sample([survey, etopo], [-1, -1], [4e3, 0.0], *pts[k])
        assert s.source[k] == src
        assert s.depth[k] == pytest.approx(ref, abs=1e-9)
    assert s.blended.sum() > 50
    assert (s.source == 0).sum() > 500 and (s.source == 1).sum() > 500
    assert not s.uncovered.any()


def test_uncovered_points_snap_within_a_cell_or_stay_uncovered():
    r = _grid([[1.0, 2.0], [3.0, 4.0]], 0.0, 50.0, 0.1)
    stack = DepthSources([DepthSource(r, "down", name="tiny")])
    s = stack.sample([[0.05, 50.05], [0.14, 50.05], [0.5, 50.05]], "EPSG:4326")
    assert s.source.tolist() == [0, 0, -1]
    assert s.snapped.tolist() == [False, True, False]
    assert s.depth[1] == 4.0 or s.depth[1] == 2.0
    message = stack.uncovered_message(
        s, [[0.05, 50.05], [0.14, 50.05], [0.5, 50.05]], "EPSG:4326"
    )
    assert "tiny" in message and "1 of 3" in message and "lon 0.5000" in message


def test_nearest_valid_and_wet_cells():
    r = _grid([[-5.0, -3.0, 2.0], [-8.0, 1.0, 4.0]], 0.0, 50.0, 0.1)  # elevations
    stack = DepthSources([DepthSource(r, "up", name="g")])
    value, which, _ = stack.nearest([[0.6, 50.0], [0.21, 50.1]], "EPSG:4326")
    assert value.tolist() == [-2.0, -4.0] and which.tolist() == [0, 0]
    wet, _, _ = stack.nearest([[0.21, 50.1]], "EPSG:4326", kind="wet")
    assert wet.tolist() == [3.0]  # the nearest cell below sea level (depth 3 m)


def test_bad_sources():
    r = _grid(np.zeros((3, 3)), 0.0, 0.0, 0.1)
    with pytest.raises(ConfigError, match="no bathymetry source"):
        DepthSources([])
    with pytest.raises(ConfigError, match="source s: blend = 20 km is at least half"):
        DepthSources([DepthSource(r, blend=20e3, name="s")])
    with pytest.raises(ConfigError, match="source s: positive = 'sideways'"):
        DepthSource(r, "sideways", name="s")
    with pytest.raises(InputDataError, match="source s has no CRS"):
        DepthSource(r.assign_attrs(crs=None), name="s")
    with pytest.raises(InputDataError, match="source s has no valid cell"):
        DepthSources([DepthSource(r * np.nan, name="s")])


def test_disjoint_sources_leave_a_gap_that_is_named():
    from coastmesh.depth import depth_at_nodes
    from coastmesh.types import Mesh

    west = _grid(np.full((5, 5), -20.0), 0.0, 50.0, 0.1)  # 0.0 - 0.4 E
    east = _grid(np.full((5, 5), -30.0), 1.0, 50.0, 0.1)  # 1.0 - 1.4 E
    stack = DepthSources(
        [DepthSource(west, name="west"), DepthSource(east, name="east")]
    )
    pts = [[0.2, 50.2], [0.7, 50.2], [1.2, 50.2]]
    mesh = Mesh(pts, [[0, 1, 2]], [[0, 1], [1, 2], [2, 0]], [1, 1, 1], 1, "EPSG:4326")
    with pytest.raises(InputDataError) as info:
        depth_at_nodes(mesh, stack)
    message = str(info.value)
    assert "sources leave a gap: 1 of 3" in message
    assert "lon 0.7000 to 0.7000, lat 50.2000 to 50.2000" in message
    assert "west covers 33.3%" in message and "east covers 33.3%" in message
    with pytest.warns(Warning, match="took the nearest valid cell"):
        depth, report = depth_at_nodes(mesh, stack, outside="nearest")
    assert depth.tolist() == [20.0, 20.0, 30.0]  # 0.7 E is nearer 0.4 than 1.0
    assert report.per_source == (2, 1) and report.nearest == 1
