"""``[mesh_size.courant]``: sizes a model runs at its time step, on by default.

The Courant number is ``C = dt (sqrt(g d) + u) / h``, with ``d`` the depth (from
``[mesh_size.bathymetry]``, else ``[bathymetry]``) and ``h`` the size. The size
is kept between ``dt (sqrt(g d) + u) / courant_max`` (a floor, which beats
``h_min``) and ``dt (sqrt(g d) + u) / courant_min`` (a cap).

``dt = "auto"`` (the default) takes the time step from the mesh the other terms
ask for: the stable step ``courant_max h / (sqrt(g d) + u)`` of each cell of
their field, weighted by the elements the cell will hold (its area over
``h^2``); the 1st percentile of these, times 0.7, rounded down to two
figures. The floor is then ``dt (sqrt(g d) + u) / (0.7 courant_max)``: the
1 % of the elements that would step slowest are made as large as the 1st
percentile's, so that no handful of elements sets the time step, and an
element down to 0.7 of its target size still has ``C <= courant_max`` at
``dt``. After meshing, the quality report checks every element at ``dt``;
with ``"auto"`` the step is lowered (to two figures) until no element is above
``courant_max``, and that is the ``dt`` reported (``quality.time_step.courant``)
and drawn: the step the model can run the mesh at. Inside ``[[sites]]`` the
floor does not apply: the user's fine regions keep their sizes, and the
quality report names the elements that then set the time step.

The term is on by default wherever a case, regional or global, has a depth;
without any bathymetry it is off (an explicit ``dt`` there is an error). On
the world grid it works as on a plane one: the depth of a sea node comes from
the wet cells alone (the nearest wet cell over raster land), and ``dt =
"auto"`` weights each node by the elements it holds, its area on the sphere
over ``h^2``.
Where no size in ``[h_min, h_max]`` meets the window, a warning gives the area.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Set as AbstractSet
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from coastmesh.case import schema
from coastmesh.case.schema import Check, key
from coastmesh.case.terms.base import SizeCase, SizeTerm, switched_on
from coastmesh.errors import CoastmeshWarning, ConfigError
from coastmesh.sizing.combine import Applied, TermSizes
from coastmesh.sizing.courant import (
    CourantReport,
    courant_bounds,
    round_step,
    wave_speed,
)
from coastmesh.sizing.grid import Grid

if TYPE_CHECKING:
    from coastmesh.case.config import CaseConfig

__all__ = [
    "AUTO_PERCENTILE",
    "AUTO_SHARE",
    "DEFAULT_COURANT_MAX",
    "Courant",
    "CourantConfig",
    "auto_time_step",
]

#: ``courant_max`` when neither bound is given (explicit models).
DEFAULT_COURANT_MAX = 0.5
#: ``dt = "auto"``: the percentile (of the elements) of the field's stable steps.
AUTO_PERCENTILE = 1.0
#: ``dt = "auto"``: the share of that percentile's step the model runs at; an
#: element down to this share of its target size keeps ``C <= courant_max``.
AUTO_SHARE = 0.7


def _dt(value: object, key: str) -> float | None:
    """``dt``: a duration > 0, or ``"auto"`` (None)."""
    if value is None or value == "auto":
        return None
    return schema.duration(value, key)


def _read_dt(value: object, key: str) -> float | None:
    """``dt`` in a case file: ``"auto"``, or a duration with its unit."""
    if value == "auto":
        return None
    return schema.duration_with_unit(value, key)


@dataclass(frozen=True)
class CourantConfig:
    """``[mesh_size.courant]``."""

    dt: float | None = key(
        None,
        check=_dt,
        read=_read_dt,
        unit="duration",
        dump=lambda v: "auto" if v is None else f"{v!r} s",
        default_doc='`"auto"`',
        doc='the model\'s time step (`"30 s"`, `"1 min"`), or `"auto"`: the '
        "1st percentile (by elements) of the stable steps of the field the other "
        "terms ask for, times 0.7, rounded down to two figures (below)",
    )
    courant_max: float | None = key(
        None,
        check=schema.positive,
        default_doc="`0.5` if neither bound is given, else none",
        doc="the largest Courant number (explicit models: ADCIRC about 0.5 to 0.9)",
    )
    courant_min: float | None = key(
        None,
        check=schema.positive,
        doc="the smallest (SCHISM asks for 0.4 or more); needs a given `dt`",
    )
    velocity: float = key(
        1.0,
        check=schema.speed,
        unit="speed",
        doc='the flow speed `u` added to the wave speed (`"m/s"`, `"kn"`, `"km/h"`)',
    )
    enabled: bool | None = key(
        None,
        check=schema.boolean,
        default_doc="`true`",
        doc="the term at all",
    )

    def _validate(self, c: Check) -> CourantConfig:
        high, low = self.courant_max, self.courant_min
        if high is None and low is None:
            high = DEFAULT_COURANT_MAX
        if high is not None and low is not None and low >= high:
            raise c.error(
                "courant_min",
                f"= {low:g} is not below courant_max = {high:g}: no Courant number "
                "fits between them",
            )
        if self.dt is None and (low is not None or high is None):
            raise c.error(
                "dt",
                '= "auto" takes the time step from courant_max alone: give dt '
                "(seconds) with courant_min",
            )
        return replace(self, courant_max=high)


def auto_time_step(
    field: NDArray[np.float64],
    speed: NDArray[np.float64],
    sea: NDArray[np.bool_],
    courant_max: float,
    *,
    areas: NDArray[np.float64] | None = None,
) -> float:
    """Return the ``dt = "auto"`` time step of a size field, seconds.

    The stable step of each sea cell, ``courant_max h / speed``, weighted by the
    elements it holds: ``1 / h^2`` where the grid's cells are of one area (a
    plane), else ``areas / h^2`` (a world grid, whose cells shrink with the
    cosine of the latitude); the :data:`AUTO_PERCENTILE` of these, times
    :data:`AUTO_SHARE`, rounded down to two significant figures. Cells without
    a depth (beyond the rasters) or an area do not count; none at all gives
    ``inf``.

    Examples
    --------
    >>> h = np.array([100.0, 1000.0, 1000.0])
    >>> float(auto_time_step(h, np.full(3, 10.0), np.ones(3, bool), 0.5))
    3.5
    >>> float(auto_time_step(h, np.full(3, 10.0), np.ones(3, bool), 0.5,
    ...                      areas=np.array([0.0, 1.0, 1.0])))
    35.0
    """
    known = sea & np.isfinite(speed)
    if areas is not None:
        known &= areas > 0
    h, c = field[known], speed[known]
    if h.size == 0:
        return math.inf
    steps = courant_max * h / c
    order = np.argsort(steps)
    share = 1.0 if areas is None else areas[known][order]
    weights = np.cumsum(share / h[order] ** 2)
    k = np.searchsorted(weights, AUTO_PERCENTILE / 100.0 * weights[-1])
    return round_step(AUTO_SHARE * float(steps[order][min(k, len(order) - 1)]))


class Courant(SizeTerm[CourantConfig | None]):
    """The term of ``[mesh_size.courant]``."""

    key = "courant"
    config = CourantConfig
    many = False
    default = CourantConfig()
    doc = 'sizes a model runs at its time step, on by default (`dt = "auto"`)'
    on_by_default = True
    reports = True

    def check(
        self,
        settings: CourantConfig | None,
        case: CaseConfig,
        *,
        label: str,
        lines: AbstractSet[str],
    ) -> None:
        """Refuse a given ``dt`` without depths: the Courant term needs them."""
        if (
            settings is not None
            and settings.enabled is not False
            and settings.dt is not None
            and case.size.bathymetry is None
            and case.bathymetry is None
        ):
            raise ConfigError(
                f"{label}: mesh_size.courant.dt = {settings.dt:g} s: the Courant term "
                "needs the depth; add [mesh_size.bathymetry] or [bathymetry]"
            )

    def sizes(self, grid: Grid, case: SizeCase) -> TermSizes | None:
        """Cap and floor the size so the Courant number stays in its window.

        The depth is ``[mesh_size.bathymetry]``'s, else ``[bathymetry]``'s.
        With ``dt = "auto"`` the floor follows from the field of the other
        terms (:func:`auto_time_step`). Warns of the area where no size in
        ``[h_min, h_max]`` meets the window.
        """
        co = self.settings(case)
        source = case.config.size.bathymetry or case.config.bathymetry
        if co is None or source is None:
            return None
        if not switched_on(co.enabled):
            return None
        min_depth = source.min_depth
        depth = grid.depth(case.depth(source), source.positive)
        depth_floor = min_depth if min_depth is not None and min_depth > 0 else 1.0
        speed = wave_speed(np.maximum(depth, depth_floor), co.velocity)
        sites = case.sites(grid)
        h_min, h_max = case.floor, case.config.size.h_max

        def bounds(
            dt: float, share: float = 1.0
        ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
            high = None if co.courant_max is None else co.courant_max * share
            floor, cap = courant_bounds(
                depth,
                dt=dt,
                courant_max=high,
                courant_min=co.courant_min,
                velocity=co.velocity,
                min_depth=depth_floor,
            )
            unknown = ~np.isfinite(depth)  # beyond the rasters: no bound
            floor = np.where(unknown, 0.0, floor)
            cap = np.where(unknown, np.inf, cap)
            if sites is not None:
                floor = np.where(sites, 0.0, floor)
            return floor, cap

        if co.dt is None:
            courant_max = co.courant_max
            assert courant_max is not None  # _validate: dt = "auto" needs it

            def time_step(floored: NDArray[np.float64]) -> float:
                return float(
                    auto_time_step(
                        floored, speed, grid.sea, courant_max, areas=grid.areas
                    )
                )

            def lower(floored: NDArray[np.float64]) -> NDArray[np.float64]:
                dt = time_step(floored)
                if not math.isfinite(dt):  # no depth in the sea: no floor
                    return np.zeros_like(floored)
                return bounds(dt, AUTO_SHARE)[0]

            def report(applied: Applied) -> CourantReport:
                dt = time_step(applied.floored)
                floor = lower(applied.floored)
                return _report(co, dt, grid, floor, None, applied, 0.0, auto=True)

            return TermSizes(
                lower_from=lower, report=report, history="Courant at dt auto"
            )
        dt = co.dt
        floor, cap = bounds(dt)
        _refuse_impossible(co, grid, floor, depth, h_max)
        unmet = grid.km2(grid.sea & ((floor > h_max) | (cap < h_min)))
        if unmet > 0:
            warnings.warn(
                f"mesh_size.courant: no size in [h_min, h_max] = [{h_min:g}, "
                f"{h_max:g}] m keeps the Courant number in its window at dt = "
                f"{co.dt:g} s on {unmet:,.1f} km2 of the domain; the Courant number "
                "leaves the window there (h_max wins over the floor, h_min over the "
                "cap)",
                CoastmeshWarning,
                stacklevel=2,
            )

        def given(applied: Applied) -> CourantReport:
            return _report(co, dt, grid, floor, cap, applied, unmet, auto=False)

        return TermSizes(
            upper=cap, lower=floor, report=given, history=f"Courant at dt {co.dt:g} s"
        )


def _refuse_impossible(
    co: CourantConfig,
    grid: Grid,
    floor: NDArray[np.float64],
    depth: NDArray[np.float64],
    h_max: float,
) -> None:
    """Raise if no element of the sea can meet ``dt``: the floor is above h_max."""
    sea = grid.sea & np.isfinite(depth)
    if not sea.any() or not (floor[sea] > h_max).all():
        return
    k = np.argmin(np.where(sea, floor, np.inf))
    d, h = float(depth.flat[k]), float(floor.flat[k])
    raise ConfigError(
        f"mesh_size.courant.dt = {co.dt:g} s: no element of the sea can meet it "
        f"at courant_max = {co.courant_max:g}: even the shallowest water "
        f"({max(d, 0.0):.1f} m deep) needs elements of at least {h:,.0f} m, above "
        f'h_max = {h_max:g} m; give a smaller dt, dt = "auto", or a larger h_max'
    )


def _report(
    co: CourantConfig,
    dt: float,
    grid: Grid,
    floor: NDArray[np.float64],
    cap: NDArray[np.float64] | None,
    applied: Applied,
    unmet: float,
    *,
    auto: bool,
) -> CourantReport:
    """Return the term's report: the step, and where its bounds set the size."""
    lowered = 0.0 if cap is None else grid.km2(grid.sea & (cap < applied.before))
    return CourantReport(
        dt=dt,
        velocity=co.velocity,
        courant_min=co.courant_min,
        courant_max=co.courant_max,
        raised_km2=grid.km2(grid.sea & (floor > applied.floored)),
        lowered_km2=lowered,
        unmet_km2=unmet,
        auto=auto,
    )
