"""Principal component analysis (PCA) approximation of shorelines and bathymetry.

The kernels here take and return numpy arrays only: :func:`simplify_contour` for one
shoreline contour, :func:`simplify_contours` and :func:`simplify_packed` for many
(small ones batched, spread over threads), :func:`simplify_raster` for a
bathymetry grid; :func:`chunk_gram`, :func:`chunk_modes` and :func:`chunk_rebuild`
are its two passes one chunk of the grid at a time, for grids computed out of core.
:func:`single_threaded_blas` keeps BLAS to one thread where small matrices
make threads cost more than they give.
"""

from __future__ import annotations

from coastmesh.pca.batch import check_workers, simplify_contours, simplify_packed
from coastmesh.pca.checks import check_modes, check_window, check_window_2d
from coastmesh.pca.chunks import chunk_gram, chunk_modes, chunk_rebuild
from coastmesh.pca.grid import raster_modes, simplify_raster
from coastmesh.pca.line import contour_modes, simplify_contour
from coastmesh.pca.threads import single_threaded_blas

__all__ = [
    "check_modes",
    "check_window",
    "check_window_2d",
    "check_workers",
    "chunk_gram",
    "chunk_modes",
    "chunk_rebuild",
    "contour_modes",
    "raster_modes",
    "simplify_contour",
    "simplify_contours",
    "simplify_packed",
    "simplify_raster",
    "single_threaded_blas",
]
