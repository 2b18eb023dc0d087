"""Size terms combined into one field: :func:`combine`, and its report.

Each term gives its sizes on the grid (:class:`TermSizes`): an ``upper`` bound
(the size it asks for: the field is at most this) and, rarely, a ``lower`` bound
that beats the floor (a model's time step). They combine in one order, the same
for every term and every grid:

1. the upper bounds, from ``h_max`` down, by minimum, term after term;
2. the floor ``h_min`` raises that (so no term goes below it), except where a
   term lowers the floor (``floor``: the channels of a ``[[sites]]`` region,
   two elements across);
3. the lower bounds raise it again (over ``h_min``: a model must run at its
   time step); a term may work its lower bound out from the field so far
   (``lower_from``: the Courant term's ``dt = "auto"``);
4. ``h_max`` caps everything (a lower bound above it is a window no size
   meets, which the term warns of);
5. the gradation limit ``rate`` lowers sizes last (it may go below the floors
   next to a small size; it never raises one).

A term's report may need what the field was when its sizes were applied (the
area its bound set the size on): it gets an :class:`Applied`.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from coastmesh.sizing.grid import Grid
from coastmesh.types import Report

if TYPE_CHECKING:
    import xarray as xr

__all__ = ["Applied", "Combined", "SizeFieldReport", "TermSizes", "combine"]


@dataclass(frozen=True, eq=False)
class Applied:
    """What the field was when a term's sizes were applied.

    Attributes
    ----------
    before : ndarray
        The field just before the term's upper bound (the terms before it, by
        minimum, from ``h_max``).
    floored : ndarray
        The field after every upper bound and the floor ``h_min``, before the
        lower bounds.
    """

    before: NDArray[np.float64]
    floored: NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class TermSizes:
    """What one size term asks of the field, on its grid (metres).

    Attributes
    ----------
    upper : ndarray or None
        The field is at most this (combined by minimum with the other terms).
    lower : ndarray or None
        The field is at least this, over the floor ``h_min``.
    floor : ndarray or None
        Where finite and below ``h_min``, the floor there instead (the term
        asks for finer elements than ``h_min`` on purpose).
    lower_from : callable, optional
        ``lower_from(floored) -> ndarray``: a lower bound worked out from the
        field after every upper bound and the floor (a time step the field
        itself sets), applied as ``lower`` is.
    report : callable, optional
        ``report(applied) -> Report``: the term's report, given what the field
        was when its sizes were applied (:class:`Applied`).
    history : str
        How the term reads in the field's ``history`` attribute.
    layers : mapping of str to ndarray
        Other grids the term measured, by name (the channel term's ``width``),
        kept with the field for figures and reports.
    conform : ndarray of bool or None
        Where the mesh's elements must take the term's sizes closely, not
        only as Gmsh makes them: after meshing, the nodes where the field is
        the term's ``upper`` are moved to bring the elements' sizes to it
        (:func:`~coastmesh.meshing.cleanup.conform.conform_sizes`).
    """

    upper: NDArray[np.float64] | None = None
    lower: NDArray[np.float64] | None = None
    floor: NDArray[np.float64] | None = None
    lower_from: Callable[[NDArray[np.float64]], NDArray[np.float64]] | None = None
    report: Callable[[Applied], Report | None] | None = None
    history: str = ""
    layers: Mapping[str, NDArray[np.float64]] = field(default_factory=dict)
    conform: NDArray[np.bool_] | None = None


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
    terms : mapping of str to Report or None
        Each reporting term's report, by its key (``channels``, ``courant``);
        None where the term is off. ``report.json`` has them beside the fields
        above.
    """

    shape: tuple[int, int]
    cell_m: float
    min_m: float
    max_m: float
    h_min_m: float | None = None
    terms: Mapping[str, Report | None] = field(
        default_factory=dict, metadata={"to_dict": False}
    )

    def __getattr__(self, name: str) -> Report | None:
        """Return a term's report by its key: ``report.channels``."""
        terms: Mapping[str, Report | None] = object.__getattribute__(self, "terms")
        if name in terms:
            return terms[name]
        raise AttributeError(f"{type(self).__name__} has no {name!r}")

    def to_dict(self) -> dict[str, object]:
        """Return the report as data: the fields, then each term's report."""
        return Report.to_dict(self) | {
            key: None if part is None else part.to_dict()
            for key, part in self.terms.items()
        }

    def summary(self) -> str:
        """Return a one-line summary."""
        text = (
            f"{self.shape[1]} x {self.shape[0]} cells of {self.cell_m:.0f} m, "
            f"{self.min_m:.0f} to {self.max_m:.0f} m"
        )
        for part in self.terms.values():
            if part is not None:
                text += f"; {part.summary()}"
        return text


@dataclass(frozen=True, eq=False)
class Combined:
    """A size field made of its terms: :func:`combine` returns it.

    Attributes
    ----------
    field : xarray.DataArray
        Sizes in metres on the grid, with a ``history`` naming the terms.
    report : SizeFieldReport
    layers : mapping of str to xarray.DataArray
        The terms' other grids (the channel term's ``width``), NaN outside the
        sea.
    conform : ndarray of bool or None
        The nodes where a term asked for its sizes to hold closely
        (:attr:`TermSizes.conform`, of every term) and the field is that
        term's size (land nodes by the coast too, as the term gives them);
        None if none asked.
    """

    field: xr.DataArray
    report: SizeFieldReport
    layers: Mapping[str, xr.DataArray]
    conform: NDArray[np.bool_] | None = None


def combine(
    grid: Grid,
    terms: Sequence[tuple[str, TermSizes | None]],
    *,
    h_min: float | None,
    h_max: float,
    rate: float | None,
    reporting: Sequence[str] = (),
) -> Combined:
    """Combine size terms into one field, in the order of the module notes.

    Parameters
    ----------
    grid : Grid
        Where every term's sizes are.
    terms : sequence of (key, TermSizes or None)
        The terms in order; None for a term that is off.
    h_min : float or None
        The floor, metres.
    h_max : float
        The ceiling, metres.
    rate : float or None
        The gradation limit, metres per metre; None for none.
    reporting : sequence of str
        The terms whose reports the field's report holds (None where off).

    Returns
    -------
    Combined

    Examples
    --------
    >>> from coastmesh.sizing.grid import PlaneGrid
    >>> g = PlaneGrid.from_bounds((0.0, 0.0, 400.0, 100.0), 100.0, "EPSG:32630")
    >>> coast = TermSizes(upper=np.array([[50.0, 1e9, 1e9, 1e9, 1e9]] * 2))
    >>> out = combine(g, [("coast", coast)], h_min=100.0, h_max=1000.0, rate=None)
    >>> out.field.values[0].tolist()  # 50 m floored to 100 m, 1e9 m capped
    [100.0, 1000.0, 1000.0, 1000.0, 1000.0]
    """
    values = np.full(grid.shape, float(h_max))
    applied: list[tuple[str, TermSizes, NDArray[np.float64]]] = []
    for key, sizes in terms:
        if sizes is None:
            continue
        applied.append((key, sizes, values))
        if sizes.upper is not None:
            values = np.minimum(values, sizes.upper)
    if h_min is not None:
        floor: float | NDArray[np.float64] = h_min
        for _, sizes, _ in applied:
            if sizes.floor is not None:
                floor = np.fmin(floor, sizes.floor)
        values = np.maximum(values, floor)
    floored = values
    for _, sizes, _ in applied:
        if sizes.lower is not None:
            values = np.maximum(values, sizes.lower)
        if sizes.lower_from is not None:
            values = np.maximum(values, sizes.lower_from(floored))
    values = np.minimum(values, h_max)
    if rate is not None:
        values = grid.limit(values, rate)
    reports = dict.fromkeys(reporting)
    for key, sizes, before in applied:
        if sizes.report is not None:
            reports[key] = sizes.report(Applied(before, floored))
    history = ", ".join(s.history for _, s, _ in applied if s.history)
    field_ = grid.field(values, _history(history, h_min, h_max, rate))
    report = SizeFieldReport(
        shape=grid.shape,
        cell_m=grid.cell_m,
        min_m=float(field_.min()),
        max_m=float(field_.max()),
        h_min_m=h_min,
        terms=reports,
    )
    layers = {
        name: _layer(field_, name, layer, grid.sea)
        for _, sizes, _ in applied
        for name, layer in sizes.layers.items()
    }
    return Combined(field_, report, layers, _conform(applied, values))


def _conform(
    applied: list[tuple[str, TermSizes, NDArray[np.float64]]],
    values: NDArray[np.float64],
) -> NDArray[np.bool_] | None:
    """Return the nodes where a term asks its sizes to hold and sets the size.

    Where the field is the term's own size (to 1e-9): not where another term,
    the floor or the grading made it other. Land nodes too: a coast node's
    grid cell has corners on land. None if no term asks.
    """
    masks = [
        sizes.conform & np.isclose(values, sizes.upper, rtol=1e-9, atol=0.0)
        for _, sizes, _ in applied
        if sizes.conform is not None and sizes.upper is not None
    ]
    if not masks:
        return None
    return np.asarray(np.logical_or.reduce(masks), dtype=bool)


def _history(terms: str, h_min: float | None, h_max: float, rate: float | None) -> str:
    text = "coastmesh size field: " + (terms or "no terms")
    text += f", h_min {h_min:g} m" if h_min is not None else ""
    text += f", h_max {h_max:g} m"
    return text + (f", rate {rate:g}" if rate is not None else "")


def _layer(
    like: xr.DataArray, name: str, values: NDArray[np.float64], sea: NDArray[np.bool_]
) -> xr.DataArray:
    layer = like.copy(data=np.where(sea, values, np.nan))
    layer.name = name
    layer.attrs["history"] = f"coastmesh: {name} (size term)"
    return layer
