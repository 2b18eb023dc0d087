"""The grid a size field lives on: :class:`PlaneGrid` and :class:`SphereGrid`.

A grid is a value: its nodes (``x``, ``y``), its CRS, its spacing, which nodes
lie in the sea (``sea``), and the scale factor of the map at each node
(``scale``). Each size term computes on the grid it is given and never asks
which kind it is: the grid measures distances to lines (:meth:`graded`),
samples any raster (:meth:`sample`; the depth is one way of reading it) and
limits the field's gradation (:meth:`limit`) in its own way.

* :class:`PlaneGrid`: regular in the projected, conformal CRS a regional domain
  is meshed in, every ``spacing`` metres, two cells beyond the domain.
* :class:`SphereGrid`: a longitude/latitude grid of the whole world, whose last
  column is its first (longitude -180 and 180), for a global case.

The sea mask and the scale factors are measured the first time they are asked
for (a term that needs neither costs nothing for them), and once.
"""

from __future__ import annotations

import math
import threading
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, ClassVar, TypeVar

import numpy as np
import shapely
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.depth import (
    READINGS,
    DepthSources,
    depth_on_grid,
    raster_at,
    raster_crs,
    raster_on_grid,
)
from coastmesh.errors import ConfigError
from coastmesh.geometry.earth import (
    EARTH_RADIUS,
    METRES_PER_DEGREE,
    densified,
    reproject,
    reproject_points,
    transformer,
)
from coastmesh.geometry.projection import scale_factor
from coastmesh.geometry.sphere import stereographic_scale
from coastmesh.sizing.bands import BandRunner, graded_sizes
from coastmesh.sizing.bathymetry import slope_size, slope_size_sphere
from coastmesh.sizing.channel import RADIUS_STEP, domain_width, over_land
from coastmesh.sizing.gradation import Gradation, gradation_size, limit_gradation
from coastmesh.sizing.narrow import narrow_channels
from coastmesh.sizing.sphere import limit_gradation_sphere, sphere_distance, wrapped
from coastmesh.sizing.sphere_channel import (
    sphere_narrow_channels,
    sphere_over_land,
    sphere_water_mask,
    sphere_width,
)
from coastmesh.types import Domain

if TYPE_CHECKING:
    import xarray as xr

__all__ = [
    "CELLS_ACROSS",
    "PAD_CELLS",
    "SAMPLINGS",
    "Grid",
    "PlaneGrid",
    "SphereGrid",
    "grid_axes",
]

#: The default spacing of a plane grid, and the densification of the domain's
#: outline before it is projected, are the domain's extent over this.
CELLS_ACROSS = 1000
#: A plane grid extends this many cells beyond the domain on every side.
PAD_CELLS = 2
_LONLAT = CRS.from_epsg(4326)
_T = TypeVar("_T")
#: How :meth:`Grid.sample` reads a raster at the nodes: between the cell
#: centres (:data:`~coastmesh.depth.READINGS`), or as a mesh's nodes get depth.
SAMPLINGS = (*READINGS, "depth")


def grid_axes(
    bounds: tuple[float, float, float, float], cell: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Return the node coordinates ``x``, ``y`` of a grid covering ``bounds``.

    From the lower-left corner of ``bounds`` every ``cell``, until the nodes
    cover them.

    Examples
    --------
    >>> x, y = grid_axes((0.0, 0.0, 250.0, 100.0), 100.0)
    >>> x.tolist(), y.tolist()
    ([0.0, 100.0, 200.0, 300.0], [0.0, 100.0])
    """
    minx, miny, maxx, maxy = (float(v) for v in bounds)
    nx = int(np.ceil((maxx - minx) / cell)) + 1
    ny = int(np.ceil((maxy - miny) / cell)) + 1
    return (
        minx + cell * np.arange(nx, dtype=np.float64),
        miny + cell * np.arange(ny, dtype=np.float64),
    )


class Grid:
    """The nodes of a size field and what terms measure on them (a base class).

    Attributes
    ----------
    x, y : ndarray
        The nodes' coordinates in ``crs``, ascending.
    crs : pyproj.CRS
        The CRS of the nodes.
    spacing : float
        The spacing asked for, in ``crs`` units (metres in a plane, degrees on
        the sphere): the unit of the gradation limit.
    cell : float
        The spacing as the nodes lie, ``x[1] - x[0]`` (floating point may put
        it a hair off ``spacing``): what the terms measure widths and areas in.
    cell_m : float
        The spacing in metres on the Earth, for reports.
    domain : Domain or None
        The domain whose sea :attr:`sea` is.
    """

    x: NDArray[np.float64]
    y: NDArray[np.float64]
    crs: CRS
    spacing: float
    domain: Domain | None

    def __init__(self) -> None:
        self._lock = threading.Lock()

    @property
    def shape(self) -> tuple[int, int]:
        """``(ny, nx)``: the nodes in rows of equal y."""
        return (len(self.y), len(self.x))

    @property
    def cell(self) -> float:
        """The nodes' spacing as they lie, ``x[1] - x[0]``."""
        return float(self.x[1] - self.x[0])

    @property
    def cell_m(self) -> float:
        """The spacing in metres, for reports."""
        return self.cell

    @property
    def sea(self) -> NDArray[np.bool_]:
        """The nodes inside the domain (measured once)."""
        return self._once("sea", self._sea)

    @property
    def scale(self) -> NDArray[np.float64]:
        """The map scale factor at the nodes: a length of ``h`` m is ``k h`` there."""
        return self._once("scale", self._scale)

    def _once(self, name: str, measure: Callable[[], _T]) -> _T:
        """Measure a property once, also when several threads ask at once."""
        with self._lock:
            if name not in self.__dict__:
                self.__dict__[name] = measure()
            value: _T = self.__dict__[name]  # what ``measure`` returned
            return value

    def nodes_as(self, crs: CRS) -> NDArray[np.float64]:
        """Return the nodes moved into ``crs``, shape ``(ny * nx, 2)``, row by row.

        Moved once for each CRS however many terms ask (a raster's window, then
        its values at the nodes).
        """

        def moved() -> NDArray[np.float64]:
            xx, yy = np.meshgrid(self.x, self.y)
            nodes = np.column_stack([xx.ravel(), yy.ravel()])
            return reproject_points(nodes, self.crs, crs)

        return self._once(f"nodes in {crs.to_wkt()}", moved)

    def km2(self, nodes: NDArray[np.bool_]) -> float:
        """Return the area the ``nodes`` stand for, km2 (a cell each)."""
        return float(nodes.sum()) * self.cell * self.cell / 1e6

    def widths(
        self,
        domain: Domain,
        *,
        max_width: float,
        step: float | None = None,
        narrow_only: bool = False,
    ) -> NDArray[np.float64] | None:
        """Return the width of the domain's water at the nodes, metres.

        None where the grid does not measure it. ``step``: the ratio of the
        radii measured (:func:`~.channel.local_width`); ``narrow_only``: only
        where narrower than ``max_width`` (:func:`~.channel.narrow_width`).
        """
        return None

    @property
    def areas(self) -> NDArray[np.float64] | None:
        """The area each node stands for, m2; None where all stand for one area."""
        return None

    #: The key of the case that closes water too narrow for this grid before
    #: the size field (a global case's ``[domain] close``), named in the
    #: advice on narrow channels left; None: no key does.
    narrow_closed_by: ClassVar[str | None] = None

    def nodes_in(self, area: shapely.Geometry) -> NDArray[np.bool_] | None:
        """Return the nodes inside ``area`` (a geometry in :attr:`crs`).

        None where the grid does not place areas (a sphere grid: global cases
        have no sites yet).
        """
        return None

    def slope_size(
        self, depth: NDArray[np.float64], *, per_slope: float, min_depth: float
    ) -> NDArray[np.float64]:
        """Return the bathymetric slope term at the nodes, metres."""
        raise NotImplementedError

    def narrow_channels(
        self, width: NDArray[np.float64], inside: NDArray[np.bool_], *, h_min: float
    ) -> tuple[NDArray[np.int32], list[tuple[int, int, float, float]]]:
        """Label the water narrower than two elements of ``h_min`` (its ``width``)."""
        raise NotImplementedError

    def over_land(
        self, values: NDArray[np.float64], water: NDArray[np.bool_]
    ) -> NDArray[np.float64]:
        """Return ``values`` with each land node given its nearest water node's."""
        raise NotImplementedError

    def graded(
        self,
        gradations: list[Gradation],
        *,
        lines_crs: CRS,
        h_max: float,
        runner: BandRunner | None = None,
    ) -> NDArray[np.float64]:
        """Return the gradations' sizes, combined by minimum (metres)."""
        raise NotImplementedError

    def sample(
        self,
        raster: xr.DataArray | DepthSources,
        how: str = "bilinear",
        *,
        positive: str = "up",
    ) -> NDArray[np.float64]:
        """Return a raster's values at the grid's nodes, read as ``how`` says.

        The raster is read in its own CRS (any CRS: the nodes are moved into
        it), and a world lon/lat raster wraps round the antimeridian on a
        :class:`SphereGrid`.

        Parameters
        ----------
        raster : xarray.DataArray or DepthSources
            Dims ``("y", "x")`` with cell-centre coordinates and a ``crs``
            attribute (:func:`coastmesh.io.read_raster`). A stack of depth
            rasters (:class:`~coastmesh.depth.DepthSources`) with ``"depth"``.
        how : {"bilinear", "nearest", "depth"}
            ``"bilinear"`` between the four cell centres around a node;
            ``"nearest"`` the value of the cell the node is in (classes and
            codes); ``"depth"`` the depth as the mesh's nodes get it, metres
            positive down: bilinear over the wet cells alone, and a node of the
            domain's sea with no wet cell around takes the nearest wet cell, so
            a size term never reads a land height in the sea
            (:func:`~coastmesh.depth.depth_on_grid` with ``sea``).
        positive : {"up", "down"}
            With ``"depth"``: the raster's sign (``"up"`` for elevations).

        Returns
        -------
        ndarray of shape :attr:`shape`
            NaN outside the raster and at missing cells.

        Raises
        ------
        ConfigError
            For another ``how``, or a raster without dims, CRS or monotonic
            axes.
        """
        if how not in SAMPLINGS:
            raise ConfigError(f"how = {how!r}: use one of {', '.join(SAMPLINGS)}")
        if how != "depth" and isinstance(raster, DepthSources):
            raise ConfigError(
                f"how = {how!r} reads one raster; a stack of depth sources is read "
                'with how = "depth"'
            )
        return self._sample(raster, how, positive)

    def depth(
        self, raster: xr.DataArray | DepthSources, positive: str = "up"
    ) -> NDArray[np.float64]:
        """Return a raster's depth at the nodes, metres, positive down.

        :meth:`sample` with ``how = "depth"``: as the mesh's nodes will get it.
        """
        return self.sample(raster, "depth", positive=positive)

    def limit(self, values: NDArray[np.float64], rate: float) -> NDArray[np.float64]:
        """Return ``values`` with no step growing faster than ``rate`` m per m."""
        raise NotImplementedError

    def neighbour_min(
        self, values: NDArray[np.float64], cells: int = 1
    ) -> NDArray[np.float64]:
        """Return each node's smallest value over the nodes within ``cells``.

        The nodes within ``cells`` columns and rows (8 neighbours for 1). Gmsh
        reads the size grid bilinearly in each cell, so a size set at some nodes
        holds everywhere in a cell only once all four of its corners have it: a
        size term spread by one cell holds in every cell its field reaches, and
        by more, at the nodes of the elements there too.
        """
        from scipy import ndimage

        return np.asarray(
            ndimage.minimum_filter(values, size=2 * cells + 1, mode="nearest"),
            dtype=np.float64,
        )

    def field(self, values: NDArray[np.float64], history: str) -> xr.DataArray:
        """Return sizes on the grid as a DataArray (dims ``("y", "x")``, metres)."""
        import xarray as xr

        return xr.DataArray(
            values,
            dims=("y", "x"),
            coords={"y": self.y, "x": self.x},
            name="size",
            attrs={"crs": self.crs.to_wkt(), "units": "m", "history": history},
        )

    def _sample(
        self, raster: xr.DataArray | DepthSources, how: str, positive: str
    ) -> NDArray[np.float64]:
        raise NotImplementedError

    def _sea(self) -> NDArray[np.bool_]:
        raise NotImplementedError

    def _scale(self) -> NDArray[np.float64]:
        raise NotImplementedError


class PlaneGrid(Grid):
    """A size grid regular in a projected CRS: nodes every ``spacing`` metres.

    Parameters
    ----------
    x, y : ndarray
        Node coordinates in ``crs``, ascending, ``spacing`` apart.
    crs : pyproj.CRS or CRS-like
        A projected CRS in metres: the conformal CRS the mesh is made in.
    spacing : float
        The spacing, metres.
    domain : Domain, optional
        The domain meshed (for :attr:`sea`).
    threads : int
        Threads for the scale factors.

    Raises
    ------
    ConfigError
        If ``crs`` is not projected, or the spacing is not > 0.

    Examples
    --------
    >>> g = PlaneGrid.from_bounds((0.0, 0.0, 1000.0, 500.0), 250.0, "EPSG:32630")
    >>> g.shape, g.cell
    ((3, 5), 250.0)
    """

    def __init__(
        self,
        x: NDArray[np.float64],
        y: NDArray[np.float64],
        crs: Any,
        spacing: float,
        domain: Domain | None = None,
        *,
        threads: int = 1,
    ) -> None:
        super().__init__()
        self.crs = CRS.from_user_input(crs)
        if not self.crs.is_projected:
            raise ConfigError(
                f"size grid: crs {self.crs.name!r} is not projected; mesh in metres"
            )
        if not spacing > 0:
            raise ConfigError(f"cell = {spacing}: must be > 0 metres")
        self.x, self.y, self.spacing = x, y, float(spacing)
        self.domain, self.threads = domain, threads

    @classmethod
    def from_bounds(
        cls, bounds: tuple[float, float, float, float], spacing: float, crs: Any
    ) -> PlaneGrid:
        """Return the grid whose nodes cover ``bounds`` (in ``crs``)."""
        minx, miny, maxx, maxy = (float(v) for v in bounds)
        if not (maxx > minx and maxy > miny):
            raise ConfigError(f"bounds = {bounds}: need minx < maxx and miny < maxy")
        if not spacing > 0:
            raise ConfigError(f"cell = {spacing}: must be > 0 metres")
        return cls(*grid_axes((minx, miny, maxx, maxy), spacing), crs, spacing)

    @classmethod
    def around(
        cls,
        domain: Domain,
        crs: Any,
        *,
        spacing: float | None,
        smallest: float,
        threads: int = 1,
    ) -> PlaneGrid:
        """Return the grid of a domain's size field, in ``crs``.

        It covers the domain with :data:`PAD_CELLS` cells to spare. The spacing
        is ``spacing``, else the extent over :data:`CELLS_ACROSS`, but not below
        ``smallest`` (metres: the smallest size asked for).
        """
        crs = CRS.from_user_input(crs)
        step = _extent(domain.polygon.bounds) / CELLS_ACROSS
        outline = reproject(
            shapely.segmentize(domain.polygon.exterior, step), domain.crs, crs
        )
        minx, miny, maxx, maxy = outline.bounds
        if spacing is None:
            spacing = max(_extent((minx, miny, maxx, maxy)) / CELLS_ACROSS, smallest)
        pad = PAD_CELLS * spacing
        bounds = (minx - pad, miny - pad, maxx + pad, maxy + pad)
        x, y = grid_axes(bounds, spacing)
        return cls(x, y, crs, spacing, domain, threads=threads)

    def graded(
        self,
        gradations: list[Gradation],
        *,
        lines_crs: CRS,
        h_max: float,
        runner: BandRunner | None = None,
    ) -> NDArray[np.float64]:
        """Return the gradations' sizes: distances in bands of rows on ``runner``.

        The lines are reprojected from ``lines_crs`` to the grid's CRS.
        """
        _check_h_max(gradations, h_max)
        graded = [
            Gradation(
                reproject(g.lines, lines_crs, self.crs),
                g.h_min,
                g.d_hold,
                g.d_grade,
                g.name,
            )
            for g in gradations
        ]
        return graded_sizes(
            self.x,
            self.y,
            graded,
            crs=self.crs,
            h_max=h_max,
            resolution=self.spacing / 4,
            runner=runner,
        )

    def widths(
        self,
        domain: Domain,
        *,
        max_width: float,
        step: float | None = None,
        narrow_only: bool = False,
    ) -> NDArray[np.float64]:
        """Return the width of the water (:func:`~.channel.domain_width`)."""
        if step is None:
            step = RADIUS_STEP
        return domain_width(
            self, domain, max_width=max_width, step=step, narrow_only=narrow_only
        )

    def _sample(
        self, raster: xr.DataArray | DepthSources, how: str, positive: str
    ) -> NDArray[np.float64]:
        """Read ``raster`` at the nodes, in the raster's own CRS."""
        if how == "depth":
            return depth_on_grid(
                raster, self.x, self.y, crs=self.crs, positive=positive, sea=self.sea
            )
        assert not isinstance(raster, DepthSources)  # sample() refuses it
        crs = raster_crs(raster)  # the cells are read once, by raster_at
        values = raster_at(raster, self.nodes_as(crs), crs, how=how)
        return values.reshape(self.shape)

    def limit(self, values: NDArray[np.float64], rate: float) -> NDArray[np.float64]:
        """Limit the gradation in 8 directions, ``spacing`` apart."""
        return limit_gradation(values, (self.spacing, self.spacing), rate)

    def slope_size(
        self, depth: NDArray[np.float64], *, per_slope: float, min_depth: float
    ) -> NDArray[np.float64]:
        """Return the slope term, the gradient ``cell`` apart (:func:`.slope_size`)."""
        return slope_size(
            depth, (self.cell, self.cell), per_slope=per_slope, min_depth=min_depth
        )

    def narrow_channels(
        self, width: NDArray[np.float64], inside: NDArray[np.bool_], *, h_min: float
    ) -> tuple[NDArray[np.int32], list[tuple[int, int, float, float]]]:
        """Label the narrow water, in cells of ``cell`` (:func:`.narrow_channels`)."""
        return narrow_channels(width, inside, h_min=h_min, cell=self.cell)

    def over_land(
        self, values: NDArray[np.float64], water: NDArray[np.bool_]
    ) -> NDArray[np.float64]:
        """Give land nodes the nearest water node's value (:func:`.over_land`)."""
        return over_land(values, water)

    def nodes_in(self, area: shapely.Geometry) -> NDArray[np.bool_]:
        """Return the nodes inside ``area`` (a geometry in :attr:`crs`)."""
        shapely.prepare(area)
        xx, yy = np.meshgrid(self.x, self.y)
        # shapely is untyped here (types-shapely is not among the dependencies)
        inside: NDArray[np.bool_] = shapely.contains_xy(area, xx, yy)
        return inside

    def _sea(self) -> NDArray[np.bool_]:
        if self.domain is None:
            return np.ones(self.shape, dtype=bool)
        polygon = densified(self.domain, [self.domain.polygon], self.crs)[0]
        shapely.prepare(polygon)
        xx, yy = np.meshgrid(self.x, self.y)
        # shapely is untyped here (types-shapely is not among the dependencies)
        sea: NDArray[np.bool_] = shapely.contains_xy(polygon, xx, yy)
        return sea

    def _scale(self) -> NDArray[np.float64]:
        gx, gy = np.meshgrid(self.x, self.y)
        return scale_factor(gx, gy, self.crs, threads=self.threads)


class SphereGrid(Grid):
    """A longitude/latitude grid of the world, for a global case's size field.

    ``x`` runs from -180 to 180 (the last column is the first meridian again)
    and ``y`` from ``south`` to the North Pole, ``spacing`` degrees apart (360
    and ``90 - south`` rounded to whole numbers of cells). Sizes are lengths on
    the sphere; the domain and lines are in the stereographic plane ``plane``
    whose singular point is ``pole``.

    Examples
    --------
    >>> g = SphereGrid(2.0, south=-80.0)
    >>> g.shape, float(g.x[0]), float(g.x[-1]), g.cell_m > 2e5
    ((86, 181), -180.0, 180.0, True)
    """

    #: Water narrower than the grid sees is closed by the case before
    #: (:meth:`narrow_channels`).
    narrow_closed_by = "[domain] close"

    def __init__(
        self,
        spacing: float,
        *,
        south: float = -90.0,
        domain: Domain | None = None,
        pole: tuple[float, float] = (0.0, -90.0),
    ) -> None:
        super().__init__()
        if not spacing > 0:
            raise ConfigError(f"cell = {spacing}: must be > 0 degrees")
        if not -90.0 <= south < 90.0:
            raise ConfigError(f"south = {south}: must be a latitude below 90")
        nx = max(round(360.0 / spacing), 4)
        ny = max(round((90.0 - south) / spacing), 2)
        self.x = np.linspace(-180.0, 180.0, nx + 1)
        self.y = np.linspace(south, 90.0, ny + 1)
        self.crs, self.spacing = _LONLAT, float(spacing)
        self.domain, self.pole = domain, pole

    @property
    def cell(self) -> float:
        """The spacing asked for, degrees (the grid's axes are ``linspace``)."""
        return self.spacing

    @property
    def cell_m(self) -> float:
        """The spacing in metres of great-circle arc."""
        return self.spacing * METRES_PER_DEGREE

    def km2(self, nodes: NDArray[np.bool_]) -> float:
        """Return the area on the sphere the ``nodes`` stand for, km2."""
        cell = math.radians(self.spacing)
        area = (EARTH_RADIUS * cell) ** 2 * np.cos(np.radians(self.y))[:, None]
        return float((area * nodes)[:, :-1].sum()) / 1e6

    def graded(
        self,
        gradations: list[Gradation],
        *,
        lines_crs: CRS,
        h_max: float,
        runner: BandRunner | None = None,
    ) -> NDArray[np.float64]:
        """Return the gradations' sizes by great-circle distance from the lines."""
        _check_h_max(gradations, h_max)
        size = np.full(self.shape, float(h_max))
        nx = len(self.x) - 1
        resolution = min(math.radians(360.0 / nx) * EARTH_RADIUS / 4, 5_000.0)
        for g in gradations:
            lines = np.asarray(g.lines, dtype=object)
            if len(lines) == 0 or shapely.is_empty(lines).all():
                continue
            distance = sphere_distance(
                lines, lines_crs, self.x[:-1], self.y, resolution, g.d_hold + g.d_grade
            )  # the last column is the first meridian again
            graded = gradation_size(distance, g.h_min, h_max, g.d_hold, g.d_grade)
            np.minimum(size, np.hstack([graded, graded[:, :1]]), out=size)
        return size

    def _sample(
        self, raster: xr.DataArray | DepthSources, how: str, positive: str
    ) -> NDArray[np.float64]:
        """Read ``raster`` on the nodes; a world raster wraps round.

        The first column is read once and repeated as the last (-180 and 180
        are one meridian). With ``"depth"``, a node in the domain's sea with no
        wet cell around (an island the case drops, which the raster still has)
        takes the nearest wet cell.
        """
        x, sea = self.x[:-1], self.sea[:, :-1]
        if isinstance(raster, DepthSources):  # how == "depth": sample() says so
            values = depth_on_grid(raster, x, self.y, crs=_LONLAT, sea=sea)
        elif how == "depth":
            values = depth_on_grid(
                wrapped(raster), x, self.y, crs=_LONLAT, positive=positive, sea=sea
            )
        else:
            values = raster_on_grid(wrapped(raster), x, self.y, crs=_LONLAT, how=how)
        return np.hstack([values, values[:, :1]])

    def limit(self, values: NDArray[np.float64], rate: float) -> NDArray[np.float64]:
        """Limit the gradation with each step's true length on the sphere."""
        return limit_gradation_sphere(values, self.y, rate)

    def neighbour_min(
        self, values: NDArray[np.float64], cells: int = 1
    ) -> NDArray[np.float64]:
        """Return each node's smallest value over the nodes within ``cells``.

        Across the antimeridian too: the last column is the first one's meridian.
        """
        from scipy import ndimage

        spread = ndimage.minimum_filter(
            values[:, :-1], size=2 * cells + 1, mode=("nearest", "wrap")
        )
        return np.hstack([spread, spread[:, :1]]).astype(np.float64)

    @property
    def areas(self) -> NDArray[np.float64]:
        """The area on the sphere each node stands for, m2 (0 on the last column).

        ``R^2 dlon dlat cos(lat)``; the last column is the first meridian again,
        and stands for nothing of its own.
        """
        dlon = math.radians(float(self.x[1] - self.x[0]))
        dlat = math.radians(float(self.y[1] - self.y[0]))
        row = EARTH_RADIUS**2 * dlon * dlat * np.cos(np.radians(self.y))
        areas = np.repeat(np.maximum(row, 0.0)[:, None], len(self.x), axis=1)
        areas[:, -1] = 0.0
        return areas

    def widths(
        self,
        domain: Domain,
        *,
        max_width: float,
        step: float | None = None,
        narrow_only: bool = False,
    ) -> NDArray[np.float64]:
        """Return the width of the water by great-circle distance (metres).

        :func:`~.sphere_channel.sphere_width` over the sea, and past the open
        boundaries (``[[cuts]]``) where nearer them than a shoreline.

        Raises
        ------
        ConfigError
            With ``narrow_only``: a global case closes narrow water with
            ``[domain] close``, not on this grid.
        """
        if narrow_only:
            raise ConfigError(
                "narrow_only: a global case closes narrow water with [domain] close"
            )
        water = self.sea
        if any(s.kind == "open" for s in domain.segments):
            shore, opened = self._line_points(domain)
            water = sphere_water_mask(water, self.y, shore, opened)
        return sphere_width(
            water,
            self.y,
            max_width=max_width,
            step=RADIUS_STEP if step is None else step,
        )

    def slope_size(
        self, depth: NDArray[np.float64], *, per_slope: float, min_depth: float
    ) -> NDArray[np.float64]:
        """Return the slope term from the sea's depths, each step's true length.

        :func:`~.bathymetry.slope_size_sphere` with :attr:`sea`: no node of the
        sea takes a slope from a land node.
        """
        return slope_size_sphere(
            depth, self.y, per_slope=per_slope, min_depth=min_depth, sea=self.sea
        )

    def narrow_channels(
        self, width: NDArray[np.float64], inside: NDArray[np.bool_], *, h_min: float
    ) -> tuple[NDArray[np.int32], list[tuple[int, int, float, float]]]:
        """Label the water narrow for sure: even a cell wider, on the sphere.

        Widths on the grid err narrow by up to a cell (:attr:`cell_m`, the
        north-south step), so a stretch counts only if it is narrower than two
        elements of ``h_min`` by more than that: on a grid coarser than
        ``2 h_min`` none does (a global case's ``[domain] close`` closes narrow
        water). Joined across the antimeridian, areas on the sphere
        (:func:`~.sphere_channel.sphere_narrow_channels`).
        """
        return sphere_narrow_channels(
            width, inside, self.y, h_min=h_min, margin=self.cell_m
        )

    def over_land(
        self, values: NDArray[np.float64], water: NDArray[np.bool_]
    ) -> NDArray[np.float64]:
        """Give land nodes the value of the nearest water node on the sphere.

        Within four cells (``4 cell_m``) of the water; farther inland, where no
        mesh is made, ``inf`` (:func:`~.sphere_channel.sphere_over_land`).
        """
        return sphere_over_land(values, water, self.y, reach=4 * self.cell_m)

    def _line_points(
        self, domain: Domain
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Points along the shorelines and open boundaries, lon/lat, < a cell apart.

        Densified in the domain's CRS: a third of a cell there is at most that
        on the Earth (the stereographic plane's scale is at least 1).
        """
        step = self.cell_m / 3 if domain.crs.is_projected else self.spacing / 3
        out = []
        for kind in ("shoreline", "open"):
            lines = [
                shapely.LineString(s.coords) for s in domain.segments if s.kind == kind
            ]
            xy = shapely.get_coordinates(shapely.segmentize(lines, step))
            out.append(reproject_points(xy, domain.crs, _LONLAT) if len(xy) else xy)
        return out[0], out[1]

    def _sea(self) -> NDArray[np.bool_]:
        if self.domain is None:
            return np.ones(self.shape, dtype=bool)
        glon, glat = np.meshgrid(self.x, self.y)
        with np.errstate(all="ignore"):  # the pole of the plane goes to infinity
            px, py = transformer(_LONLAT, self.domain.crs).transform(glon, glat)
        polygon = self.domain.polygon
        shapely.prepare(polygon)
        # shapely is untyped here (types-shapely is not among the dependencies)
        sea: NDArray[np.bool_] = shapely.contains_xy(polygon, px, py)
        return sea

    def _scale(self) -> NDArray[np.float64]:
        glon, glat = np.meshgrid(self.x, self.y)
        return stereographic_scale(glon, glat, self.pole)


def _extent(bounds: tuple[float, ...]) -> float:
    minx, miny, maxx, maxy = bounds
    return max(maxx - minx, maxy - miny)


def _check_h_max(gradations: list[Gradation], h_max: float) -> None:
    for g in gradations:
        if g.h_min > h_max:
            raise ConfigError(
                f"gradation {g.name!r}: h_min = {g.h_min} > h_max = {h_max}"
            )
