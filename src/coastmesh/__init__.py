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
from coastmesh.pca import simplify_contour, simplify_raster

__version__ = "0.1.0"

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
