"""coastmesh: shorelines and bathymetry to meshes for tidal and coastal ocean models.

The public API:

==============================  ================================================
:func:`build_case`              a case (file, TOML text or :class:`CaseConfig`)
                                -> :class:`CaseResult` in memory, nothing written
:func:`run_case`                build, then write what ``coastmesh run`` writes
:func:`read_case`               a case file -> :class:`CaseConfig`
:func:`dump_case`               a :class:`CaseConfig` -> case-file text
:func:`read_mesh`               a mesh file (msh, fort.14, gr3, UGRID, ...)
                                -> :class:`Mesh`
:func:`write_mesh`              a :class:`Mesh` -> any registered format
:func:`mesh_formats`            the mesh formats, by name
:func:`simplify_contour`        PCA of one shoreline contour
:func:`simplify_raster`         PCA of a raster in 2-D windows
:class:`Mesh`, :class:`Domain`, the core types (:mod:`coastmesh.types`)
:class:`BoundarySegment`,
:class:`SizeGrid`,
:class:`Features`
:mod:`coastmesh.data`           the bundled real data sets
==============================  ================================================

The stages are subpackages, each usable on its own: :mod:`coastmesh.pca`,
:mod:`coastmesh.geometry`, :mod:`coastmesh.sizing`, :mod:`coastmesh.meshing`,
:mod:`coastmesh.io`, :mod:`coastmesh.plot`, :mod:`coastmesh.case`,
:mod:`coastmesh.commands`. Importing coastmesh imports neither gmsh,
matplotlib nor rasterio: names and subpackages (``coastmesh.io``, ...) are
loaded on first use (PEP 562).
"""

from __future__ import annotations

import importlib

from coastmesh.errors import (
    CoastmeshError,
    CoastmeshWarning,
    ConfigError,
    FormatError,
    InputDataError,
    MeshingError,
    OutputExistsError,
)
from coastmesh.version import __version__

# typing.TYPE_CHECKING without importing typing (8 ms): `import coastmesh` stays
# quick for the command line
TYPE_CHECKING = False
if TYPE_CHECKING:
    from typing import Any

    from coastmesh import data
    from coastmesh.case import (
        CaseConfig,
        CaseResult,
        build_case,
        dump_case,
        read_case,
        run_case,
    )
    from coastmesh.io import mesh_formats, read_mesh, write_mesh
    from coastmesh.pca import simplify_contour, simplify_raster
    from coastmesh.types import BoundarySegment, Domain, Features, Mesh, SizeGrid


_LAZY = {
    "CaseConfig": "coastmesh.case",
    "CaseResult": "coastmesh.case",
    "build_case": "coastmesh.case",
    "dump_case": "coastmesh.case",
    "read_case": "coastmesh.case",
    "run_case": "coastmesh.case",
    "mesh_formats": "coastmesh.io",
    "read_mesh": "coastmesh.io",
    "write_mesh": "coastmesh.io",
    "simplify_contour": "coastmesh.pca",
    "simplify_raster": "coastmesh.pca",
    "BoundarySegment": "coastmesh.types",
    "Domain": "coastmesh.types",
    "Features": "coastmesh.types",
    "Mesh": "coastmesh.types",
    "SizeGrid": "coastmesh.types",
}
#: subpackages reachable as attributes after ``import coastmesh`` alone
_SUBMODULES = (
    "case",
    "commands",
    "data",
    "geometry",
    "io",
    "meshing",
    "pca",
    "plot",
    "sizing",
    "types",
)

__all__ = [
    "BoundarySegment",
    "CaseConfig",
    "CaseResult",
    "CoastmeshError",
    "CoastmeshWarning",
    "ConfigError",
    "Domain",
    "Features",
    "FormatError",
    "InputDataError",
    "Mesh",
    "MeshingError",
    "OutputExistsError",
    "SizeGrid",
    "__version__",
    "build_case",
    "data",
    "dump_case",
    "mesh_formats",
    "read_case",
    "read_mesh",
    "run_case",
    "simplify_contour",
    "simplify_raster",
    "write_mesh",
]


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return getattr(importlib.import_module(_LAZY[name]), name)
    if name in _SUBMODULES:
        return importlib.import_module(f"coastmesh.{name}")
    raise AttributeError(f"module 'coastmesh' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
