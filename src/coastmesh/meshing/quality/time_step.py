"""The time step a mesh lets a model run at, and its Courant numbers at a given step.

Each triangle limits an explicit shallow-water model to the time a wave takes to
cross its inscribed circle's radius, ``dt_e = r_in / (sqrt(g d) + u)``, with ``d``
the deepest of its three nodes and ``u`` a velocity scale (:func:`element_time_steps`).
The mesh runs at the smallest of these; :class:`TimeStepStats` says how small it is,
where, and whether one element throttles the model (the minimum over the 1st
percentile). At a model time step ``dt``, :class:`CourantStats` gives the
Courant numbers ``dt (sqrt(g d) + u) / h_e``, with ``h_e`` the element's mean
side: the definition the Courant size field uses with ``h`` the target edge length.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from coastmesh.geometry.earth import mesh_earth_centred
from coastmesh.meshing.quality.measure import Place, places, triangle_measures
from coastmesh.sizing.courant import wave_speed
from coastmesh.types import Mesh, Report

__all__ = [
    "MIN_OVER_P1_TARGET",
    "SLOWEST",
    "CourantStats",
    "SlowElement",
    "TimeStepStats",
    "check_time_step_options",
    "element_time_steps",
    "node_depth",
    "time_step_arrays",
    "time_step_stats",
]


#: Smallest stable element time step over the 1st percentile of them that means
#: no single element throttles the model.
MIN_OVER_P1_TARGET = 0.6


@dataclass(frozen=True, slots=True)
class CourantStats(Report):
    """Courant numbers ``C_e = dt c_e / h_e`` of the triangles at a model time step.

    Attributes
    ----------
    dt : float
        The model time step, seconds.
    max, p99, p50 : float
        Largest value, 99th percentile and median, over the triangles with a
        depth.
    at : Place or None
        The triangle with the largest Courant number (its centroid); None if no
        triangle has a depth.
    courant_max, courant_min : float or None
        The limits asked for, if any.
    above, below : int or None
        Triangles with a Courant number above ``courant_max`` and below
        ``courant_min``; None without that limit.
    """

    dt: float
    max: float
    p99: float
    p50: float
    at: Place | None
    courant_max: float | None
    courant_min: float | None
    above: int | None
    below: int | None

    def summary(self) -> str:
        """Return a one-line summary.

        Examples
        --------
        >>> CourantStats(10.0, 1.2, 0.8, 0.3, None, 1.0, None, 4, None).summary()
        'Courant number at dt = 10 s: max 1.2, p99 0.8, median 0.3; 4 above 1'
        """
        where = "" if self.at is None else f" at {self.at.summary()}"
        text = (
            f"Courant number at dt = {self.dt:g} s: max {self.max:.3g}{where}, "
            f"p99 {self.p99:.3g}, median {self.p50:.3g}"
        )
        limits = []
        if self.above is not None:
            limits.append(f"{self.above:,} above {self.courant_max:g}")
        if self.below is not None:
            limits.append(f"{self.below:,} below {self.courant_min:g}")
        return text + ("; " + ", ".join(limits) if limits else "")


#: Elements listed by :attr:`TimeStepStats.slowest`.
SLOWEST = 10


@dataclass(frozen=True, slots=True)
class SlowElement(Report):
    """One of the elements with the smallest stable time step.

    Attributes
    ----------
    at : Place
        The triangle and its centroid (lon/lat where the mesh has a CRS).
    dt : float
        Its stable time step, seconds.
    over_p1 : float
        ``dt`` over the 1st percentile of the mesh's.
    depth : float
        The deepest of its nodes, metres.
    r_in : float
        Its inscribed radius, metres.
    """

    at: Place
    dt: float
    over_p1: float
    depth: float
    r_in: float

    def summary(self) -> str:
        """Return one line.

        Examples
        --------
        >>> SlowElement(Place(7, 0.0, 0.0, -70.3, -22.8), 11.7, 0.27, 30.0,
        ...             54.0).summary()
        'triangle 7 at (-70.3000, -22.8000): 11.7 s (0.27 of p1), depth 30 m, r_in 54 m'
        """
        return (
            f"triangle {self.at.index} at {self.at.summary()}: {self.dt:.3g} s "
            f"({self.over_p1:.2f} of p1), depth {self.depth:.0f} m, "
            f"r_in {self.r_in:.0f} m"
        )


@dataclass(frozen=True, slots=True)
class TimeStepStats(Report):
    """The stable time steps ``dt_e = r_in / c_e`` of the triangles, seconds.

    Attributes
    ----------
    velocity : float
        The velocity scale ``u`` added to the wave speed, m/s.
    min : float
        The largest time step the whole mesh is stable at: the smallest
        ``dt_e`` (inf when no triangle limits it).
    at : Place or None
        The triangle where it occurs (its centroid); None when none limits.
    p1, p50 : float
        1st percentile and median of ``dt_e`` over the triangles that limit it.
    min_over_p1 : float
        ``min / p1``; at least :data:`MIN_OVER_P1_TARGET` (0.6) when no single
        triangle throttles the model.
    dry : int
        Triangles with a wave speed of 0 (no node deeper than 0 m and
        ``velocity`` 0): they limit nothing.
    no_depth : int
        Triangles without a finite depth at any node: left out.
    courant : CourantStats or None
        At the model time step, when one was given.
    min_away_from_corners : float
        ``min`` over the triangles that touch no sharp boundary corner (where the
        geometry, not the mesher, caps the shape); ``min_over_p1_away`` is it
        over ``p1``.
    slowest : tuple of SlowElement
        The :data:`SLOWEST` triangles with the smallest time steps, smallest
        first, with where they are: what to look at when ``min_over_p1`` is
        under its target.
    """

    velocity: float
    min: float
    at: Place | None
    p1: float
    p50: float
    min_over_p1: float
    dry: int
    no_depth: int
    courant: CourantStats | None
    min_away_from_corners: float = math.nan
    min_over_p1_away: float = math.nan
    slowest: tuple[SlowElement, ...] = ()

    def summary(self) -> str:
        """Return a one-line summary (the Courant numbers are their own line).

        Examples
        --------
        >>> TimeStepStats(0.0, 3.0, None, 6.0, 20.0, 0.5, 0, 0, None).summary()
        'stable time step (s): min 3, p1 6, median 20; min / p1 0.50 (target >= 0.6)'
        """
        where = "" if self.at is None else f" at {self.at.summary()}"
        text = (
            f"stable time step (s): min {self.min:.3g}{where}, p1 {self.p1:.3g}, "
            f"median {self.p50:.3g}; min / p1 {self.min_over_p1:.2f} "
            f"(target >= {MIN_OVER_P1_TARGET:g})"
        )
        if self.min_away_from_corners != self.min and not math.isnan(
            self.min_away_from_corners
        ):
            text += (
                f"; away from sharp corners min {self.min_away_from_corners:.3g}, "
                f"/ p1 {self.min_over_p1_away:.2f}"
            )
        if self.velocity:
            text += f"; velocity {self.velocity:g} m/s"
        if self.dry:
            text += f"; {self.dry:,} dry"
        if self.no_depth:
            text += f"; {self.no_depth:,} without depth"
        return text


def element_time_steps(
    mesh: Mesh, *, velocity: float = 0.0, dt: float | None = None
) -> dict[str, NDArray[np.float64]]:
    """Return each triangle's stable time step and, at ``dt``, Courant number.

    Parameters
    ----------
    mesh : Mesh
        With ``point_data["depth"]`` (metres, positive down), in a geographic or
        projected CRS, or planar metres when ``mesh.crs`` is None.
    velocity : float, default 0
        Velocity scale ``u`` added to the wave speed, m/s (>= 0).
    dt : float, optional
        A model time step, seconds (> 0), for the Courant numbers.

    Returns
    -------
    dict of str to ndarray of shape (M,)
        ``"r_in"`` the inscribed radius ``2 A / P`` (metres); ``"mean_edge"`` the
        mean side ``P / 3`` (metres); ``"depth"`` the deepest of the three nodes
        (metres, NaN where none has a finite depth); ``"wave_speed"``
        ``sqrt(g max(d, 0)) + u`` (m/s); ``"dt"`` ``r_in / wave_speed``
        (seconds, inf where the wave speed is 0); and, with ``dt``,
        ``"courant"`` ``dt wave_speed / mean_edge``.

    Raises
    ------
    TypeError
        If ``mesh`` is not a :class:`Mesh`.
    ValueError
        If the mesh has no ``"depth"`` point data (or not one value per node),
        ``velocity`` is negative or ``dt`` not > 0, or the mesh cannot be placed
        on the Earth (see :func:`~coastmesh.meshing.quality.triangle_quality`).

    Notes
    -----
    Sides are measured on the WGS84 ellipsoid as for
    :func:`~coastmesh.meshing.quality.mesh_quality.triangle_quality`; ``g`` is
    :data:`GRAVITY`. The deepest node makes the estimate conservative: the wave
    speed is the fastest the triangle sees. An equilateral triangle of side
    ``L`` has ``r_in = L / (2 sqrt 3)``, so its Courant number at its own stable
    step is ``1 / (2 sqrt 3) = 0.29``.

    Examples
    --------
    >>> m = Mesh([[0, 0], [4, 0], [0, 3]], [[0, 1, 2]], [[0, 1], [1, 2], [2, 0]],
    ...          [1, 1, 1], 1, None, {"depth": [0.0, 9.80665, -2.0]})
    >>> q = element_time_steps(m, velocity=0.19335, dt=2.0)
    >>> [q[k].round(12).tolist() for k in ("r_in", "wave_speed", "dt")]
    [[1.0], [10.0], [0.1]]
    >>> q["courant"].round(12).tolist()
    [5.0]
    """
    if not isinstance(mesh, Mesh):
        raise TypeError(f"mesh is a {type(mesh).__name__}, expected a Mesh")
    depth = node_depth(mesh)
    if depth is None:
        raise ValueError(
            f"mesh.point_data has no 'depth' (it has {sorted(mesh.point_data)}); "
            "add one with mesh.with_point_data(depth=...)"
        )
    check_time_step_options(velocity, dt, None, None)
    xyz, planar = mesh_earth_centred(mesh)
    sides = triangle_measures(xyz, mesh.triangles, planar, ("r_in", "mean_edge"))
    return time_step_arrays(
        sides["r_in"], sides["mean_edge"], depth[mesh.triangles], velocity, dt
    )


def node_depth(mesh: Mesh) -> NDArray[np.float64] | None:
    """Return ``mesh.point_data["depth"]`` as float64 (N,), or None without one."""
    if "depth" not in mesh.point_data:
        return None
    depth = np.asarray(mesh.point_data["depth"], dtype=np.float64)
    if depth.shape != (len(mesh.points),):
        raise ValueError(
            f"mesh.point_data['depth'] has shape {depth.shape}, expected "
            f"({len(mesh.points)},): one depth (metres, positive down) per node"
        )
    return depth


def check_time_step_options(
    velocity: float,
    dt: float | None,
    courant_max: float | None,
    courant_min: float | None,
) -> None:
    """Raise ValueError naming the first option out of range."""
    if not (math.isfinite(velocity) and velocity >= 0):
        raise ValueError(f"velocity = {velocity}: must be a finite speed >= 0 m/s")
    for name, value in (
        ("dt", dt),
        ("courant_max", courant_max),
        ("courant_min", courant_min),
    ):
        if value is not None and not (math.isfinite(value) and value > 0):
            raise ValueError(f"{name} = {value}: must be finite and > 0")
    if courant_max is not None and courant_min is not None:
        if courant_min >= courant_max:
            raise ValueError(
                f"courant_min = {courant_min} must be below courant_max = {courant_max}"
            )
    if dt is None and (courant_max is not None or courant_min is not None):
        raise ValueError("courant_max and courant_min need a model time step dt")


def time_step_arrays(
    r_in: NDArray[np.float64],
    mean_edge: NDArray[np.float64],
    corner_depth: NDArray[np.float64],
    velocity: float,
    dt: float | None,
) -> dict[str, NDArray[np.float64]]:
    """Return the arrays of :func:`element_time_steps` from measured triangles.

    ``corner_depth`` (M, 3) holds the depth at each node of each triangle.
    """
    deepest = np.fmax.reduce(corner_depth, axis=1)  # NaN only where all three are
    speed = wave_speed(deepest, velocity)
    with np.errstate(divide="ignore", invalid="ignore"):
        step = np.where(speed > 0, r_in / speed, np.inf)
        step[np.isnan(speed)] = np.nan
        out = {
            "r_in": r_in,
            "mean_edge": mean_edge,
            "depth": deepest,
            "wave_speed": speed,
            "dt": step,
        }
        if dt is not None:
            out["courant"] = dt * speed / mean_edge
    return out


def time_step_stats(
    mesh: Mesh,
    arrays: dict[str, NDArray[np.float64]],
    *,
    velocity: float,
    dt: float | None,
    courant_max: float | None = None,
    courant_min: float | None = None,
    at_corner: NDArray[np.bool_] | None = None,
) -> TimeStepStats:
    """Summarise :func:`time_step_arrays` of ``mesh`` as a :class:`TimeStepStats`.

    ``at_corner``: the triangles that touch a sharp boundary corner.
    """
    step = arrays["dt"]
    known = ~np.isnan(step)
    limits = np.flatnonzero(known & np.isfinite(step))
    if limits.size:
        first = int(limits[np.argmin(step[limits])])
        low, p1, p50 = float(step[first]), *np.percentile(step[limits], [1, 50])
        at = places(mesh, np.array([first]), triangles=True)[0]
    else:
        low = p1 = p50 = math.inf
        at = None
    courant = None
    if dt is not None:
        courant = _courant_stats(
            mesh, arrays["courant"], known, dt, courant_max, courant_min
        )
    slowest = _slowest(mesh, arrays, limits, float(p1))
    away = math.nan
    if at_corner is not None and limits.size:
        kept = limits[~at_corner[limits]]
        away = float(step[kept].min()) if kept.size else math.inf
    return TimeStepStats(
        min_away_from_corners=away,
        min_over_p1_away=away / float(p1) if limits.size and p1 > 0 else math.nan,
        velocity=float(velocity),
        min=low,
        at=at,
        p1=float(p1),
        p50=float(p50),
        min_over_p1=low / float(p1) if limits.size and p1 > 0 else math.nan,
        dry=int((known & np.isinf(step)).sum()),
        no_depth=int((~known).sum()),
        courant=courant,
        slowest=slowest,
    )


def _slowest(
    mesh: Mesh,
    arrays: dict[str, NDArray[np.float64]],
    limits: NDArray[np.intp],
    p1: float,
) -> tuple[SlowElement, ...]:
    """Return the :data:`SLOWEST` triangles of ``limits`` by time step, with places."""
    if not limits.size:
        return ()
    # stable: of equal steps (a regular grid has many), the lowest index first
    first = limits[np.argsort(arrays["dt"][limits], kind="stable")[:SLOWEST]]
    return tuple(
        SlowElement(
            at=where,
            dt=float(arrays["dt"][t]),
            over_p1=float(arrays["dt"][t]) / p1 if p1 > 0 else math.nan,
            depth=float(arrays["depth"][t]),
            r_in=float(arrays["r_in"][t]),
        )
        for t, where in zip(first, places(mesh, first, triangles=True), strict=True)
    )


def _courant_stats(
    mesh: Mesh,
    courant: NDArray[np.float64],
    known: NDArray[np.bool_],
    dt: float,
    courant_max: float | None,
    courant_min: float | None,
) -> CourantStats:
    values = courant[known]
    if values.size:
        top = int(np.flatnonzero(known)[np.argmax(values)])
        high, p99, p50 = float(courant[top]), *np.percentile(values, [99, 50])
        at = places(mesh, np.array([top]), triangles=True)[0]
    else:
        high = p99 = p50 = math.nan
        at = None
    return CourantStats(
        dt=float(dt),
        max=high,
        p99=float(p99),
        p50=float(p50),
        at=at,
        courant_max=courant_max,
        courant_min=courant_min,
        above=None if courant_max is None else int((values > courant_max).sum()),
        below=None if courant_min is None else int((values < courant_min).sum()),
    )
