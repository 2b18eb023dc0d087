"""The size field of a whole domain, graded from its named boundaries.

Gradations from named boundary segments, bathymetry terms, a floor, a ceiling
and a gradation limit. This is the size stage of a case (``[mesh_size]``), for a
:class:`~coastmesh.types.Domain` built in Python as much as for one built from a
case file. Terms combine by minimum, then the floor ``h_min`` wins over every
term, then ``h_max`` caps the result, and the gradation limit ``rate`` lowers
sizes last (so it may go below ``h_min`` next to a small size; it never raises
one).
"""

from __future__ import annotations

import logging
import warnings
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import shapely
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.errors import CoastmeshWarning, ConfigError
from coastmesh.geometry.earth import reproject
from coastmesh.sizing.bathymetry import BathymetrySize, bathymetry_size
from coastmesh.sizing.channel import ChannelReport, channel_polygons, over_land
from coastmesh.sizing.field import Gradation, grid_axes, size_field
from coastmesh.sizing.gradation import DEFAULT_RATE, limit_gradation
from coastmesh.sizing.slots import domain_slots, off_open_boundaries
from coastmesh.sizing.terms import (
    ChannelSize,
    CourantReport,
    CourantSize,
    apply_courant,
    channel_report_of,
    domain_inside,
    domain_width,
    warn_narrow,
)
from coastmesh.types import Domain, Progress, Report, Runner

if TYPE_CHECKING:
    import xarray as xr

__all__ = [
    "BathymetrySize",
    "BoundaryGradation",
    "SizeField",
    "SizeFieldReport",
    "domain_size_field",
    "domain_slots",  # from coastmesh.sizing.slots, where it lives
    "size_field_with_report",
]

logger = logging.getLogger(__name__)

#: The default grid spacing, and the densification of the domain's outline
#: before it is projected, are the domain's extent over this.
_CELLS_ACROSS = 1000
#: The channel term as it is by default: 3 elements across, narrow channels kept.
DEFAULT_CHANNELS = ChannelSize()
#: The grid extends this many cells beyond the domain on every side.
_PAD_CELLS = 2


@dataclass(frozen=True, slots=True)
class BoundaryGradation:
    """The paper's gradation from named boundary segments of a domain.

    Parameters
    ----------
    lines : sequence of str
        Names of :class:`~coastmesh.types.BoundarySegment` of the domain: its
        shoreline sets and open boundaries.
    h_min : float
        Size at the lines, metres.
    d_grade : float
        Distance over which the size grows linearly to ``h_max``, metres.
    d_hold : float, default 0
        Distance over which ``h_min`` holds first, metres.
    """

    lines: tuple[str, ...]
    h_min: float
    d_grade: float
    d_hold: float = 0.0


@dataclass(frozen=True, slots=True)
class SizeFieldReport(Report):
    """The grid and the range of a size field, and what its terms did.

    Attributes
    ----------
    shape : (ny, nx)
        Grid nodes.
    cell_m : float
        Grid spacing, metres.
    min_m, max_m : float
        Smallest and largest size, metres.
    h_min_m : float or None
        The floor of the field, metres.
    channels : ChannelReport or None
        The channel-width term, when on.
    courant : CourantReport or None
        The Courant term, when on.
    """

    shape: tuple[int, int]
    cell_m: float
    min_m: float
    max_m: float
    h_min_m: float | None = None
    channels: ChannelReport | None = None
    courant: CourantReport | None = None

    @classmethod
    def of(
        cls,
        field: xr.DataArray,
        *,
        h_min: float | None = None,
        channels: ChannelReport | None = None,
        courant: CourantReport | None = None,
    ) -> SizeFieldReport:
        """Describe a size field DataArray (dims ``("y", "x")``, metres)."""
        return cls(
            shape=(int(field.shape[0]), int(field.shape[1])),
            cell_m=float(field.x[1] - field.x[0]),
            min_m=float(field.min()),
            max_m=float(field.max()),
            h_min_m=h_min,
            channels=channels,
            courant=courant,
        )

    def summary(self) -> str:
        """Return a one-line summary."""
        text = (
            f"{self.shape[1]} x {self.shape[0]} cells of {self.cell_m:.0f} m, "
            f"{self.min_m:.0f} to {self.max_m:.0f} m"
        )
        for part in (self.channels, self.courant):
            if part is not None:
                text += f"; {part.summary()}"
        return text


def domain_size_field(
    domain: Domain,
    *,
    mesh_crs: CRS | str,
    h_max: float,
    gradations: Sequence[BoundaryGradation] = (),
    h_min: float | None = None,
    cell: float | None = None,
    rate: float | None = DEFAULT_RATE,
    bathymetry: BathymetrySize | None = None,
    channels: ChannelSize | None = DEFAULT_CHANNELS,
    courant: CourantSize | None = None,
    progress: Progress | None = None,
    runner: Runner | None = None,
) -> xr.DataArray:
    """Compute the target element size over a domain, on a grid in ``mesh_crs``.

    Parameters
    ----------
    domain : Domain
        The domain; gradations name its boundary segments.
    mesh_crs : pyproj.CRS or str
        The projected CRS the mesh is made in (e.g.
        :func:`coastmesh.meshing.default_mesh_crs`); the grid is regular there.
    h_max : float
        The largest size, metres.
    gradations : sequence of BoundaryGradation
        Combined by minimum. One whose names match no segment of the domain is
        skipped, with a warning.
    h_min : float, optional
        A floor of the whole field, metres. Default: the smallest gradation
        ``h_min`` when the channel term is on (it needs a floor), else none.
    cell : float, optional
        Grid spacing, metres; default 1/1000 of the domain's extent, but not
        below the smallest ``h_min``.
    rate : float or None, default DEFAULT_RATE (0.7)
        Gradation limit: sizes grow by at most ``rate`` metres per metre; None
        for none (steeper grading makes worse triangles).
    bathymetry : BathymetrySize, optional
        Wavelength and slope terms.
    channels : ChannelSize or None
        The channel-width term, on by default (3 elements across); None turns
        it off.
    courant : CourantSize, optional
        The Courant window at a model time step.
    progress : callable, optional
        Called as ``progress(done, 3)``.
    runner : Runner, optional
        Where the gradations' distances run, in bands of rows
        (:mod:`coastmesh.sizing.bands`); default here. The field is the same.

    Returns
    -------
    xarray.DataArray
        Sizes in metres, dims ``("y", "x")``, ascending node coordinates in
        ``mesh_crs``, attrs ``crs`` (WKT), ``units`` and ``history``; the grid
        covers the domain with two cells to spare. :func:`size_field_with_report`
        returns it with its report.

    Raises
    ------
    ConfigError
        If a size is not > 0, a gradation's ``h_min`` exceeds ``h_max``, or
        ``mesh_crs`` is not projected.

    Warns
    -----
    CoastmeshWarning
        For a gradation whose lines name no segment of the domain, narrow
        channels kept, and a Courant window no size in ``[h_min, h_max]`` meets.

    Notes
    -----
    How the terms combine, in this order (later steps win):

    1. the gradations, the bathymetry terms, the channel term and the Courant
       cap (``courant_min``) combine by minimum;
    2. ``h_min`` floors the result (so the channel term never goes below it);
    3. the Courant floor (``courant_max``) raises it: a model must run at its
       time step, so this beats ``h_min``, the channel term and the gradations;
    4. ``h_max`` caps it, over everything (a floor above ``h_max`` is a window
       no size meets: it is warned of, with its area);
    5. the gradation limit ``rate`` lowers sizes last (it may go below the
       floors next to a small size; it never raises one).

    Examples
    --------
    >>> from coastmesh.types import BoundarySegment
    >>> ring = [[0, 0], [20000, 0], [20000, 20000], [0, 20000], [0, 0]]
    >>> d = Domain(shapely.Polygon(ring),
    ...            (BoundarySegment(ring[:2], "open", "south", 2),
    ...             BoundarySegment(ring[1:], "shoreline", "coast", 1)),
    ...            crs="EPSG:32630")
    >>> field = domain_size_field(
    ...     d, mesh_crs="EPSG:32630", h_max=2000.0, cell=500.0,
    ...     gradations=[BoundaryGradation(("coast",), h_min=200.0, d_grade=5000.0)])
    >>> float(field.min()), float(field.max()), field.shape
    (200.0, 2000.0, (45, 45))
    """
    return size_field_with_report(
        domain,
        mesh_crs=mesh_crs,
        h_max=h_max,
        gradations=gradations,
        h_min=h_min,
        cell=cell,
        rate=rate,
        bathymetry=bathymetry,
        channels=channels,
        courant=courant,
        progress=progress,
        runner=runner,
    ).field


@dataclass(frozen=True, slots=True)
class SizeField:
    """A size field with its report (:func:`size_field_with_report`).

    Attributes
    ----------
    field : xarray.DataArray
        As :func:`domain_size_field` returns it.
    report : SizeFieldReport
    narrow : ndarray of shapely polygons
        The channels narrower than two elements of ``h_min``, in the domain's
        CRS, grown by a cell: what ``narrow = "close"`` takes out of the domain.
        The size field does not change the domain: :func:`coastmesh.build_case`
        adds these to the land and builds the domain again; a Python caller
        does the same with :func:`coastmesh.geometry.build_domain`.
    width : xarray.DataArray or None
        With the channel term: the width of the water on the same grid, metres
        (NaN outside the domain, inf where wider than ``elements_across *
        h_max``).
    """

    field: xr.DataArray
    report: SizeFieldReport
    narrow: NDArray[np.object_]
    width: xr.DataArray | None = None


def size_field_with_report(
    domain: Domain,
    *,
    mesh_crs: CRS | str,
    h_max: float,
    gradations: Sequence[BoundaryGradation] = (),
    h_min: float | None = None,
    cell: float | None = None,
    rate: float | None = DEFAULT_RATE,
    bathymetry: BathymetrySize | None = None,
    channels: ChannelSize | None = DEFAULT_CHANNELS,
    courant: CourantSize | None = None,
    progress: Progress | None = None,
    runner: Runner | None = None,
) -> SizeField:
    """:func:`domain_size_field`, with the report of every term.

    Same parameters; returns a :class:`SizeField`.
    """
    mesh_crs = CRS.from_user_input(mesh_crs)
    for name, value in (("h_max", h_max), ("h_min", h_min), ("cell", cell)):
        if value is not None and not value > 0:
            raise ConfigError(f"{name} = {value!r}: must be > 0 metres")
    if h_min is None and channels is not None:
        h_min = min([g.h_min for g in gradations] or [h_max])
    step = _extent(domain.polygon.bounds) / _CELLS_ACROSS
    outline = reproject(
        shapely.segmentize(domain.polygon.exterior, step), domain.crs, mesh_crs
    )
    minx, miny, maxx, maxy = outline.bounds
    smallest = min(
        [g.h_min for g in gradations] + ([h_min] if h_min else []) or [h_max]
    )
    if cell is None:
        cell = max(_extent((minx, miny, maxx, maxy)) / _CELLS_ACROSS, smallest)
    pad = _PAD_CELLS * cell
    bounds = (minx - pad, miny - pad, maxx + pad, maxy + pad)
    graded = _gradations(domain, gradations, mesh_crs)
    _report(progress, 0)
    with ThreadPoolExecutor(1) as thread:
        # the width of the water needs only the grid: measured in a thread
        # while the gradations are (GEOS and scipy let the threads run at once)
        widths = (
            None
            if channels is None
            else thread.submit(
                domain_width,
                domain,
                *grid_axes(bounds, cell),
                mesh_crs,
                max_width=channels.elements_across * h_max,
            )
        )
        field = size_field(
            bounds, graded, crs=mesh_crs, h_max=h_max, cell=cell, runner=runner
        )
        measured = None if widths is None else widths.result()
    _report(progress, 1)
    x, y = field.x.values, field.y.values
    values = field.values
    if bathymetry is not None:
        values = np.minimum(values, bathymetry_size(bathymetry, field, mesh_crs))
    channel_report, narrow, inside = None, np.empty(0, dtype=object), None
    width = None
    if channels is not None:
        values, channel_report, narrow, inside, width = _channel_term(
            domain, channels, values, x, y, mesh_crs, measured, h_min=h_min
        )
        width = field.copy(data=np.where(inside, width, np.nan))
        width.name = "width"
        width.attrs["history"] = "coastmesh: width of the water (local thickness)"
    courant_report = None
    if courant is not None:
        if inside is None:
            inside = domain_inside(domain, x, y, mesh_crs)
        values, courant_report = apply_courant(
            courant, values, x, y, mesh_crs, inside, h_min=h_min, h_max=h_max
        )
    elif h_min is not None:
        values = np.maximum(values, h_min)
    values = np.minimum(values, h_max)
    if rate is not None:
        values = limit_gradation(values, (cell, cell), rate)
    _report(progress, 2)
    field = field.copy(data=values)
    field.attrs["history"] = (
        f"coastmesh domain_size_field: {len(graded)} gradations"
        + (", bathymetry" if bathymetry is not None else "")
        + (
            f", channels ({channels.elements_across:g} across)"
            if channels is not None
            else ""
        )
        + (f", Courant at dt {courant.dt:g} s" if courant is not None else "")
        + (f", h_min {h_min:g} m" if h_min is not None else "")
        + f", h_max {h_max:g} m"
        + (f", rate {rate:g}" if rate is not None else "")
    )
    _report(progress, 3)
    report = SizeFieldReport.of(
        field, h_min=h_min, channels=channel_report, courant=courant_report
    )
    logger.info("size field: %s", report.summary())
    return SizeField(field, report, narrow, width)


def _channel_term(
    domain: Domain,
    channels: ChannelSize,
    values: NDArray[np.float64],
    x: NDArray[np.float64],
    y: NDArray[np.float64],
    mesh_crs: CRS,
    measured: tuple[NDArray[np.float64], NDArray[np.bool_]],
    *,
    h_min: float,
) -> tuple[Any, ...]:
    """Apply the channel term, given ``domain_width``'s width and inside.

    Returns the sizes, report, narrow channels, nodes inside and the width.
    """
    width, inside = measured
    term = over_land(np.maximum(width / channels.elements_across, h_min), width > 0)
    limited = inside & (term < values)
    values = np.minimum(values, term)
    report, labels = channel_report_of(
        width,
        inside,
        limited,
        x=x,
        y=y,
        mesh_crs=mesh_crs,
        channels=channels,
        h_min=h_min,
    )
    narrow = np.empty(0, dtype=object)
    if channels.narrow == "close":
        narrow = domain_slots(domain, mesh_crs, h_min / 2)
    if report.narrow_channels:
        # closed as land: the cells of each channel, one cell wider (into the
        # land, and past its mouth) and simplified, so that the cut is clean
        cell = float(x[1] - x[0])
        cells = channel_polygons(labels, x, y)
        grown = shapely.simplify(shapely.buffer(cells, cell, quad_segs=2), cell)
        grown = shapely.make_valid(grown)
        narrow = np.concatenate([narrow, reproject(grown, mesh_crs, domain.crs)])
    if len(narrow):
        narrow = off_open_boundaries(narrow, domain)
    if report.narrow_channels and channels.narrow == "keep":
        warn_narrow(report)
    return values, report, narrow, inside, width


def _extent(bounds: tuple[float, ...]) -> float:
    minx, miny, maxx, maxy = bounds
    return max(maxx - minx, maxy - miny)


def _report(progress: Progress | None, done: int) -> None:
    if progress is not None:
        progress(done, 3)


def _gradations(
    domain: Domain, gradations: Sequence[BoundaryGradation], mesh_crs: CRS
) -> list[Gradation]:
    """Return each gradation's lines: the domain segments it names, in ``mesh_crs``."""
    graded = []
    for k, g in enumerate(gradations):
        wanted = set(g.lines)
        lines = [
            shapely.LineString(s.coords) for s in domain.segments if s.name in wanted
        ]
        if not lines:
            warnings.warn(
                f"mesh_size.gradations[{k}]: {sorted(wanted)} have no edges on the "
                "domain boundary; the gradation is skipped",
                CoastmeshWarning,
                stacklevel=3,
            )
            continue
        graded.append(
            Gradation(
                reproject(np.array(lines, dtype=object), domain.crs, mesh_crs),
                h_min=g.h_min,
                d_hold=g.d_hold,
                d_grade=g.d_grade,
                name=",".join(g.lines),
            )
        )
    return graded
