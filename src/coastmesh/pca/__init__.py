"""Principal component analysis (PCA) approximation of shorelines and bathymetry.

The kernels here take and return numpy arrays only: :func:`simplify_contour` for one
shoreline contour, :func:`simplify_raster` for a bathymetry grid.
:func:`single_threaded_blas` keeps BLAS to one thread where small matrices
make threads cost more than they give.
"""

from __future__ import annotations

from coastmesh.pca.checks import check_modes, check_window, check_window_2d
from coastmesh.pca.grid import raster_modes, simplify_raster
from coastmesh.pca.line import contour_modes, simplify_contour
from coastmesh.pca.threads import single_threaded_blas

__all__ = [
    "check_modes",
    "check_window",
    "check_window_2d",
    "contour_modes",
    "raster_modes",
    "simplify_contour",
    "simplify_raster",
    "single_threaded_blas",
]
