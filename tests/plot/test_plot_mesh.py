"""Figures of a case: domain, mesh, size field, Mercator view."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
import xarray as xr

from coastmesh.geometry import reproject_points
from coastmesh.plot import domain_figure, mercator_figure, mesh_figure, size_figure
from coastmesh.types import BoundarySegment, Domain, Mesh


def _legend(ax) -> list[str]:
    return [t.get_text() for t in ax.get_legend().get_texts()]


def test_domain_figure_colours_each_id():
    ring = [[0, 0], [1000, 0], [1000, 1000], [0, 1000], [0, 0]]
    domain = Domain(
        shapely.Polygon(ring),
        (
            BoundarySegment(ring[:2], "open", "south", 2),
            BoundarySegment(ring[1:], "shoreline", "coast", 1),
        ),
        crs="EPSG:32630",
    )
    (ax,) = domain_figure(domain, title="square").axes
    assert _legend(ax) == ["1: coast", "2: south"]
    water, lines = ax.collections  # the water, one path, under the boundary
    assert water.get_zorder() < lines.get_zorder()
    assert len({tuple(c) for c in lines.get_colors()}) == 2


def test_domain_figure_leaves_the_islands_out_of_the_water():
    outer = shapely.box(0, 0, 1000, 1000).exterior.coords
    hole = shapely.box(400, 400, 600, 600).exterior.coords  # either turning way
    domain = Domain(
        shapely.Polygon(outer, [hole]),
        (
            BoundarySegment(list(outer), "shoreline", "coast", 1),
            BoundarySegment(list(hole), "shoreline", "rock", 3),
        ),
        crs="EPSG:32630",
    )
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    figure = domain_figure(domain)
    canvas = FigureCanvasAgg(figure)
    canvas.draw()
    pixels = np.asarray(canvas.buffer_rgba())
    (ax,) = figure.axes

    def colour(x, y):
        px, py = ax.transData.transform((x, y))
        return tuple(pixels[int(pixels.shape[0] - py), int(px), :3])

    assert colour(500, 500) == (255, 255, 255)  # the island: not water
    assert colour(200, 200) == (0xDB, 0xE9, 0xF6)  # water


def test_mesh_figure_names_ids_from_the_mesh(mesh_with_islands):
    figure = mesh_figure(mesh_with_islands, title="islands")
    (ax,) = figure.axes
    assert _legend(ax) == ["1: coast", "2: south", "3: rock"]
    assert f"{len(mesh_with_islands.triangles):,} triangles" in ax.get_title()
    (ax,) = mesh_figure(mesh_with_islands, names={3: "skerry"}).axes
    assert _legend(ax)[2] == "3: skerry"


def test_size_figure_is_logarithmic():
    field = xr.DataArray(
        np.geomspace(100.0, 10_000.0, 12).reshape(3, 4),
        dims=("y", "x"),
        coords={"y": [0.0, 1e3, 2e3], "x": [0.0, 1e3, 2e3, 3e3]},
        attrs={"crs": "EPSG:32630", "units": "m"},
    )
    figure = size_figure(field, title="size")
    image = figure.axes[0].collections[0]
    assert type(image.norm).__name__ == "LogNorm"
    assert image.norm.vmin == pytest.approx(100.0)


def test_mercator_figure_with_a_detail(mesh_with_islands):
    m = mesh_with_islands
    lonlat = Mesh(
        reproject_points(m.points, m.crs, "EPSG:4326"),
        m.triangles,
        m.boundary_edges,
        m.boundary_ids,
        1,
        "EPSG:4326",
        boundary_names=m.boundary_names,
    )
    lon, lat = lonlat.points.mean(axis=0)
    figure = mercator_figure(lonlat, detail=(lon - 0.01, lat - 0.01, lon, lat))
    whole, detail = figure.axes
    assert whole.get_xlabel().startswith("Mercator x")
    assert detail.get_xlim()[1] - detail.get_xlim()[0] < 2.0  # km
    with pytest.raises(ValueError, match="no CRS"):
        mercator_figure(Mesh(m.points, m.triangles, [], [], 1, None))


def test_a_mercator_map_of_the_globe_stops_at_85_degrees():
    points = [[-60, -89.5], [60, -89.5], [60, 89.5], [-60, 89.5], [0, 0]]
    triangles = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]
    mesh = Mesh(
        points, triangles, [[0, 1], [1, 2], [2, 3], [3, 0]], [1] * 4, 1, "EPSG:4326"
    )
    figure = mercator_figure(mesh)
    y0, y1 = figure.axes[0].get_ylim()
    edge = reproject_points([[0.0, 85.0]], "EPSG:4326", "EPSG:3395")[0, 1] / 1000
    assert (y0, y1) == pytest.approx((-edge, edge))
    assert "to 85 deg" in figure.axes[0].get_title()
