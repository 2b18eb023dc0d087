"""Figures of mesh quality and of depth on the mesh."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from coastmesh.geometry import reproject_points
from coastmesh.meshing import element_time_steps, mesh_quality, triangle_quality
from coastmesh.plot import depth_figure, quality_figure, time_step_figure
from coastmesh.types import Mesh


@pytest.fixture(scope="module")
def lonlat_mesh(mesh_with_islands):
    """The islands mesh of conftest, in longitude and latitude."""
    m = mesh_with_islands
    lonlat = reproject_points(m.points, m.crs, "EPSG:4326")
    return Mesh(
        lonlat,
        m.triangles,
        m.boundary_edges,
        m.boundary_ids,
        m.surface_id,
        "EPSG:4326",
        {"size": np.full(len(lonlat), 250.0)},
        m.boundary_names,
        m.boundary_kinds,
    )


def test_quality_figure_builds_and_saves(lonlat_mesh, tmp_path):
    report = mesh_quality(lonlat_mesh)
    figure = quality_figure(lonlat_mesh, report, title="test")
    assert len(figure.axes) == 3
    assert figure.axes[2].get_xscale() == "log"
    bars = figure.axes[0].patches[0]  # the minimum-angle histogram
    assert bars.get_data().values.sum() == len(lonlat_mesh.triangles)
    figure.savefig(tmp_path / "quality.png")
    assert (tmp_path / "quality.png").stat().st_size > 1000
    sizeless = Mesh(
        lonlat_mesh.points,
        lonlat_mesh.triangles,
        lonlat_mesh.boundary_edges,
        lonlat_mesh.boundary_ids,
        1,
        lonlat_mesh.crs,
    )
    assert len(quality_figure(sizeless).axes) == 2  # no size, no edge panel


def test_depth_figure_builds_and_saves(lonlat_mesh, tmp_path):
    lon, lat = lonlat_mesh.points.T
    depth = 10 + 1000 * (lon - lon.min())
    depth[0] = np.nan
    mesh = lonlat_mesh.with_point_data(depth=depth)
    figure = depth_figure(mesh, title="depth")
    assert len(figure.axes) == 2  # the map and its colour bar
    ax, bar = figure.axes
    assert ax.get_xlabel().startswith("longitude")
    assert ax.get_aspect() == pytest.approx(
        1 / math.cos(math.radians(lat.mean())), 1e-2
    )
    assert "positive down" in bar.get_ylabel()
    figure.savefig(tmp_path / "depth.png")
    assert (tmp_path / "depth.png").stat().st_size > 1000
    with pytest.raises(ValueError, match="no 'depth'"):
        depth_figure(lonlat_mesh)


def test_time_step_figure_builds_and_saves(lonlat_mesh, mesh_with_islands, tmp_path):
    lon = lonlat_mesh.points[:, 0]
    # 72 m deep in the east, dry (above 0 m) in the west: blank there
    mesh = lonlat_mesh.with_point_data(depth=2000 * (lon - lon.min()) - 10)
    figure = time_step_figure(mesh, title="test")
    assert len(figure.axes) == 2  # the map and its colour bar
    ax, bar = figure.axes
    assert ax.get_xlabel().startswith("longitude")
    assert "stable time step (s)" in bar.get_ylabel()
    assert bar.yaxis.get_scale() == "log"
    steps = element_time_steps(mesh)["dt"]
    finite = np.isfinite(steps)
    assert 0 < finite.sum() < 0.95 * len(steps)
    assert ax.collections[0].get_array().size == finite.sum()
    marker = ax.lines[0]  # the smallest circled, and labelled
    k = int(np.flatnonzero(finite)[np.argmin(steps[finite])])
    centroid = mesh.points[mesh.triangles[k]].mean(axis=0)
    np.testing.assert_allclose(marker.get_xydata()[0], centroid)
    assert ax.texts[0].get_text() == f"min {steps[k]:.3g}"
    figure.savefig(tmp_path / "time_step.png")
    assert (tmp_path / "time_step.png").stat().st_size > 1000

    both = time_step_figure(mesh_with_islands, dt=20.0, velocity=1.0)
    assert len(both.axes) == 4
    courant = both.axes[1]
    assert "Courant number at dt = 20 s" in both.axes[3].get_ylabel()
    report = mesh_quality(mesh_with_islands, dt=20.0, velocity=1.0).time_step
    assert courant.texts[0].get_text() == f"max {report.courant.max:.3g}"
    assert both.axes[0].texts[0].get_text() == f"min {report.min:.3g}"
    both.savefig(tmp_path / "both.png")
    assert (tmp_path / "both.png").stat().st_size > 1000
    with pytest.raises(ValueError, match="no 'depth'"):
        time_step_figure(lonlat_mesh)


def test_time_step_figure_of_a_large_mesh_shades_each_node_by_its_worst(
    lonlat_mesh, monkeypatch, tmp_path
):
    import coastmesh.plot.quality as quality

    lon = lonlat_mesh.points[:, 0]
    mesh = lonlat_mesh.with_point_data(depth=2000 * (lon - lon.min()) + 5)
    steps = element_time_steps(mesh, dt=2.0)
    monkeypatch.setattr(quality, "FLAT_TRIANGLES", len(mesh.triangles) - 1)
    figure = time_step_figure(mesh, dt=2.0)
    ax, ax2 = (a for a in figure.axes if a.get_xlabel().startswith("longitude"))
    for axes, key, worst in ((ax, "dt", np.minimum), (ax2, "courant", np.maximum)):
        image = axes.collections[0]
        assert (
            image.get_shading() == "gouraud" if hasattr(image, "get_shading") else True
        )
        at_nodes = image.get_array()
        want = np.full(len(mesh.points), np.nan)
        for t, value in zip(mesh.triangles, steps[key], strict=True):
            for node in t:  # the literal reduction, one triangle at a time
                want[node] = value if np.isnan(want[node]) else worst(want[node], value)
        np.testing.assert_array_equal(at_nodes, want)
        assert not image.get_in_layout()
    figure.savefig(tmp_path / "time_step.png")


@pytest.mark.parametrize("figure_of", ["depth", "time_step"])
def test_a_mesh_shaded_in_chunks_is_the_same_image(lonlat_mesh, monkeypatch, figure_of):
    """Gouraud shading in chunks of triangles (for memory) draws the same bytes.

    With a triangle masked out (no depth at a node): each chunk drops its own.
    """
    import io

    import coastmesh.plot.base as base
    import coastmesh.plot.quality as quality

    lon = lonlat_mesh.points[:, 0]
    depth = 2000 * (lon - lon.min()) + 5
    depth[lonlat_mesh.triangles[len(lonlat_mesh.triangles) // 2, 0]] = np.nan
    mesh = lonlat_mesh.with_point_data(depth=depth)
    monkeypatch.setattr(quality, "FLAT_TRIANGLES", 0)  # shaded from the nodes
    draw = {"depth": depth_figure, "time_step": time_step_figure}[figure_of]

    def one_collection(ax, triangulation, values, *, in_layout=True, **kwargs):
        """matplotlib's own call, the reference."""
        image = ax.tripcolor(triangulation, values, shading="gouraud", **kwargs)
        image.set_in_layout(in_layout)
        return image

    images = {}
    for chunk in (None, 97):
        with monkeypatch.context() as patch:
            if chunk is None:
                patch.setattr(quality, "shaded_mesh", one_collection)
            else:
                patch.setattr(base, "SHADED_CHUNK", chunk)
            figure = draw(mesh)
        shaded = [c for c in figure.axes[0].collections if c.get_array() is not None]
        assert len(shaded) == (
            1 if chunk is None else math.ceil(len(mesh.triangles) / chunk)
        )
        buffer = io.BytesIO()
        figure.savefig(buffer, format="png", dpi=60)
        images[chunk] = buffer.getvalue()
    assert images[97] == images[None]


def test_shaded_mesh_needs_the_colour_range(lonlat_mesh):
    from matplotlib.figure import Figure
    from matplotlib.tri import Triangulation

    from coastmesh.plot.base import shaded_mesh

    m = lonlat_mesh
    tri = Triangulation(m.points[:, 0], m.points[:, 1], m.triangles)
    ax = Figure().add_subplot()
    with pytest.raises(ValueError, match="vmin and vmax, or norm"):
        shaded_mesh(ax, tri, m.points[:, 0], vmin=0.0)


def test_the_quality_figure_draws_the_reports_histograms(lonlat_mesh):
    """The histograms measured with the report are those of the mesh.

    The figure drawn from them is the figure drawn from the mesh measured
    again (a report without histograms), byte for byte.
    """
    import dataclasses
    import io

    report = mesh_quality(lonlat_mesh)
    assert set(report.histograms) == {"min_angle", "radius_ratio", "edge_ratio"}
    images = []
    for r in (report, dataclasses.replace(report, histograms={})):
        buffer = io.BytesIO()
        quality_figure(lonlat_mesh, r, title="t").savefig(buffer, format="png")
        images.append(buffer.getvalue())
    assert images[0] == images[1]
    angles = triangle_quality(lonlat_mesh)["min_angle"]
    counts, bins = report.histograms["min_angle"]
    assert bins[0] == 0 and bins[-1] == 60 and len(bins) == 91
    literal = [  # one triangle at a time; the last bin holds 60 itself
        sum(1 for a in angles if lo <= a < hi or (k == 89 and a == hi))
        for k, (lo, hi) in enumerate(itertools.pairwise(bins))
    ]
    assert counts.tolist() == literal


def _world_strip(worst_at: tuple[float, float]) -> Mesh:
    """A lon/lat band 360 x 160 deg; one small triangle (the worst) at ``worst_at``."""
    lon = np.linspace(-180, 180, 13)
    lat = np.linspace(-80, 80, 7)
    xx, yy = np.meshgrid(lon, lat)
    points = np.column_stack([xx.ravel(), yy.ravel()])
    nx = len(lon)
    tri = []
    for j, i in itertools.product(range(len(lat) - 1), range(nx - 1)):
        a = j * nx + i
        tri += [[a, a + 1, a + nx + 1], [a, a + nx + 1, a + nx]]
    x, y = worst_at
    small = np.array([[x, y], [x + 0.01, y], [x, y + 0.01]])
    points = np.vstack([points, small])
    n = len(points)
    tri.append([n - 3, n - 2, n - 1])
    depth = np.full(n, 4000.0)
    return Mesh(points, tri, [], [], 1, "EPSG:4326", {"depth": depth})


@pytest.mark.parametrize(
    ("worst_at", "ha", "va"),
    [((-170.0, 75.0), "left", "top"), ((170.0, -75.0), "right", "bottom")],
)
def test_the_worst_label_stays_on_the_map_and_the_map_keeps_its_shape(worst_at, ha, va):
    figure = time_step_figure(_world_strip(worst_at))
    width, height = figure.get_size_inches()
    assert height < 0.75 * width  # a 2:1 map, not a square frame
    ax = figure.axes[0]
    (label,) = [t for t in ax.texts if t.get_text().startswith("min")]
    assert (label.get_ha(), label.get_va()) == (ha, va)
    assert "range" in ax.get_title() and " to 0" not in ax.get_title()


def _pixels(figure) -> np.ndarray:
    figure.canvas.draw()
    return np.asarray(figure.canvas.buffer_rgba())[..., :3]


def test_a_flat_mesh_gives_each_triangle_its_own_colour(lonlat_mesh):
    """Each triangle is one colour, its value's, as matplotlib's flat tripcolor.

    Compared at the pixel of each triangle's centroid (the triangles wider
    than 6 pixels there) with ``tripcolor(facecolors=...)``, the reference;
    chunks draw the same image.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.colors import ListedColormap
    from matplotlib.figure import Figure
    from matplotlib.tri import Triangulation

    import coastmesh.plot.base as base

    m = lonlat_mesh
    values = np.arange(len(m.triangles)) % 5
    colours = ListedColormap(["0.85", "C0", "C2", "C8", "C1"])
    style = {"cmap": colours, "vmin": -0.5, "vmax": 4.5}

    def drawn(how, chunk=None):
        figure = Figure(figsize=(6, 6), dpi=100)
        FigureCanvasAgg(figure)
        ax = figure.add_axes((0, 0, 1, 1))
        if how == "flat":
            base.flat_mesh(ax, m.points, m.triangles, values, chunk=chunk, **style)
        else:
            tri = Triangulation(m.points[:, 0], m.points[:, 1], m.triangles)
            ax.tripcolor(
                tri, facecolors=values.astype(float), antialiased=False, **style
            )
        ax.set_xlim(m.points[:, 0].min(), m.points[:, 0].max())
        ax.set_ylim(m.points[:, 1].min(), m.points[:, 1].max())
        return figure, ax

    figure, ax = drawn("flat")
    image, reference = _pixels(figure), _pixels(drawn("polygons")[0])
    corners = ax.transData.transform(m.points[m.triangles].reshape(-1, 2)).reshape(
        -1, 3, 2
    )
    centre = corners.mean(axis=1)
    # the inscribed circle's radius, pixels: well inside the triangle
    sides = np.linalg.norm(corners - np.roll(corners, 1, axis=1), axis=2)
    u, v = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
    cross = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
    big = np.abs(cross) / sides.sum(axis=1) > 3
    assert big.sum() > 20
    col = np.round(centre[big, 0]).astype(int)
    row = image.shape[0] - 1 - np.round(centre[big, 1]).astype(int)
    np.testing.assert_array_equal(image[row, col], reference[row, col])
    want = np.asarray(colours(values[big].astype(float) / 5 + 0.1))[:, :3] * 255
    np.testing.assert_allclose(image[row, col], want, atol=1)
    assert np.array_equal(_pixels(drawn("flat", chunk=7)[0]), image)


def test_flat_mesh_needs_the_colour_range(lonlat_mesh):
    from matplotlib.figure import Figure

    from coastmesh.plot.base import flat_mesh

    m = lonlat_mesh
    with pytest.raises(ValueError, match="vmin and vmax, or norm"):
        flat_mesh(
            Figure().add_subplot(), m.points, m.triangles, np.zeros(len(m.triangles))
        )
