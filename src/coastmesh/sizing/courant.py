"""The Courant number: sizes a model runs at its time step, and what they did.

A model run at time step ``dt`` has Courant number ``C = dt (sqrt(g d) + u) / h``
in an element of size ``h`` in water ``d`` deep, with flow speed ``u``.
:func:`courant_bounds` gives the sizes that keep ``C`` between ``courant_min``
and ``courant_max``: a floor (explicit models blow up above ``courant_max``;
ADCIRC asks for about 0.5 to 0.9) and a cap (SCHISM asks for 0.4 or more).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from coastmesh.geometry.earth import GRAVITY
from coastmesh.types import Report

__all__ = ["CourantReport", "courant_bounds", "round_step", "wave_speed"]


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
    auto : bool
        ``dt`` was worked out from the field (``dt = "auto"``).
    """

    dt: float
    velocity: float
    courant_min: float | None
    courant_max: float | None
    raised_km2: float
    lowered_km2: float
    unmet_km2: float
    auto: bool = False

    def summary(self) -> str:
        """Return a one-line summary."""
        window = (
            f"{self.courant_min if self.courant_min is not None else 0:g} to "
            f"{self.courant_max if self.courant_max is not None else 'inf'}"
        )
        return (
            f"Courant {window} at dt {self.dt:g} s"
            f"{' (auto)' if self.auto else ''} (u {self.velocity:g} m/s): "
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
    depth: NDArray[np.float64],
    *,
    dt: float,
    courant_max: float | None,
    courant_min: float | None = None,
    velocity: float = 1.0,
    min_depth: float = 1.0,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Return the sizes (floor, cap) that keep the Courant number in its window.

    Parameters
    ----------
    depth : ndarray
        Depth, metres, positive down (raised to ``min_depth``; land too).
    dt : float
        The model's time step, seconds.
    courant_max, courant_min : float or None
        The window; None for no bound.
    velocity : float
        The flow speed added to the wave speed, m/s.
    min_depth : float
        Depths below this are taken as this, metres.

    Returns
    -------
    floor, cap : ndarray
        ``dt (sqrt(g d) + u) / courant_max`` (0 without ``courant_max``) and
        ``dt (sqrt(g d) + u) / courant_min`` (inf without ``courant_min``).

    Examples
    --------
    >>> floor, cap = courant_bounds(np.array([100 / GRAVITY]), dt=10.0,
    ...                             courant_max=0.5, courant_min=0.25, velocity=0.0)
    >>> floor.round(6).tolist(), cap.round(6).tolist()
    ([200.0], [400.0])
    """
    speed = dt * wave_speed(np.maximum(depth, min_depth), velocity)
    floor = np.zeros_like(speed) if courant_max is None else speed / courant_max
    no_cap = np.full_like(speed, np.inf)
    cap = no_cap if courant_min is None else speed / courant_min
    return floor, cap


def round_step(seconds: float) -> float:
    """Round a time step down to two significant figures (a step a model takes).

    Examples
    --------
    >>> round_step(5.678), round_step(0.1234), round_step(123.0)
    (5.6, 0.12, 120.0)
    """
    if not (math.isfinite(seconds) and seconds > 0):
        return seconds
    digits = 1 - math.floor(math.log10(seconds))
    scale: float = 10**digits  # an int, or a float for digits < 0
    return round(math.floor(seconds * scale + 1e-9) / scale, max(digits, 0))
