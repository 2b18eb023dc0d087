"""Checks of the PCA parameters.

Shared by the kernels and the pipeline, which checks them before it reads any input.
"""

from __future__ import annotations

import numbers
from collections.abc import Iterable

import numpy as np

from coastmesh.errors import ConfigError

__all__ = ["check_modes", "check_window", "check_window_2d"]


def check_window(window: object, name: str = "window") -> int:
    """Return ``window`` as an int >= 2, or raise naming the parameter."""
    if isinstance(window, bool) or not isinstance(window, numbers.Integral):
        raise ConfigError(f"{name} = {window!r}: must be an integer number of points")
    if window < 2:
        raise ConfigError(
            f"{name} = {window}: must be >= 2 points (a partition needs two points)"
        )
    return int(window)


def check_window_2d(window: object) -> tuple[int, int]:
    """Return a raster window as ``(wy, wx)``; an int means a square window."""
    if isinstance(window, numbers.Integral) and not isinstance(window, bool):
        w = check_window(window)
        return w, w
    bad = f"window = {window!r}: must be an int or a (rows, columns) pair"
    if not isinstance(window, Iterable):
        raise ConfigError(bad)
    try:
        wy, wx = window
    except (TypeError, ValueError):
        raise ConfigError(bad) from None
    return check_window(wy, "window rows"), check_window(wx, "window columns")


def check_modes(modes: object, size: int) -> int:
    """Return ``modes`` as an int in ``[1, size]``, or raise naming the parameter."""
    if isinstance(modes, bool) or not isinstance(modes, numbers.Integral):
        raise ConfigError(f"modes = {modes!r}: must be an integer")
    if not 1 <= int(modes) <= size:
        raise ConfigError(
            f"modes = {modes}: must be between 1 and the partition size ({size})"
        )
    return int(modes)


def deterministic_start(size: int) -> np.ndarray:
    """Start vector for iterative eigensolvers: fixed, so results are reproducible."""
    return np.random.default_rng(20150101).standard_normal(size)
