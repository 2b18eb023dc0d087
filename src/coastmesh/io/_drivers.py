"""GDAL drivers and plot formats, by file extension.

Readers let GDAL detect the format of an input file; the vector and raster writers
pick the GDAL driver, and the plots their matplotlib format, from the output
file's extension through these tables. Mesh formats have a registry of their own,
for reading and writing (:mod:`coastmesh.io.meshes._registry`).
"""

from __future__ import annotations

import os
from pathlib import Path

from coastmesh.errors import FormatError

__all__ = [
    "PLOT_FORMATS",
    "RASTER_DRIVERS",
    "VECTOR_DRIVERS",
    "plot_format",
    "raster_driver",
    "vector_driver",
]

VECTOR_DRIVERS: dict[str, str] = {
    ".gpkg": "GPKG",
    ".shp": "ESRI Shapefile",
    ".geojson": "GeoJSON",
    ".json": "GeoJSON",
    ".fgb": "FlatGeobuf",
}
RASTER_DRIVERS: dict[str, str] = {
    ".tif": "GTiff",
    ".tiff": "GTiff",
    ".nc": "netCDF",
}
PLOT_FORMATS: dict[str, str] = {
    ".png": "png",
    ".pdf": "pdf",
    ".svg": "svg",
    ".jpg": "jpeg",
    ".jpeg": "jpeg",
}


def vector_driver(path: str | os.PathLike[str]) -> str:
    """Return the GDAL vector driver that writes ``path``, such as ``"GPKG"``.

    Parameters
    ----------
    path : str or path-like
        The output file; its extension (any case) is looked up in
        :data:`VECTOR_DRIVERS`.

    Returns
    -------
    str

    Raises
    ------
    FormatError
        If the extension is not a vector format; the message lists the known ones.

    Examples
    --------
    >>> vector_driver("coast.gpkg")
    'GPKG'
    """
    return _lookup(path, VECTOR_DRIVERS, "vector")


def raster_driver(path: str | os.PathLike[str]) -> str:
    """Return ``"GTiff"`` or ``"netCDF"``: the GDAL driver that writes ``path``.

    See :func:`vector_driver`; the table is :data:`RASTER_DRIVERS`.

    Examples
    --------
    >>> raster_driver("depth.nc")
    'netCDF'
    """
    return _lookup(path, RASTER_DRIVERS, "raster")


def plot_format(path: str | os.PathLike[str]) -> str:
    """Return the matplotlib format that saves a figure to ``path``.

    See :func:`vector_driver`; the table is :data:`PLOT_FORMATS`.

    Examples
    --------
    >>> plot_format("overlay.PNG")
    'png'
    """
    return _lookup(path, PLOT_FORMATS, "plot")


def _lookup(path: str | os.PathLike[str], table: dict[str, str], kind: str) -> str:
    suffix = Path(path).suffix.lower()
    try:
        return table[suffix]
    except KeyError:
        known = ", ".join(sorted(table))
        shown = f"extension {suffix!r}" if suffix else "no extension"
        raise FormatError(
            f"{os.fspath(path)}: unknown {kind} format ({shown}); pick one of {known}"
        ) from None
