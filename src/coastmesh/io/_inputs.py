"""Checks on input paths shared by the readers."""

from __future__ import annotations

import os
from collections.abc import Sequence

import numpy as np

from coastmesh.errors import ConfigError, InputDataError

__all__ = ["check_bbox", "check_input"]


def check_input(path: str | os.PathLike[str]) -> str:
    """Check that an input file exists and can be read; return it as a string.

    GDAL virtual paths (``/vsizip/...``, URLs) and GDAL subdataset names
    (``NETCDF:"file.nc":var``) are passed through unchecked.

    Parameters
    ----------
    path : str or path-like
        The input file.

    Returns
    -------
    str
        The path.

    Raises
    ------
    InputDataError
        If the file does not exist or cannot be read.
    """
    source = os.fspath(path)
    if source.startswith("/vsi") or "://" in source or ':"' in source:
        return source
    if not os.path.exists(source):
        raise InputDataError("file not found", path=source)
    if not os.access(source, os.R_OK):
        raise InputDataError("file cannot be read (permission denied)", path=source)
    return source


def check_bbox(bbox: Sequence[float]) -> tuple[float, float, float, float]:
    """Check a bounding box ``(minx, miny, maxx, maxy)`` and return it as floats.

    Parameters
    ----------
    bbox : sequence of 4 floats
        ``(minx, miny, maxx, maxy)``.

    Returns
    -------
    tuple of 4 floats

    Raises
    ------
    ConfigError
        If there are not 4 finite numbers, or a minimum is not below its maximum.

    Examples
    --------
    >>> check_bbox([-3.5, 58.8, -2.5, 59.2])
    (-3.5, 58.8, -2.5, 59.2)
    """
    try:
        values = tuple(float(v) for v in bbox)
    except (TypeError, ValueError):
        raise ConfigError(
            f"bbox = {bbox!r}: expected 4 numbers minx, miny, maxx, maxy"
        ) from None
    if len(values) != 4 or not np.all(np.isfinite(values)):
        raise ConfigError(
            f"bbox = {bbox!r}: expected 4 finite numbers minx, miny, maxx, maxy"
        )
    minx, miny, maxx, maxy = values
    if minx >= maxx or miny >= maxy:
        raise ConfigError(
            f"bbox = {values}: need minx < maxx and miny < maxy "
            "(order minx, miny, maxx, maxy)"
        )
    return minx, miny, maxx, maxy  # type: ignore[return-value]
