"""Size terms for hard coasts: channel width and the Courant number.

:class:`ChannelSize` asks for ``elements_across`` elements across every channel
(:mod:`coastmesh.sizing.channel` measures the width of the water on the size
grid); :class:`CourantSize` bounds the size so that the Courant number
``C = dt (sqrt(g d) + u) / h`` of a model run at time step ``dt`` stays between
``courant_min`` and ``courant_max``. :func:`coastmesh.sizing.domain_size_field`
combines them with the other terms; its docstring says which bound wins.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import shapely
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.depth.grid import depth_on_grid
from coastmesh.depth.sources import DepthSources
from coastmesh.errors import CoastmeshWarning
from coastmesh.geometry.earth import GRAVITY, reproject, transformer
from coastmesh.sizing.channel import (
    NARROW_ELEMENTS,
    ChannelReport,
    NarrowChannel,
    local_width,
    narrow_channels,
    water_mask,
)
from coastmesh.types import Domain, Report

if TYPE_CHECKING:
    import xarray as xr

__all__ = [
    "NARROW_CHOICES",
    "ChannelSize",
    "CourantReport",
    "CourantSize",
    "apply_courant",
    "channel_report_of",
    "courant_bounds",
    "domain_inside",
    "domain_width",
    "projected",
    "warn_narrow",
    "wave_speed",
]

#: What to do with channels too narrow for two elements of the floor size.
NARROW_CHOICES = ("keep", "close")


@dataclass(frozen=True, slots=True)
class ChannelSize:
    """The channel-width term: ``elements_across`` elements across the water.

    Parameters
    ----------
    elements_across : float, default 3
        Elements across every channel; at least 1. The size is at most the width
        of the water over this, and at least the field's ``h_min``.
    narrow : {"keep", "close"}
        Channels narrower than two elements of ``h_min``: kept (and reported,
        with a warning) or closed, i.e. taken out of the domain as land
        (:func:`coastmesh.build_case` builds the domain again without them).
    """

    elements_across: float = 3.0
    narrow: str = "keep"

    def __post_init__(self) -> None:
        if not (
            isinstance(self.elements_across, int | float) and self.elements_across >= 1
        ):
            raise ValueError(
                f"elements_across = {self.elements_across!r}: must be a number >= 1"
            )
        if self.narrow not in NARROW_CHOICES:
            raise ValueError(
                f"narrow = {self.narrow!r}: expected one of {NARROW_CHOICES}"
            )


@dataclass(frozen=True, slots=True)
class CourantSize:
    """The Courant term: sizes a model runs at time step ``dt``.

    Parameters
    ----------
    raster : xarray.DataArray or DepthSources
        Bathymetry, as :func:`coastmesh.io.read_raster` returns it.
    dt : float
        The model's time step, seconds.
    positive : {"up", "down"}
        The raster's sign.
    courant_max : float, optional
        Largest Courant number: the size is at least ``dt (c + u) / courant_max``
        (explicit models: ADCIRC asks for about 0.5 to 0.9).
    courant_min : float, optional
        Smallest Courant number: the size is at most ``dt (c + u) / courant_min``
        (SCHISM asks for 0.4 or more).
    velocity : float
        The flow speed ``u`` added to the wave speed ``c = sqrt(g d)``, m/s.
    min_depth : float
        Depths below this (and land) are taken as this, metres.
    """

    raster: xr.DataArray | DepthSources
    dt: float
    positive: str = "up"
    courant_max: float | None = 0.5
    courant_min: float | None = None
    velocity: float = 1.0
    min_depth: float = 1.0

    def __post_init__(self) -> None:
        for name in ("dt", "courant_max", "courant_min"):
            value = getattr(self, name)
            if value is not None and not value > 0:
                raise ValueError(f"{name} = {value!r}: must be > 0")
        if not self.velocity >= 0:
            raise ValueError(f"velocity = {self.velocity!r}: must be >= 0 m/s")
        if (
            self.courant_min is not None
            and self.courant_max is not None
            and self.courant_min >= self.courant_max
        ):
            raise ValueError(
                f"courant_min = {self.courant_min!r} is not below courant_max = "
                f"{self.courant_max!r}"
            )


@dataclass(frozen=True, slots=True)
class CourantReport(Report):
    """What the Courant term did to the size field.

    Attributes
    ----------
    dt, velocity : float
        The time step (s) and velocity scale (m/s).
    courant_min, courant_max : float or None
        The window.
    raised_km2 : float
        Area where ``courant_max`` raised the size (over the other terms).
    lowered_km2 : float
        Area where ``courant_min`` lowered it.
    unmet_km2 : float
        Area where no size in ``[h_min, h_max]`` meets the window.
    """

    dt: float
    velocity: float
    courant_min: float | None
    courant_max: float | None
    raised_km2: float
    lowered_km2: float
    unmet_km2: float

    def summary(self) -> str:
        """Return a one-line summary."""
        window = (
            f"{self.courant_min if self.courant_min is not None else 0:g} to "
            f"{self.courant_max if self.courant_max is not None else 'inf'}"
        )
        return (
            f"Courant {window} at dt {self.dt:g} s (u {self.velocity:g} m/s): "
            f"raised on {self.raised_km2:,.1f} km2, lowered on "
            f"{self.lowered_km2:,.1f} km2, unmet on {self.unmet_km2:,.1f} km2"
        )


def wave_speed(depth: NDArray[np.float64], velocity: float) -> NDArray[np.float64]:
    """Return ``sqrt(g d) + u``, with depths below 0 taken as 0 (m/s).

    Examples
    --------
    >>> wave_speed(np.array([10.0, -2.0]), 1.0).round(3).tolist()
    [10.903, 1.0]
    """
    return np.sqrt(GRAVITY * np.maximum(depth, 0.0)) + velocity


def courant_bounds(
    depth: NDArray[np.float64], c: CourantSize
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Return the sizes (floor, cap) that keep the Courant number in its window.

    Parameters
    ----------
    depth : ndarray
        Depth, metres, positive down (raised to ``c.min_depth``).
    c : CourantSize

    Returns
    -------
    floor, cap : ndarray
        ``dt (sqrt(g d) + u) / courant_max`` (0 without ``courant_max``) and
        ``dt (sqrt(g d) + u) / courant_min`` (inf without ``courant_min``).

    Examples
    --------
    >>> import xarray as xr
    >>> raster = xr.DataArray(np.zeros((2, 2)), dims=("y", "x"))
    >>> c = CourantSize(raster, dt=10.0, courant_max=0.5, courant_min=0.25,
    ...                 velocity=0.0)
    >>> floor, cap = courant_bounds(np.array([100 / GRAVITY]), c)
    >>> floor.round(6).tolist(), cap.round(6).tolist()
    ([200.0], [400.0])
    """
    speed = c.dt * wave_speed(np.maximum(depth, c.min_depth), c.velocity)
    floor = np.zeros_like(speed) if c.courant_max is None else speed / c.courant_max
    no_cap = np.full_like(speed, np.inf)
    cap = no_cap if c.courant_min is None else speed / c.courant_min
    return floor, cap


def domain_width(
    domain: Domain,
    x: NDArray[np.float64],
    y: NDArray[np.float64],
    mesh_crs: CRS,
    *,
    max_width: float,
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Return the width of the domain's water at the grid nodes, and the inside.

    Parameters
    ----------
    domain : Domain
        Its shoreline segments are walls; its open boundaries are not.
    x, y : ndarray
        Ascending, evenly spaced node coordinates in ``mesh_crs`` (metres).
    mesh_crs : pyproj.CRS
        A projected CRS.
    max_width : float
        Wider water comes out as ``inf`` (see
        :func:`~coastmesh.sizing.channel.local_width`).

    Returns
    -------
    width : ndarray, shape (len(y), len(x))
        Metres; 0 on land.
    inside : ndarray of bool
        Nodes inside the domain.
    """
    cell = float(x[1] - x[0])
    inside = domain_inside(domain, x, y, mesh_crs)
    lines: dict[str, list[shapely.Geometry]] = {"shoreline": [], "open": []}
    for s in domain.segments:
        lines[s.kind].append(shapely.LineString(s.coords))
    shore = _touched(projected(domain, lines["shoreline"], mesh_crs), x, y)
    opened = _touched(projected(domain, lines["open"], mesh_crs), x, y)
    water = water_mask(inside, shore, opened)
    return local_width(water, cell, max_width=max_width), inside


def _touched(
    lines: NDArray[np.object_], x: NDArray[np.float64], y: NDArray[np.float64]
) -> NDArray[np.bool_]:
    """Grid nodes next to the lines: the nearest node of every point of them.

    Each line is sampled at a third of the grid spacing, so every cell it
    crosses has a sample (a line burnt into the grid; rasterio is kept out of
    the core stages).
    """
    mask = np.zeros((len(y), len(x)), dtype=bool)
    if not len(lines):
        return mask
    cell = float(x[1] - x[0])
    points = shapely.get_coordinates(shapely.segmentize(lines, cell / 3))
    col = np.clip(np.rint((points[:, 0] - x[0]) / cell).astype(np.int64), 0, len(x) - 1)
    row = np.clip(np.rint((points[:, 1] - y[0]) / cell).astype(np.int64), 0, len(y) - 1)
    mask[row, col] = True
    return mask


def channel_report_of(
    width: NDArray[np.float64],
    inside: NDArray[np.bool_],
    limited: NDArray[np.bool_],
    *,
    x: NDArray[np.float64],
    y: NDArray[np.float64],
    mesh_crs: CRS,
    channels: ChannelSize,
    h_min: float,
) -> tuple[ChannelReport, NDArray[np.int32]]:
    """Describe the term: where it set the size, and the narrow channels.

    Returns the report and the labels of the narrow channels
    (:func:`~coastmesh.sizing.channel.narrow_channels`).
    """
    cell = float(x[1] - x[0])
    labels, found = narrow_channels(width, inside, h_min=h_min, cell=cell)
    to_lonlat = transformer(mesh_crs, "EPSG:4326")
    worst = []
    for row, col, area, w in found[:20]:
        lon, lat = to_lonlat.transform(x[col], y[row])
        worst.append(
            NarrowChannel(
                x=float(x[col]),
                y=float(y[row]),
                lon=round(float(lon), 6),
                lat=round(float(lat), 6),
                area_m2=area,
                width_m=w,
            )
        )
    report = ChannelReport(
        elements_across=float(channels.elements_across),
        h_min=float(h_min),
        narrow=channels.narrow,
        limited_km2=float(limited.sum()) * cell * cell / 1e6,
        narrow_channels=len(found),
        narrow_km2=sum(a for _, _, a, _ in found) / 1e6,
        worst=tuple(worst),
    )
    return report, labels


def apply_courant(
    courant: CourantSize,
    values: NDArray[np.float64],
    x: NDArray[np.float64],
    y: NDArray[np.float64],
    mesh_crs: CRS,
    inside: NDArray[np.bool_],
    *,
    h_min: float | None,
    h_max: float,
) -> tuple[NDArray[np.float64], CourantReport]:
    """Apply the Courant cap, then ``h_min``, then the Courant floor.

    Returns the sizes and the report; warns of a window no size meets.
    """
    depth = depth_on_grid(courant.raster, x, y, crs=mesh_crs, positive=courant.positive)
    floor, cap = courant_bounds(depth, courant)
    lowered = inside & (cap < values)
    values = np.minimum(values, cap)
    if h_min is not None:
        values = np.maximum(values, h_min)
    raised = inside & (floor > values)
    values = np.maximum(values, floor)
    low = h_min if h_min is not None else 0.0
    unmet = inside & ((floor > h_max) | (cap < low))
    cell = float(x[1] - x[0])
    km2 = cell * cell / 1e6
    report = CourantReport(
        dt=courant.dt,
        velocity=courant.velocity,
        courant_min=courant.courant_min,
        courant_max=courant.courant_max,
        raised_km2=float(raised.sum()) * km2,
        lowered_km2=float(lowered.sum()) * km2,
        unmet_km2=float(unmet.sum()) * km2,
    )
    if unmet.any():
        warnings.warn(
            f"mesh_size.courant: no size in [h_min, h_max] = [{low:g}, {h_max:g}] m "
            f"keeps the Courant number in its window at dt = {courant.dt:g} s on "
            f"{report.unmet_km2:,.1f} km2 of the domain; the Courant number "
            "leaves the window there (h_max wins over the floor, h_min over the cap)",
            CoastmeshWarning,
            stacklevel=4,
        )
    return values, report


def domain_inside(
    domain: Domain, x: NDArray[np.float64], y: NDArray[np.float64], mesh_crs: CRS
) -> NDArray[np.bool_]:
    """Return the grid nodes inside the domain."""
    polygon = projected(domain, [domain.polygon], mesh_crs)[0]
    shapely.prepare(polygon)
    xx, yy = np.meshgrid(x, y)
    return shapely.contains_xy(polygon, xx, yy)


def projected(
    domain: Domain, geometries: list[shapely.Geometry], mesh_crs: CRS | str
) -> NDArray[np.object_]:
    """Return geometries of the domain in ``mesh_crs``, densified first.

    Vertices go in every 1/4000 of the domain's extent, so that straight
    edges in the domain's CRS (a meridian, a loxodrome) keep their shape.
    """
    b = domain.polygon.bounds
    step = max(b[2] - b[0], b[3] - b[1]) / 4000
    return reproject(
        shapely.segmentize(np.array(geometries, dtype=object), step),
        domain.crs,
        mesh_crs,
    )


def warn_narrow(
    report: ChannelReport, *, closed: bool = False, after_closing: int = 0
) -> None:
    """Warn of narrow channels kept (or closed), where they are, and what to do.

    ``after_closing``: these are left after closing others this many times.
    """
    where = "; ".join(c.summary() for c in report.worst[:3])
    if closed:
        action = "closed: taken out of the domain as land"
    elif after_closing:
        action = (
            f"left after closing narrow channels {after_closing} times (the cuts "
            "made them), kept: they are one element wide. Lower h_min to resolve "
            "them"
        )
    else:
        action = (
            "kept: they are one element wide. Lower h_min to resolve them, or set "
            '[mesh_size.channels] narrow = "close"'
        )
    warnings.warn(
        f"mesh_size: {report.narrow_channels} channels are narrower than "
        f"{NARROW_ELEMENTS} elements of h_min = {report.h_min:g} m ("
        f"{report.narrow_km2:,.2f} km2; the largest: {where}), {action}",
        CoastmeshWarning,
        stacklevel=4,
    )
