"""Bathymetry from several rasters: priority, coverage and blending.

Sources are listed in priority order, highest first. A point takes the
highest-priority source that has a valid value there: bilinear between valid
cell centres, inside the source's region. Near the edge of a source's valid
data its weight ramps to the sources below it::

    t = clip((d - delta) / (blend - delta), 0, 1),   w = 3 t^2 - 2 t^3
    depth = w * own + (1 - w) * below

where ``d`` is the distance on the Earth to the source's nearest edge cell and
``delta`` half its cell size. An edge cell is a valid cell next to a missing one
or on the frame of the raster, so ``w`` is 0 wherever the bilinear value ends:
the depth has no step at the seam, and beyond ``blend`` from the edge it is the
source's own bilinear value. Where nothing lies below, the source counts fully.

Points no source covers, but within one cell diagonal of a source's valid cell,
take that nearest cell's value (``snapped``): the half cell beyond the outer
cell centres. Others are ``uncovered``; the caller decides whether that is an
error (:func:`coastmesh.depth.depth_at_nodes`).

Distances are chords between earth-centred points, to the edge cells only: the
nearest valid (or wet) cell to a point outside the valid (wet) data is always an
edge cell, so the k-d trees stay small even for GEBCO-size windows.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray
from pyproj import CRS
from scipy.ndimage import binary_erosion
from scipy.spatial import cKDTree

from coastmesh.depth.raster import interpolate_wet, raster_grid
from coastmesh.errors import ConfigError, InputDataError
from coastmesh.geometry.earth import (
    METRES_PER_DEGREE,
    earth_centred,
    metres_per_unit,
    reproject_points,
)
from coastmesh.geometry.grids import interpolate_bilinear

if TYPE_CHECKING:
    import xarray as xr

__all__ = ["DepthSource", "DepthSources", "SourceSample"]


@dataclass(frozen=True, slots=True)
class DepthSource:
    """One bathymetry raster of a stack.

    Parameters
    ----------
    raster : xarray.DataArray
        Dims ``("y", "x")``, cell-centre coordinates, a ``crs`` attr, NaN for
        nodata (as :func:`coastmesh.io.read_raster` returns).
    positive : {"up", "down"}
        The raster's sign: ``"up"`` for elevations (GEBCO, ETOPO).
    blend : float
        Metres inside the edge of the valid data over which the source's weight
        ramps up from 0; 0 for a hard seam.
    name : str
        How messages and reports name it (the file, say).
    """

    raster: xr.DataArray
    positive: str = "up"
    blend: float = 0.0
    name: str = ""

    def __post_init__(self) -> None:
        label = self.name or str(self.raster.attrs.get("source", "raster"))
        object.__setattr__(self, "name", label)
        if self.positive not in ("up", "down"):
            raise ConfigError(
                f"bathymetry source {label}: positive = {self.positive!r}: use "
                "'up' or 'down'"
            )
        if not (np.isfinite(self.blend) and self.blend >= 0):
            raise ConfigError(
                f"bathymetry source {label}: blend = {self.blend}: a distance >= 0 m"
            )
        if self.raster.attrs.get("crs") is None:
            raise no_crs(label)


def no_crs(label: str) -> InputDataError:
    """Return the error of a source raster with no CRS (checked before meshing too)."""
    return InputDataError(
        f"bathymetry source {label} has no CRS: give a raster with its "
        "coordinate reference system (e.g. a GeoTIFF with EPSG)"
    )


def check_blend(label: str, blend: float, width: float, height: float) -> None:
    """Raise ConfigError if ``blend`` is at least half the source's extent (metres).

    Then no node would take the source's own depth. Checked before meshing
    (from the file's bounds) and again on the cells read.
    """
    if blend > 0 and blend >= 0.5 * min(width, height):
        raise ConfigError(
            f"bathymetry source {label}: blend = {blend / 1e3:g} km is at least "
            f"half the source's extent ({width / 1e3:.3g} x {height / 1e3:.3g} "
            "km): no node would take its own depth; use a smaller blend"
        )


@dataclass(frozen=True, slots=True)
class SourceSample:
    """Depths sampled from a :class:`DepthSources` stack.

    Attributes
    ----------
    depth : ndarray of shape (N,)
        Metres, positive down; NaN where ``source`` is -1.
    source : ndarray of shape (N,) of int
        Index of the highest-priority source with a weight there; -1 if none.
    blended : ndarray of bool
        Points whose depth mixes a source with the ones below.
    snapped : ndarray of bool
        Points outside every source's bilinear cover but within a cell
        diagonal of one, given its nearest valid cell.
    averaged : ndarray of bool
        Points whose depth is a mean of cells (``radius``).
    hits : tuple of int
        Points covered by each source's own data (bilinear), before snapping.
    """

    depth: NDArray[np.float64]
    source: NDArray[np.int64]
    blended: NDArray[np.bool_]
    snapped: NDArray[np.bool_]
    averaged: NDArray[np.bool_]
    hits: tuple[int, ...]

    @property
    def uncovered(self) -> NDArray[np.bool_]:
        """Points no source covers."""
        return self.source < 0


class _Prepared:
    """A source unpacked once: axes, depths positive down, edge trees (lazy)."""

    def __init__(self, source: DepthSource) -> None:
        self.name = source.name
        self.blend = float(source.blend)
        self.x, self.y, values, self.crs = raster_grid(source.raster)
        self.depth = -values if source.positive == "up" else values
        if not np.isfinite(self.depth).any():
            raise InputDataError(f"bathymetry source {self.name} has no valid cell")
        dx = abs(self.x[1] - self.x[0]) if len(self.x) > 1 else 0.0
        dy = abs(self.y[1] - self.y[0]) if len(self.y) > 1 else 0.0
        if self.crs.is_geographic:
            lat = float(np.min(np.abs(self.y)))
            dx_m = dx * METRES_PER_DEGREE * max(np.cos(np.radians(lat)), 1e-6)
            dy_m = dy * METRES_PER_DEGREE
            width = (
                (self.x[-1] - self.x[0])
                * METRES_PER_DEGREE
                * np.cos(np.radians(float(np.max(np.abs(self.y)))))
            )
            height = (self.y[-1] - self.y[0]) * METRES_PER_DEGREE
        else:
            unit = metres_per_unit(self.crs)
            dx_m, dy_m = dx * unit, dy * unit
            width = (self.x[-1] - self.x[0]) * unit
            height = (self.y[-1] - self.y[0]) * unit
        #: w is 0 within half a cell of an edge cell's centre: the bilinear edge
        self.delta = 0.5 * max(dx_m, dy_m)
        #: points this close to a valid cell count as covered (one cell diagonal)
        self.tolerance = float(np.hypot(dx_m, dy_m))
        check_blend(self.name, self.blend, width, height)
        self.blend = max(self.blend, self.delta) if self.blend > 0 else 0.0
        #: the ramp's width; a blend under half a cell is a step at the half cell
        self.ramp = max(self.blend - self.delta, 1e-6)
        self._trees: dict[str, tuple[cKDTree, NDArray[np.float64]] | None] = {}
        self._sums: dict[bool, tuple[NDArray[np.float64], NDArray[np.float64]]] = {}
        #: the cell size, metres: what the raster can tell apart
        self.cell_m = float(max(dx_m, dy_m))

    def values_at(
        self,
        points: NDArray[np.float64],
        crs: CRS,
        radius: NDArray[np.float64] | None,
        wet: bool = False,
    ) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
        """Bilinear values, or cell means where ``radius`` spans several cells.

        ``wet``: over the wet cells only (:func:`interpolate_wet`; 0 where
        every cell around is dry).
        """
        px, py = _reproject(points, crs, self.crs)
        interpolate = interpolate_wet if wet else interpolate_bilinear
        z = interpolate(self.x, self.y, self.depth, px, py)
        if radius is None:
            return z, np.zeros(len(z), dtype=bool)
        means, used = self._box_means(px, py, radius, wet)
        used &= np.isfinite(z)
        return np.where(used, means, z), used

    def _box_means(
        self,
        px: NDArray[np.float64],
        py: NDArray[np.float64],
        radius: NDArray[np.float64],
        wet: bool = False,
    ) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
        """Mean of the valid (wet) cells within ``radius`` of each point.

        By summed-area tables, one per kind of cell.
        """
        rx, ry, values = self.x, self.y, self.depth
        if len(rx) < 2 or len(ry) < 2:
            return np.full(len(px), np.nan), np.zeros(len(px), dtype=bool)
        dx, dy = rx[1] - rx[0], ry[1] - ry[0]
        half_x = half_y = radius / metres_per_unit(self.crs)
        if self.crs.is_geographic:  # a degree of longitude is shorter
            half_x = half_y / np.maximum(np.cos(np.radians(py)), 1e-6)
        kx = np.floor(np.nan_to_num(half_x / dx)).astype(np.int64)
        ky = np.floor(np.nan_to_num(half_y / dy)).astype(np.int64)
        used = (kx >= 1) | (ky >= 1)
        ci = np.rint(np.nan_to_num((px - rx[0]) / dx, nan=-1.0)).astype(np.int64)
        cj = np.rint(np.nan_to_num((py - ry[0]) / dy, nan=-1.0)).astype(np.int64)
        ny, nx = values.shape
        used &= (ci >= 0) & (ci < nx) & (cj >= 0) & (cj < ny)
        if wet not in self._sums:
            valid = np.isfinite(values)
            if wet:
                with np.errstate(invalid="ignore"):
                    valid &= values > 0
            sums = np.zeros((ny + 1, nx + 1))
            sums[1:, 1:] = np.where(valid, values, 0.0).cumsum(0).cumsum(1)
            counts = np.zeros((ny + 1, nx + 1))
            counts[1:, 1:] = valid.cumsum(0).cumsum(1)
            self._sums[wet] = (sums, counts)
        sums, counts = self._sums[wet]
        i0, i1 = np.clip(ci - kx, 0, nx), np.clip(ci + kx + 1, 0, nx)
        j0, j1 = np.clip(cj - ky, 0, ny), np.clip(cj + ky + 1, 0, ny)

        def box(table: NDArray[np.float64]) -> NDArray[np.float64]:
            total: NDArray[np.float64] = (
                table[j1, i1] - table[j0, i1] - table[j1, i0] + table[j0, i0]
            )
            return total

        n = box(counts)
        with np.errstate(invalid="ignore", divide="ignore"):
            means = box(sums) / n
        return means, used & (n > 0)

    def tree(self, kind: str) -> tuple[cKDTree, NDArray[np.float64]] | None:
        """Return the k-d tree of the edge cells of the valid or the wet data."""
        if kind not in self._trees:
            valid = np.isfinite(self.depth)
            if kind == "wet":
                with np.errstate(invalid="ignore"):
                    valid &= self.depth > 0
            edge = valid & ~binary_erosion(
                valid, structure=np.ones((3, 3), bool), border_value=0
            )
            j, i = np.nonzero(edge)
            if j.size == 0:
                self._trees[kind] = None
            else:
                cells = np.column_stack([self.x[i], self.y[j]])
                xyz = earth_centred(cells, self.crs, name=f"{self.name} cells")
                self._trees[kind] = (cKDTree(xyz), self.depth[j, i])
        return self._trees[kind]


class DepthSources:
    """Several bathymetry rasters in priority order, sampled as one.

    Parameters
    ----------
    sources : sequence of DepthSource or xarray.DataArray
        Highest priority first; a bare DataArray is a source with
        ``positive="up"``.

    Raises
    ------
    ConfigError
        If there is no source, or a ``blend`` is at least half a source's
        extent.
    InputDataError
        If a source has no CRS or no valid cell.

    Examples
    --------
    >>> import xarray as xr
    >>> def grid(value, x0):
    ...     return xr.DataArray(np.full((3, 3), value), dims=("y", "x"),
    ...         coords={"y": [2.0, 1.0, 0.0], "x": [x0, x0 + 1, x0 + 2]},
    ...         attrs={"crs": "EPSG:4326"})
    >>> stack = DepthSources([DepthSource(grid(5.0, 0.0), "down", name="survey"),
    ...                       DepthSource(grid(-20.0, -1.0), "up", name="gebco")])
    >>> s = stack.sample([[0.5, 1.0], [-0.5, 1.0]], "EPSG:4326")
    >>> s.depth.tolist(), s.source.tolist()
    ([5.0, 20.0], [0, 1])
    """

    def __init__(self, sources: Sequence[DepthSource | xr.DataArray]) -> None:
        items = [s if isinstance(s, DepthSource) else DepthSource(s) for s in sources]
        if not items:
            raise ConfigError("no bathymetry source: give at least one raster")
        self.sources = tuple(items)
        self._prepared = [_Prepared(s) for s in items]

    @property
    def names(self) -> tuple[str, ...]:
        """The sources' names, in priority order."""
        return tuple(s.name for s in self.sources)

    def __len__(self) -> int:
        return len(self.sources)

    @property
    def cells_m(self) -> tuple[float, ...]:
        """Each source's cell size (the larger side), metres."""
        return tuple(p.cell_m for p in self._prepared)

    def sample(
        self,
        points: ArrayLike,
        crs: CRS | str,
        *,
        radius: ArrayLike | None = None,
        wet: bool = False,
    ) -> SourceSample:
        """Return the depth at ``points`` (in ``crs``) from the stack.

        ``radius`` (metres, one per point), if given, replaces a source's
        bilinear value by the mean of its valid cells within that distance
        wherever that spans more than one cell (``method="mean"``). ``wet``
        samples each source over its wet cells only (no land cell mixes into
        a depth; a point whose cells are all dry gets 0 from that source).
        """
        pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        crs = CRS.from_user_input(crs)
        n = len(pts)
        depth = np.full(n, np.nan)
        source = np.full(n, -1, dtype=np.int64)
        blended = np.zeros(n, dtype=bool)
        averaged = np.zeros(n, dtype=bool)
        hits = [0] * len(self)
        if radius is not None:
            radius = np.broadcast_to(np.asarray(radius, dtype=np.float64), (n,))
        xyz = None
        for k in range(len(self) - 1, -1, -1):
            prep = self._prepared[k]
            z, means = prep.values_at(pts, crs, radius, wet)
            ok = np.flatnonzero(np.isfinite(z))
            hits[k] = ok.size
            if ok.size == 0:
                continue
            w = np.ones(ok.size)
            below = depth[ok]
            under = np.isfinite(below)
            if prep.blend > 0 and under.any():
                if xyz is None:
                    xyz = _earth(pts, crs)
                d = _distance(prep.tree("valid"), xyz[ok[under]], prep.blend)
                t = np.clip((d - prep.delta) / prep.ramp, 0.0, 1.0)
                w[under] = t * t * (3.0 - 2.0 * t)
            mixed = z[ok] * w
            mixed[under] += (1.0 - w[under]) * below[under]
            depth[ok] = mixed
            took = w > 0
            source[ok[took]] = k
            blended[ok] = np.where(took, w < 1, blended[ok])
            averaged[ok] = np.where(took, means[ok], averaged[ok])
        snapped = self._snap(pts, crs, depth, source)
        return SourceSample(depth, source, blended, snapped, averaged, tuple(hits))

    def _snap(
        self,
        pts: NDArray[np.float64],
        crs: CRS,
        depth: NDArray[np.float64],
        source: NDArray[np.int64],
    ) -> NDArray[np.bool_]:
        """Give uncovered points within a cell diagonal of a source its cell."""
        snapped = np.zeros(len(pts), dtype=bool)
        for k, prep in enumerate(self._prepared):
            left = np.flatnonzero(source < 0)
            if left.size == 0:
                break
            tree = prep.tree("valid")
            if tree is None:
                continue
            d, i = tree[0].query(
                _earth(pts[left], crs), distance_upper_bound=prep.tolerance
            )
            near = np.isfinite(d)
            depth[left[near]] = tree[1][i[near]]
            source[left[near]] = k
            snapped[left[near]] = True
        return snapped

    def nearest(
        self, points: ArrayLike, crs: CRS | str, *, kind: str = "valid"
    ) -> tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.float64]]:
        """Return the nearest valid (or ``kind="wet"``) cell of any source.

        Returns the cell values (metres, positive down), the source of each and
        the distances (metres). Ties go to the higher-priority source; a point
        with no such cell anywhere gets NaN.
        """
        pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        xyz = _earth(pts, CRS.from_user_input(crs))
        best = np.full(len(pts), np.inf)
        value = np.full(len(pts), np.nan)
        which = np.full(len(pts), -1, dtype=np.int64)
        for k, prep in enumerate(self._prepared):
            tree = prep.tree(kind)
            if tree is None or len(pts) == 0:
                continue
            d, i = tree[0].query(xyz)
            closer = d < best
            best[closer], value[closer], which[closer] = (
                d[closer],
                tree[1][i[closer]],
                k,
            )
        return value, which, best

    def uncovered_message(
        self, sample: SourceSample, points: ArrayLike, crs: CRS | str
    ) -> str:
        """Say which points no source covers, where, and each source's share."""
        pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        gap = sample.uncovered
        lon, lat = reproject_points(pts[gap], crs, "EPSG:4326").T
        where = (
            f"lon {lon.min():.4f} to {lon.max():.4f}, lat {lat.min():.4f} to "
            f"{lat.max():.4f}"
        )
        shares = ", ".join(
            f"{name} covers {hit / len(pts):.1%}"
            for name, hit in zip(self.names, sample.hits, strict=True)
        )
        if len(self) == 1:
            head = f"the bathymetry raster {self.names[0]} leaves"
        else:
            head = "the bathymetry sources leave a gap:"
        return (
            f"{head} {gap.sum():,} of {len(pts):,} points ({gap.mean():.1%}) without "
            f"a depth, at {where} ({shares})"
        )


def _reproject(
    points: ArrayLike, src: CRS, dst: CRS
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Reproject, with points the target cannot hold as NaN (never covered)."""
    with np.errstate(invalid="ignore"):
        xy = reproject_points(points, src, dst)
    return xy[:, 0], xy[:, 1]


def _earth(points: NDArray[np.float64], crs: CRS) -> NDArray[np.float64]:
    return earth_centred(points, crs, name="bathymetry points")


def _distance(
    tree: tuple[cKDTree, NDArray[np.float64]] | None,
    xyz: NDArray[np.float64],
    upper: float,
) -> NDArray[np.float64]:
    """Distances to the nearest edge cell, capped at ``upper`` (inf beyond)."""
    if tree is None:
        return np.full(len(xyz), np.inf)
    # scipy is untyped here (no stubs among the dependencies)
    d: NDArray[np.float64]
    d, _ = tree[0].query(xyz, distance_upper_bound=upper)
    return d
