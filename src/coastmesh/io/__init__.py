"""Readers and writers: file names in, coastmesh types out, and back.

=====================  ==========================================================
:func:`read_features`  vector layer -> :class:`~coastmesh.types.Features`
:func:`write_features` :class:`~coastmesh.types.Features` -> vector file
:func:`read_raster`    raster band -> :class:`xarray.DataArray` (``y``, ``x``)
:func:`write_raster`   :class:`xarray.DataArray` -> GeoTIFF or NetCDF
=====================  ==========================================================

The submodules are imported on first use, so reading vectors does not import
rasterio and reading rasters does not import pyogrio.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from coastmesh.io._inputs import check_bbox
    from coastmesh.io.msh import read_msh, write_msh
    from coastmesh.io.raster import read_raster, write_raster
    from coastmesh.io.vector import read_features, write_features

__all__ = [
    "check_bbox",
    "read_features",
    "read_msh",
    "read_raster",
    "write_features",
    "write_msh",
    "write_raster",
]

_HOME = {
    "check_bbox": "coastmesh.io._inputs",
    "read_features": "coastmesh.io.vector",
    "write_features": "coastmesh.io.vector",
    "read_raster": "coastmesh.io.raster",
    "write_raster": "coastmesh.io.raster",
    "read_msh": "coastmesh.io.msh",
    "write_msh": "coastmesh.io.msh",
}


def __getattr__(name: str) -> Any:
    if name in _HOME:
        return getattr(importlib.import_module(_HOME[name]), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(list(globals()) + __all__)
