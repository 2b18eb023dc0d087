"""coastmesh: shorelines and bathymetry to meshes for tidal and coastal ocean models.

The public API is re-exported here. Importing coastmesh imports neither gmsh,
matplotlib nor rasterio.
"""

from __future__ import annotations

from coastmesh.errors import (
    CoastmeshError,
    CoastmeshWarning,
    ConfigError,
    FormatError,
    InputDataError,
    MeshingError,
    OutputExistsError,
)

__version__ = "0.1.0"

# The kernels pull in scipy (0.3 s); load them on first use so that the command
# line's --help and the error classes stay quick to import (PEP 562).
_LAZY = {"simplify_contour": "coastmesh.pca", "simplify_raster": "coastmesh.pca"}


def __getattr__(name: str):
    if name in _LAZY:
        import importlib

        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'coastmesh' has no attribute {name!r}")


__all__ = [
    "CoastmeshError",
    "CoastmeshWarning",
    "ConfigError",
    "FormatError",
    "InputDataError",
    "MeshingError",
    "OutputExistsError",
    "__version__",
    "simplify_contour",
    "simplify_raster",
]
