"""Checks shared by the readers: the input path, a bounding box, the CRS."""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import Any

import numpy as np
from pyproj import CRS
from pyproj.exceptions import CRSError

from coastmesh.errors import ConfigError, InputDataError

__all__ = ["check_bbox", "check_input", "resolve_crs"]


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

    Examples
    --------
    >>> from coastmesh.data import path as data_path
    >>> check_input(data_path("orkney_gshhg_f.geojson")).endswith(".geojson")
    True
    >>> check_input("/no/such/file.gpkg")
    Traceback (most recent call last):
    ...
    coastmesh.errors.InputDataError: /no/such/file.gpkg: file not found
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
    return minx, miny, maxx, maxy


def resolve_crs(
    stored: CRS | None, crs: Any, path: str | os.PathLike[str]
) -> CRS | None:
    """Return the CRS of what a reader read: the file's own, else the one given.

    Parameters
    ----------
    stored : pyproj.CRS or None
        The CRS the file declares; None if it declares none.
    crs : pyproj.CRS or CRS-like, optional
        The CRS the caller gave (``crs=``), for files that declare none.
    path : str or path-like
        The file, for messages.

    Returns
    -------
    pyproj.CRS or None
        ``stored`` if the file declares one, else ``crs`` (None if neither).

    Raises
    ------
    ConfigError
        If ``crs`` is not a CRS pyproj knows.
    InputDataError
        If the file declares a CRS and ``crs`` is another one.

    Examples
    --------
    >>> resolve_crs(None, "EPSG:4326", "mesh.msh").to_epsg()
    4326
    >>> resolve_crs(CRS.from_epsg(32630), "EPSG:4326", "mesh.nc")
    Traceback (most recent call last):
    ...
    coastmesh.errors.InputDataError: mesh.nc: the file's CRS is EPSG:32630, ...
    """
    try:
        given = None if crs is None else CRS.from_user_input(crs)
    except CRSError as exc:
        raise ConfigError(f"crs={crs!r}: not a CRS pyproj knows ({exc})") from None
    if stored is None or given is None:
        return stored if given is None else given
    if stored != given:
        raise InputDataError(
            f"the file's CRS is {_shown(stored)}, but crs={_shown(given)} was given; "
            "leave crs out (it is for files that declare no CRS)",
            path=os.fspath(path),
        )
    return stored


def _shown(crs: CRS) -> str:
    epsg = crs.to_epsg()
    return f"EPSG:{epsg}" if epsg is not None else repr(crs.name)
