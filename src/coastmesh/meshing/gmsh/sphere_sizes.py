"""Sizes for a mesh of the whole sphere, meshed in a stereographic plane.

A global mesh is made in the stereographic plane of
:func:`coastmesh.geometry.sphere.plane_crs`, whose singular point lies on land.
Its size field cannot be a regular grid in that plane: the ocean's image reaches
about 11 Earth radii from the centre while the scale factor runs from 1 to about
90, so a plane grid fine enough at the centre would hold 10^8 cells. The field
is kept on a longitude/latitude grid instead (:class:`SphereSizeGrid`), and
handed to the mesher as it is:

* sampled at points of the plane by inverting the projection and interpolating
  bilinearly in longitude and latitude (longitude wraps round);
* given to Gmsh as a view of the grid's cells with their corners moved into the
  plane: meridians are straight there, parallels are circles that the cells'
  edges cut as chords; the cells at a pole of the grid are triangles;
* in map units, the sizes are multiplied by the plane's scale factor, so edge
  lengths on the sphere follow the field.

Gmsh's own interpolation inside a cell is bilinear in the plane, not in
longitude and latitude: at most a few per cent apart where the field changes
fast within one cell, which the grid spacing controls.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray
from pyproj import CRS

from coastmesh.geometry.cells import points_inside
from coastmesh.geometry.earth import EARTH_RADIUS, transformer
from coastmesh.geometry.grids import cell_of, interpolate_bilinear
from coastmesh.geometry.sphere import plane_crs, stereographic_scale
from coastmesh.types import SizeGrid

__all__ = ["SphereSizeGrid"]

_LONLAT = CRS.from_epsg(4326)


@dataclass(frozen=True, slots=True)
class SphereSizeGrid:
    """A size field on a longitude/latitude grid, for a mesh in a plane.

    Parameters
    ----------
    grid : SizeGrid
        ``x`` longitudes and ``y`` latitudes (degrees, ascending) of the nodes,
        ``values`` the edge lengths in metres on the sphere. The longitudes
        span one turn exactly (the last is the first plus 360) so that the grid
        wraps round.
    pole : (lon, lat)
        The plane's singular point (:func:`~coastmesh.geometry.sphere.plane_crs`).
    map_units : bool
        Whether :meth:`sample` and :meth:`view_data` give plane lengths (metres
        on the sphere times the scale factor) or lengths on the sphere.
    reach : float, default inf
        The farthest the water reaches from the plane's centre, metres in
        the plane: :meth:`view_data` leaves out the cells wholly beyond it.
        Round the plane's singular point (on land) the cells grow without
        bound (a node on the pole itself is at infinity), and Gmsh's search
        tree over a view of such cells took over 24 GB (a pole in Asia).

    Raises
    ------
    ValueError
        If the longitudes do not span exactly 360 degrees, or a latitude is
        beyond 90.

    Examples
    --------
    >>> lon = np.linspace(-180.0, 180.0, 9)
    >>> lat = np.linspace(-60.0, 90.0, 6)
    >>> g = SphereSizeGrid(SizeGrid(lon, lat, np.full((6, 9), 1000.0)))
    >>> xy = np.array([[0.0, 0.0]])  # the plane's centre: the North Pole
    >>> float(g.sample(xy)[0]), float(g.in_map_units().sample(xy)[0])
    (1000.0, 1000.0)
    """

    grid: SizeGrid
    pole: tuple[float, float] = (0.0, -90.0)
    map_units: bool = False
    reach: float = math.inf

    def __post_init__(self) -> None:
        lon, lat = self.grid.x, self.grid.y
        if abs(lon[-1] - lon[0] - 360.0) > 1e-9:
            raise ValueError(
                f"the size grid's longitudes run from {lon[0]} to {lon[-1]}: a "
                "global grid spans exactly 360 degrees (the last is the first + 360)"
            )
        if lat[0] < -90.0 or lat[-1] > 90.0:
            raise ValueError(
                f"the size grid's latitudes run from {lat[0]} to {lat[-1]}, past a pole"
            )
        object.__setattr__(self, "pole", (float(self.pole[0]), float(self.pole[1])))

    @property
    def crs(self) -> CRS:
        """The plane the mesh is made in."""
        return plane_crs(self.pole)

    def in_map_units(self) -> SphereSizeGrid:
        """Return the same field, sampled in plane lengths."""
        return SphereSizeGrid(self.grid, self.pole, map_units=True, reach=self.reach)

    def lonlat(self, xy: NDArray[np.float64]) -> NDArray[np.float64]:
        """Return the longitude and latitude of points of the plane."""
        xy = np.asarray(xy, dtype=np.float64).reshape(-1, 2)
        lon, lat = transformer(self.crs, _LONLAT).transform(xy[:, 0], xy[:, 1])
        return np.column_stack([lon, lat])

    def sample(self, xy: NDArray[np.float64]) -> NDArray[np.float64]:
        """Interpolate the field at points of the plane (bilinear in lon/lat)."""
        ll = self.lonlat(xy)
        values = self.at_lonlat(ll[:, 0], ll[:, 1])
        if self.map_units:
            values = values * stereographic_scale(ll[:, 0], ll[:, 1], self.pole)
        return values

    def at_lonlat(
        self, lon: NDArray[np.float64], lat: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        """Interpolate the field (metres on the sphere) at lon/lat points.

        Longitudes wrap round; latitudes past the grid's first or last row take
        that row's values.
        """
        g = self.grid
        return interpolate_bilinear(
            g.x, g.y, g.values, self._wrap(lon), lat, clamp=True
        )

    def view_data(
        self,
        bounds: tuple[float, ...] | None = None,
        near: NDArray[np.float64] | None = None,
    ) -> dict[str, NDArray[np.float64]]:
        """Return the grid's cells in the plane, in Gmsh's list format, by type.

        Returns ``{"SQ": quadrangles, "ST": triangles}``: a quadrangle per cell
        (corners counter-clockwise in the plane), and a triangle per cell of a
        row that ends at the North Pole (where the cell's two top corners are one
        point). Values are plane lengths when :attr:`map_units` is set. With
        ``bounds`` (x0, y0, x1, y1 in the plane: a part of the water), only the
        cells whose extent meets them: each part's Gmsh holds a view of its
        own water, not of the world. With ``near`` (points of the plane, (k,
        2)), only the cells holding a point and the 3 x 3 around each (round
        the antimeridian too): a point within a cell of one of them lies in
        one (Gmsh's 1-D mesher asks for sizes on the curves only).
        """
        x, y = self.grid.x, self.grid.y
        top = y[-1] >= 90.0 - 1e-9
        rows, columns = len(y) - 1 - int(top), x.size - 1
        corners = [(0, 0), (0, 1), (1, 1), (1, 0)]  # (dj, di): east, then north
        if near is None:
            px, py = self._whole_plane()

            def plane(
                j: NDArray[np.int64], i: NDArray[np.int64]
            ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
                return px[j, i], py[j, i]

            def chosen(
                order: list[tuple[int, int]], r0: int, r1: int
            ) -> NDArray[np.bool_]:
                """Return which cells of rows r0 to r1 meet ``bounds``."""
                keep = np.ones((r1 - r0, columns), dtype=bool)
                if bounds is None:
                    return keep
                for a, low, high in (
                    (px, bounds[0], bounds[2]),
                    (py, bounds[1], bounds[3]),
                ):
                    at = [a[r0 + dj : r1 + dj, di : columns + di] for dj, di in order]
                    with np.errstate(invalid="ignore"):
                        keep &= np.maximum.reduce(at) >= low
                        keep &= np.minimum.reduce(at) <= high
                return keep

        else:  # the few cells along the curves: their corners projected alone
            plane, wanted = self._nodes_in_plane, self._cells_near(near)

            def chosen(
                order: list[tuple[int, int]], r0: int, r1: int
            ) -> NDArray[np.bool_]:
                return wanted[r0:r1]

        def block(
            order: list[tuple[int, int]], r0: int, r1: int
        ) -> NDArray[np.float64]:
            # the cells are chosen on the grid, then only theirs are gathered: a
            # part's view holds a few per cent of the world's 10^6 cells
            j, i = np.nonzero(chosen(order, r0, r1))
            j = j + r0
            xy = [plane(j + dj, i + di) for dj, di in order]
            if near is not None and bounds is not None:
                keep = _meets(xy, bounds)
                j, i, xy = j[keep], i[keep], [(a[keep], b[keep]) for a, b in xy]
            values = [self._value(j + dj, i + di) for dj, di in order]
            cells = np.column_stack(
                [a for a, _ in xy]
                + [b for _, b in xy]
                + [np.zeros(j.size)] * len(order)
                + values
            )
            return cells[self._near(cells, len(order))].ravel()

        out = {"SQ": block(corners, 0, rows)}
        if top:
            out["ST"] = block([(0, 0), (0, 1), (1, 0)], rows, rows + 1)
        else:
            out["ST"] = np.zeros(0)
        return out

    def _whole_plane(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Return the plane x and y of every grid node, the wrapped column too.

        The wrapped column (the first again, a turn on) is projected as itself.
        """
        x, y = self.grid.x, self.grid.y
        px, py = _plane_nodes(x, y, self.pole)
        ex, ey = transformer(_LONLAT, self.crs).transform(np.full(y.size, x[-1]), y)
        return np.column_stack([px, ex]), np.column_stack([py, ey])

    def _nodes_in_plane(
        self, j: NDArray[np.int64], i: NDArray[np.int64]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Return the plane x and y of grid nodes (rows ``j``, columns ``i``).

        Each node projected alone: the same numbers as the whole grid's (the
        projection is point by point), for a view of a few cells in a grid of
        millions (``world_fine.toml``: 0.4 s a batch of the boundary for the
        whole grid).
        """
        return transformer(_LONLAT, self.crs).transform(self.grid.x[i], self.grid.y[j])

    def _value(self, j: NDArray[np.int64], i: NDArray[np.int64]) -> NDArray[np.float64]:
        """Return the field at grid nodes (rows ``j``, columns ``i``).

        In plane lengths when :attr:`map_units` is set.
        """
        v = self.grid.values[j, i]
        if self.map_units:
            x, y = self.grid.x, self.grid.y
            v = v * stereographic_scale(x[i], y[j], self.pole)
        return v

    def _wrap(self, lon: ArrayLike) -> NDArray[np.float64]:
        """Return longitudes moved by whole turns into the grid's first turn."""
        x0 = float(self.grid.x[0])
        return (np.asarray(lon, dtype=np.float64) - x0) % 360.0 + x0

    def _cells_near(self, xy: NDArray[np.float64]) -> NDArray[np.bool_]:
        """Return which grid cells (rows, columns) hold a point or are next to one."""
        x, y = self.grid.x, self.grid.y
        ll = self.lonlat(xy)
        i, j = cell_of(x, y, self._wrap(ll[:, 0]), ll[:, 1])
        held = np.zeros((y.size - 1, x.size - 1), dtype=bool)
        held[j, i] = True
        # the 3 x 3 around each: columns wrap round, rows stop at the poles
        out = held | np.roll(held, 1, axis=1) | np.roll(held, -1, axis=1)
        out[1:] |= out[:-1].copy()
        out[:-1] |= out[1:].copy()
        return out

    def plane_cell(self, xy: NDArray[np.float64]) -> NDArray[np.float64]:
        """Return the grid cell's shorter side in the plane at points of it."""
        ll = self.lonlat(xy)
        dlon = math.radians(float(self.grid.x[1] - self.grid.x[0]))
        dlat = math.radians(float(self.grid.y[1] - self.grid.y[0]))
        side = EARTH_RADIUS * np.minimum(dlat, dlon * np.cos(np.radians(ll[:, 1])))
        return side * stereographic_scale(ll[:, 0], ll[:, 1], self.pole)

    def _near(self, cells: NDArray[np.float64], corners: int) -> NDArray[np.bool_]:
        """Which cells (rows of Gmsh's list format) to give Gmsh.

        Those with finite corners and values, not wholly beyond :attr:`reach`:
        a cell's nearest point to the centre is at least its nearest corner's
        distance less its longest side.
        """
        ok: NDArray[np.bool_] = np.all(np.isfinite(cells), axis=1)  # stub: Any
        if math.isinf(self.reach):
            return ok
        x, y = cells[:, :corners], cells[:, corners : 2 * corners]
        with np.errstate(invalid="ignore"):
            r = np.hypot(x, y).min(axis=1)
            side = np.hypot(np.diff(x, append=x[:, :1]), np.diff(y, append=y[:, :1]))
            near: NDArray[np.bool_] = r - side.max(axis=1) <= self.reach  # Any
            return ok & near

    def cells(
        self, polygon: shapely.Polygon, threads: int = 1
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """Grid nodes in ``polygon`` (plane), and the sphere area each stands for.

        Returns the nodes' plane x and y and, per node, the area of its cell on
        the sphere divided by its size squared (the triangle density's weight).
        The nodes are found on ``threads`` threads.
        """
        x, y, v = self.grid.x, self.grid.y, self.grid.values
        px, py = _plane_nodes(x, y, self.pole)
        # the nodes in the polygon's box first: the cuts ask for each part
        # they try, most of them a small share of the world's 1 M nodes
        x0, y0, x1, y1 = polygon.bounds
        inside = (px >= x0) & (px <= x1) & (py >= y0) & (py <= y1)
        at = np.flatnonzero(inside)
        inside.ravel()[at] = points_inside(
            polygon, px.ravel()[at], py.ravel()[at], threads
        )
        dlon = math.radians(float(x[1] - x[0]))
        dlat = math.radians(float(y[1] - y[0]))
        row = EARTH_RADIUS**2 * dlon * dlat * np.cos(np.radians(y))
        area = np.broadcast_to(row[:, None], px.shape)
        return px[inside], py[inside], area[inside] / v[:, :-1][inside] ** 2


def _meets(
    xy: list[tuple[NDArray[np.float64], NDArray[np.float64]]],
    bounds: tuple[float, ...],
) -> NDArray[np.bool_]:
    """Return which cells, by their corners' plane x and y, meet ``bounds``."""
    keep = np.ones(len(xy[0][0]), dtype=bool)
    for k, low, high in ((0, bounds[0], bounds[2]), (1, bounds[1], bounds[3])):
        at = [corner[k] for corner in xy]
        with np.errstate(invalid="ignore"):
            keep &= np.maximum.reduce(at) >= low
            keep &= np.minimum.reduce(at) <= high
    return keep


#: The last grid's nodes in the plane: (x, y, pole, px, py). The cuts ask
#: for :meth:`SphereSizeGrid.cells` of every part they try (15 on world.toml,
#: 0.14 s each to project the world grid).
_LAST_NODES: list[
    tuple[
        NDArray[np.float64],
        NDArray[np.float64],
        tuple[float, float],
        NDArray[np.float64],
        NDArray[np.float64],
    ]
] = []


def _plane_nodes(
    x: NDArray[np.float64], y: NDArray[np.float64], pole: tuple[float, float]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Return the plane x and y of the grid nodes (the wrapped column once)."""
    for lon, lat, at, px, py in _LAST_NODES:
        if lon is x and lat is y and at == pole:
            return px, py
    glon, glat = np.meshgrid(x[:-1], y)
    px, py = transformer(_LONLAT, plane_crs(pole)).transform(glon, glat)
    _LAST_NODES[:] = [(x, y, pole, px, py)]
    return px, py
