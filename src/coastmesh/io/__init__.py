"""Readers and writers: file names in, coastmesh types out, and back.

=========================  ========================================================
:func:`read_features`      vector layer -> :class:`~coastmesh.types.Features`
:func:`write_features`     :class:`~coastmesh.types.Features` -> vector file
:func:`read_raster`        raster band -> :class:`xarray.DataArray` (``y``, ``x``)
:func:`write_raster`       :class:`xarray.DataArray` -> GeoTIFF or NetCDF
:func:`read_cells`         a window of a raster that :func:`open_raster_source`
                           described (:mod:`coastmesh.io.raster_stream`)
:class:`RasterWriter`      a GeoTIFF written a window at a time
:func:`read_mesh`          msh, fort.14, gr3, UGRID, ... ->
                           :class:`~coastmesh.types.Mesh`
:func:`write_mesh`         :class:`~coastmesh.types.Mesh` -> msh, fort.14, UGRID, ...
:func:`mesh_formats`       the mesh formats, by name, with their readers and writers
:func:`formats_table`      the formats as a Markdown table: what each holds
:func:`write_domain`       :class:`~coastmesh.types.Domain` -> GeoPackage
:func:`write_model_test`   a smoke-test run folder for ADCIRC or SCHISM
                           (:mod:`coastmesh.io.model_tests`)
:func:`write_report`       a report -> JSON (``to_dict()``) and text (``summary()``)
:func:`read_field_source`  a model's results (ANUGA, SCHISM, ADCIRC, UGRID, VTU)
                           -> :class:`FieldSource`, a mesh with values on it
                           (:mod:`coastmesh.io.field_sources`)
:func:`check_on_sphere`    a lon/lat mesh's triangles rebuilt and measured on the
                           sphere (:mod:`coastmesh.io.sphere`, global meshes)
=========================  ========================================================

The submodules are imported on first use, so reading vectors does not import
rasterio and reading rasters does not import pyogrio. Code outside this package
imports from ``coastmesh.io`` only, never from its private modules.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from coastmesh.io._atomic import (
        AtomicOutputs,
        atomic_directory,
        atomic_write,
        check_directory,
        check_output,
    )
    from coastmesh.io._drivers import plot_format, raster_driver, vector_driver
    from coastmesh.io._inputs import check_bbox, check_input
    from coastmesh.io._mesh_format import MeshFormat
    from coastmesh.io._registry import (
        format_for_path,
        formats_table,
        mesh_format,
        mesh_formats,
        read_mesh,
        register_mesh_format,
        write_mesh,
    )
    from coastmesh.io.domain_gpkg import write_domain
    from coastmesh.io.field_sources import FieldSource, read_field_source
    from coastmesh.io.model_tests import write_model_test
    from coastmesh.io.msh import read_msh, write_msh
    from coastmesh.io.raster import raster_transform, read_raster, write_raster
    from coastmesh.io.raster_stream import (
        RasterSource,
        RasterWriter,
        encode_cells,
        open_raster_source,
        read_cells,
        read_decimated,
    )
    from coastmesh.io.report import write_report
    from coastmesh.io.sphere import SphereCheck, check_on_sphere
    from coastmesh.io.vector import read_features, write_features

__all__ = [
    "AtomicOutputs",
    "FieldSource",
    "MeshFormat",
    "RasterSource",
    "RasterWriter",
    "SphereCheck",
    "atomic_directory",
    "atomic_write",
    "check_bbox",
    "check_directory",
    "check_input",
    "check_on_sphere",
    "check_output",
    "encode_cells",
    "format_for_path",
    "formats_table",
    "mesh_format",
    "mesh_formats",
    "open_raster_source",
    "plot_format",
    "raster_driver",
    "raster_transform",
    "read_cells",
    "read_decimated",
    "read_features",
    "read_field_source",
    "read_mesh",
    "read_msh",
    "read_raster",
    "register_mesh_format",
    "vector_driver",
    "write_domain",
    "write_features",
    "write_mesh",
    "write_model_test",
    "write_msh",
    "write_raster",
    "write_report",
]

_HOME = {
    "AtomicOutputs": "coastmesh.io._atomic",
    "atomic_directory": "coastmesh.io._atomic",
    "atomic_write": "coastmesh.io._atomic",
    "check_directory": "coastmesh.io._atomic",
    "check_output": "coastmesh.io._atomic",
    "check_bbox": "coastmesh.io._inputs",
    "check_input": "coastmesh.io._inputs",
    "plot_format": "coastmesh.io._drivers",
    "raster_driver": "coastmesh.io._drivers",
    "vector_driver": "coastmesh.io._drivers",
    "read_features": "coastmesh.io.vector",
    "write_features": "coastmesh.io.vector",
    "raster_transform": "coastmesh.io.raster",
    "read_raster": "coastmesh.io.raster",
    "write_raster": "coastmesh.io.raster",
    "RasterSource": "coastmesh.io.raster_stream",
    "RasterWriter": "coastmesh.io.raster_stream",
    "encode_cells": "coastmesh.io.raster_stream",
    "open_raster_source": "coastmesh.io.raster_stream",
    "read_cells": "coastmesh.io.raster_stream",
    "read_decimated": "coastmesh.io.raster_stream",
    "read_msh": "coastmesh.io.msh",
    "write_msh": "coastmesh.io.msh",
    "MeshFormat": "coastmesh.io._mesh_format",
    "format_for_path": "coastmesh.io._registry",
    "formats_table": "coastmesh.io._registry",
    "mesh_format": "coastmesh.io._registry",
    "mesh_formats": "coastmesh.io._registry",
    "read_mesh": "coastmesh.io._registry",
    "register_mesh_format": "coastmesh.io._registry",
    "write_mesh": "coastmesh.io._registry",
    "write_domain": "coastmesh.io.domain_gpkg",
    "FieldSource": "coastmesh.io.field_sources",
    "read_field_source": "coastmesh.io.field_sources",
    "write_model_test": "coastmesh.io.model_tests",
    "write_report": "coastmesh.io.report",
    "SphereCheck": "coastmesh.io.sphere",
    "check_on_sphere": "coastmesh.io.sphere",
}


def __getattr__(name: str) -> Any:
    if name in _HOME:
        return getattr(importlib.import_module(_HOME[name]), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(list(globals()) + __all__)
