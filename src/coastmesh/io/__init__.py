"""Readers and writers: file names in, coastmesh types out, and back.

=========================  ========================================================
:func:`read_features`      vector layer -> :class:`~coastmesh.types.Features`
:func:`write_features`     :class:`~coastmesh.types.Features` -> vector file
:func:`read_raster`        raster band -> :class:`xarray.DataArray` (``y``, ``x``)
:func:`write_raster`       :class:`xarray.DataArray` -> GeoTIFF or NetCDF
:func:`read_cells`         a window of a raster that :func:`open_raster_source`
                           described (:mod:`coastmesh.io.rasters.raster_stream`)
:class:`RasterWriter`      a GeoTIFF written a window at a time
:func:`read_mesh`          msh, fort.14, gr3, UGRID, ... ->
                           :class:`~coastmesh.types.Mesh`
:func:`write_mesh`         :class:`~coastmesh.types.Mesh` -> msh, fort.14, UGRID, ...
:func:`mesh_formats`       the mesh formats, by name, with their readers and writers
:func:`formats_table`      the formats as a Markdown table: what each holds
:func:`write_domain`       :class:`~coastmesh.types.Domain` -> GeoPackage
:func:`write_model_test`   a smoke-test run folder for ADCIRC or SCHISM
                           (:mod:`coastmesh.io.meshes.model_tests`)
:func:`write_report`       a report -> JSON (``to_dict()``) and text (``summary()``)
:func:`read_field_source`  a model's results (ANUGA, SCHISM, ADCIRC, UGRID, VTU)
                           -> :class:`FieldSource`, a mesh with values on it
                           (:mod:`coastmesh.io.fields.field_sources`)
:func:`check_on_sphere`    a lon/lat mesh's triangles rebuilt and measured on the
                           sphere (:mod:`coastmesh.io.meshes.sphere`, global meshes)
=========================  ========================================================

The modules, in subpackages by what they read and write:

=================  ===================================================================
:mod:`.fields`     fields to size by: a model's results, and values on a size grid
:mod:`.meshes`     the mesh format registry, one module per format, the model tests
:mod:`.rasters`    rasters: whole, a window of rows at a time, the window points need
:mod:`.vectors`    vector layers, and the domain GeoPackage
(here)             shared: ``_atomic``, ``_inputs``, ``_drivers``, ``_cf``, ``report``
=================  ===================================================================

A row uses only the rows below it (meshes use vectors but not rasters; rasters
and vectors use neither the other): an import-linter contract in
``pyproject.toml`` keeps it so.

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
    from coastmesh.io.fields.field_sources import FieldSource, read_field_source
    from coastmesh.io.meshes._mesh_format import MeshFormat
    from coastmesh.io.meshes._registry import (
        format_for_path,
        formats_table,
        mesh_format,
        mesh_formats,
        read_mesh,
        register_mesh_format,
        write_mesh,
    )
    from coastmesh.io.meshes.model_tests import write_model_test
    from coastmesh.io.meshes.msh import read_msh, write_msh
    from coastmesh.io.meshes.sphere import SphereCheck, check_on_sphere
    from coastmesh.io.rasters.raster import raster_transform, read_raster, write_raster
    from coastmesh.io.rasters.raster_stream import (
        RasterSource,
        RasterWriter,
        encode_cells,
        open_raster_source,
        read_cells,
        read_decimated,
    )
    from coastmesh.io.report import write_report
    from coastmesh.io.vectors.domain_gpkg import write_domain
    from coastmesh.io.vectors.vector import read_features, write_features

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
    "read_features": "coastmesh.io.vectors.vector",
    "write_features": "coastmesh.io.vectors.vector",
    "raster_transform": "coastmesh.io.rasters.raster",
    "read_raster": "coastmesh.io.rasters.raster",
    "write_raster": "coastmesh.io.rasters.raster",
    "RasterSource": "coastmesh.io.rasters.raster_stream",
    "RasterWriter": "coastmesh.io.rasters.raster_stream",
    "encode_cells": "coastmesh.io.rasters.raster_stream",
    "open_raster_source": "coastmesh.io.rasters.raster_stream",
    "read_cells": "coastmesh.io.rasters.raster_stream",
    "read_decimated": "coastmesh.io.rasters.raster_stream",
    "read_msh": "coastmesh.io.meshes.msh",
    "write_msh": "coastmesh.io.meshes.msh",
    "MeshFormat": "coastmesh.io.meshes._mesh_format",
    "format_for_path": "coastmesh.io.meshes._registry",
    "formats_table": "coastmesh.io.meshes._registry",
    "mesh_format": "coastmesh.io.meshes._registry",
    "mesh_formats": "coastmesh.io.meshes._registry",
    "read_mesh": "coastmesh.io.meshes._registry",
    "register_mesh_format": "coastmesh.io.meshes._registry",
    "write_mesh": "coastmesh.io.meshes._registry",
    "write_domain": "coastmesh.io.vectors.domain_gpkg",
    "FieldSource": "coastmesh.io.fields.field_sources",
    "read_field_source": "coastmesh.io.fields.field_sources",
    "write_model_test": "coastmesh.io.meshes.model_tests",
    "write_report": "coastmesh.io.report",
    "SphereCheck": "coastmesh.io.meshes.sphere",
    "check_on_sphere": "coastmesh.io.meshes.sphere",
}


def __getattr__(name: str) -> Any:
    if name in _HOME:
        return getattr(importlib.import_module(_HOME[name]), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(list(globals()) + __all__)
