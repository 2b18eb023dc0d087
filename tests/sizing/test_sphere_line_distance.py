"""Great-circle distance from lines in a plane to the world grid: to the whole
line, as a case's gradations pass the domain's segments, not to its ends."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from pyproj import Geod

from coastmesh.geometry.earth import EARTH_RADIUS, reproject
from coastmesh.geometry.sphere import plane_crs
from coastmesh.sizing.sphere import sphere_distance

SPHERE = Geod(a=EARTH_RADIUS, b=EARTH_RADIUS)
LON = np.arange(-180.0, 180.1, 10.0)
LAT = np.arange(-60.0, 80.1, 10.0)


def _reference(vertices_lonlat: np.ndarray) -> np.ndarray:
    """Node by node: the shortest great-circle distance to any vertex."""
    out = np.empty((len(LAT), len(LON)))
    for j, lat in enumerate(LAT):
        for i, lon in enumerate(LON):
            n = len(vertices_lonlat)
            _, _, d = SPHERE.inv(
                np.full(n, lon),
                np.full(n, lat),
                vertices_lonlat[:, 0],
                vertices_lonlat[:, 1],
            )
            out[j, i] = d.min()
    return out


@settings(max_examples=5, deadline=None)
@given(st.floats(-150, 150), st.floats(-40, 60), st.floats(5, 40), st.booleans())
def test_a_line_and_a_ring_are_measured_along_their_length(lon0, lat0, span, closed):
    plane = plane_crs()
    coords = [(lon0, lat0), (lon0 + span, lat0), (lon0 + span, lat0 + span / 2)]
    if closed:
        coords.append(coords[0])
    line = reproject(
        shapely.segmentize(shapely.LineString(coords), 0.05), "EPSG:4326", plane
    )
    got = sphere_distance(np.array([line]), plane, LON, LAT, 20e3, np.inf)
    dense = reproject(shapely.segmentize(line, 20e3), plane, "EPSG:4326")
    want = _reference(shapely.get_coordinates(dense))
    near = want < 5000e3  # a gradation's reach (far off, the search is coarser)
    np.testing.assert_allclose(got[near], want[near], rtol=0.02, atol=25e3)
    # the middle of the line is at distance ~0, not the distance to its ends
    mid = (lon0 + span / 2 + 180.0) % 360.0 - 180.0
    i = np.argmin(np.abs(LON - mid))
    j = np.argmin(np.abs(LAT - lat0))
    assert got[j, i] == pytest.approx(want[j, i], abs=25e3)


def test_a_polygon_is_measured_from_its_rings():
    plane = plane_crs()
    box = reproject(
        shapely.segmentize(shapely.box(0, 0, 30, 30), 0.05), "EPSG:4326", plane
    )
    got = sphere_distance(np.array([box]), plane, LON, LAT, 20e3, np.inf)
    i, j = np.argmin(np.abs(LON - 15)), np.argmin(np.abs(LAT - 15))
    assert got[j, i] > 1000e3  # its middle is far from its ring


@settings(max_examples=10, deadline=None)
@given(st.integers(0, 10_000), st.floats(2e3, 50e3), st.floats(100e3, 3000e3))
def test_nearest_arcs_are_within_the_resolution_of_the_brute_force(
    seed, resolution, max_distance
):
    """Crowds of vertices centimetres apart (what buffers leave) and nodes far
    from them: every arc within ``resolution`` of the brute-force one, and
    ``inf`` only beyond ``max_distance``."""
    from coastmesh.geometry.sphere import lonlat_to_xyz
    from coastmesh.sizing.distance import nearest_arcs

    rng = np.random.default_rng(seed)
    centres = lonlat_to_xyz(
        np.column_stack([rng.uniform(-180, 180, 30), rng.uniform(-80, 80, 30)])
    )
    crowds = np.repeat(centres, 40, axis=0) + rng.normal(0, 1e-8, (1200, 3))
    vertices = EARTH_RADIUS * crowds
    nodes = EARTH_RADIUS * lonlat_to_xyz(
        np.column_stack([rng.uniform(-180, 180, 400), rng.uniform(-90, 90, 400)])
    )
    got = nearest_arcs(
        vertices, nodes, resolution=resolution, max_distance=max_distance
    )
    cos = np.clip(nodes @ vertices.T / EARTH_RADIUS**2, -1.0, 1.0)
    want = EARTH_RADIUS * np.arccos(cos).min(axis=1)
    found = np.isfinite(got)
    assert (np.abs(got[found] - want[found]) <= resolution).all()
    assert (want[~found] > max_distance - resolution).all()
    assert found[want < max_distance - 2 * resolution].all()
