"""One Gmsh session: options, the size field as a background view, cleanup.

Gmsh keeps process-global state, so :func:`gmsh_session` holds a lock for the
whole session and always finalises; every Gmsh model coastmesh builds, in this
process or in a worker (:mod:`coastmesh.meshing.parts.tasks`), is set up here, with
the same options, so a part meshed anywhere is meshed the same way.
"""

from __future__ import annotations

import ctypes
import functools
import logging
import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy import ndimage

from coastmesh.errors import MeshingError
from coastmesh.types import SizeGrid

__all__ = [
    "ALGORITHMS",
    "add_size_view",
    "crop_grid",
    "gmsh_session",
    "grid_view_data",
    "release_memory",
    "set_options",
]

logger = logging.getLogger("coastmesh.meshing.engine")

#: Gmsh 2D algorithms by name (the ``Mesh.Algorithm`` option).
ALGORITHMS = {"meshadapt": 1, "automatic": 2, "delaunay": 5, "frontal-delaunay": 6}

_LOCK = threading.Lock()
# Relative precision of Gmsh's integral of 1/h along each curve (boundary nodes).
_INTEGRATION_PRECISION = 1e-4


@contextmanager
def gmsh_session() -> Iterator[Any]:
    """Initialise Gmsh, route its messages to our logger, and always finalise.

    Yields
    ------
    module
        The ``gmsh`` module, initialised with an empty model.
    """
    import gmsh

    with _LOCK:
        if gmsh.isInitialized():
            raise MeshingError(
                "Gmsh is already initialised in this process by other code; "
                "coastmesh needs it to itself"
            )
        pipe = signal.getsignal(signal.SIGPIPE) if hasattr(signal, "SIGPIPE") else None
        gmsh.initialize(readConfigFiles=False, run=False, interruptible=False)
        if pipe is not None and threading.current_thread() is threading.main_thread():
            # Gmsh resets SIGPIPE to its default (end the process) behind
            # Python's back: a worker of ours that died would then kill this
            # process when it wrote to its pipe, instead of raising
            signal.signal(signal.SIGPIPE, pipe)
        try:
            gmsh.option.setNumber("General.Terminal", 0)
            gmsh.logger.start()
            gmsh.model.add("coastmesh")
            yield gmsh
        finally:
            for line in gmsh.logger.get():
                if line.startswith(("Warning", "Error")):
                    logger.warning("gmsh: %s", line)
                else:
                    logger.debug("gmsh: %s", line)
            gmsh.logger.stop()
            gmsh.finalize()
            release_memory()


def release_memory() -> None:
    """Give the heap memory freed so far back to the system (glibc only).

    glibc keeps freed pages for later: a worker that finalised a Gmsh model
    of 1.5 M triangles then holds hundreds of megabytes it does not use
    through the cleanup that follows, and so does the main process after the
    shoreline sets. ``malloc_trim`` returns them (as Dask's workers do for
    unmanaged memory). Elsewhere this does nothing.
    """
    trim = _malloc_trim()
    if trim is not None:
        trim(0)


@functools.cache
def _malloc_trim() -> Any:
    try:
        return ctypes.CDLL("libc.so.6").malloc_trim
    except (OSError, AttributeError):  # not glibc
        return None


def set_options(gmsh: Any, *, threads: int, seed: int, algorithm: str) -> None:
    """Set the options every coastmesh model is meshed with."""
    for name, value in (
        ("General.NumThreads", threads),
        ("Mesh.MaxNumThreads1D", threads),
        ("Mesh.MaxNumThreads2D", threads),
        ("Mesh.RandomSeed", int(seed)),
        ("Mesh.Algorithm", ALGORITHMS[algorithm]),
        ("Mesh.MeshSizeFromPoints", 0),
        ("Mesh.MeshSizeFromCurvature", 0),
        ("Mesh.MeshSizeExtendFromBoundary", 0),
        # 1e-9 (the default) makes 1D meshing of long splines 100 times slower
        ("Mesh.LcIntegrationPrecision", _INTEGRATION_PRECISION),
    ):
        gmsh.option.setNumber(name, value)


def add_size_view(
    gmsh: Any,
    size: SizeGrid,
    bounds: tuple[float, ...],
    near: NDArray[np.float64] | None = None,
) -> None:
    """Make the size grid, padded to ``bounds``, Gmsh's background mesh size.

    With ``near`` (points, (k, 2)), only the cells holding a point and the
    cells around them (:func:`grid_view_data`) go into the view: Gmsh then
    sizes right only there (elsewhere its field gives no size).
    """
    view = gmsh.view.add("size")
    if isinstance(size, SizeGrid):
        data = grid_view_data(size, bounds, None if size.patches else near)
        gmsh.view.addListData(view, "SQ", len(data) // 16, data)
    else:  # a SphereSizeGrid: its cells, moved into the plane
        for kind, data in size.view_data(bounds, near).items():
            per = 16 if kind == "SQ" else 12
            if len(data):
                gmsh.view.addListData(view, kind, len(data) // per, data)
    field = gmsh.model.mesh.field.add("PostView")
    gmsh.model.mesh.field.setNumber(field, "ViewTag", view)
    gmsh.model.mesh.field.setAsBackgroundMesh(field)
    # build the view's search structure on one thread (Gmsh: lazily, in-loop)
    at = (bounds[0], bounds[1]) if near is None or not len(near) else near[0]
    gmsh.view.probe(view, float(at[0]), float(at[1]), 0.0)


def grid_view_data(
    size: SizeGrid,
    bounds: tuple[float, ...],
    near: NDArray[np.float64] | None = None,
) -> NDArray[np.float64]:
    """Quadrangles of the size grid, padded to ``bounds``, in Gmsh list format.

    Each cell is 16 numbers: its corners' x, y, z (0) and values,
    counter-clockwise from its lower left. All cells in row order, or with
    ``near`` (points, (k, 2)) only those holding a point or next to one
    (the 3 x 3 cells around each point's cell), in row order: a point within
    one cell's width of a point of ``near`` lies in one of them.
    """
    x, y, v = _padded(size, bounds)
    ny, nx = len(y) - 1, len(x) - 1
    corners = [(0, 0), (0, 1), (1, 1), (1, 0)]  # (dj, di), counter-clockwise
    if near is None:
        cells = _quads(x, y, v)
        if not size.patches:
            # gmsh's Python API takes a contiguous float64 array as it is
            return cells.ravel()
        # a finer patch's cells stand for the cells it covers
        grids = [cells.reshape(-1, 16)] + [
            _quads(p.x, p.y, p.values).reshape(-1, 16) for p in size.patches
        ]
        steps = [np.inf] + [float(p.x[1] - p.x[0]) for p in size.patches]
        kept = []
        for g, quads in enumerate(grids):
            keep = np.ones(len(quads), dtype=bool)
            for p, patch in enumerate(size.patches, start=1):
                if steps[p] < steps[g]:
                    keep &= ~(
                        (quads[:, 0] >= patch.x[0])
                        & (quads[:, 1] <= patch.x[-1])
                        & (quads[:, 4] >= patch.y[0])
                        & (quads[:, 6] <= patch.y[-1])
                    )
            kept.append(quads[keep].ravel())
        return np.concatenate(kept)
    near = np.asarray(near, dtype=np.float64).reshape(-1, 2)
    hit = np.zeros((ny, nx), dtype=bool)
    i = np.clip(np.searchsorted(x, near[:, 0], side="right") - 1, 0, nx - 1)
    j = np.clip(np.searchsorted(y, near[:, 1], side="right") - 1, 0, ny - 1)
    hit[j, i] = True
    j, i = np.nonzero(ndimage.binary_dilation(hit, np.ones((3, 3), dtype=bool)))
    cells = np.zeros((len(j), 16))
    for k, (dj, di) in enumerate(corners):
        cells[:, k] = x[i + di]
        cells[:, 4 + k] = y[j + dj]
        cells[:, 12 + k] = v[j + dj, i + di]
    return cells.ravel()


def _quads(
    x: NDArray[np.float64], y: NDArray[np.float64], v: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Return the cells of a grid as (ny - 1, nx - 1, 16) Gmsh list quadrangles."""
    ny, nx = len(y) - 1, len(x) - 1
    cells = np.zeros((ny, nx, 16))
    for k, (dj, di) in enumerate([(0, 0), (0, 1), (1, 1), (1, 0)]):
        cells[:, :, k] = x[di : di + nx]
        cells[:, :, 4 + k] = y[dj : dj + ny, None]
        cells[:, :, 12 + k] = v[dj : dj + ny, di : di + nx]
    return cells


def _cut_patch(
    patch: SizeGrid, x: NDArray[np.float64], y: NDArray[np.float64]
) -> SizeGrid | None:
    """Return ``patch`` within the frame of axes ``x``, ``y``; None outside it."""
    x0, x1 = max(patch.x[0], x[0]), min(patch.x[-1], x[-1])
    y0, y1 = max(patch.y[0], y[0]), min(patch.y[-1], y[-1])
    if x0 >= x1 or y0 >= y1:
        return None
    i = (patch.x >= x0) & (patch.x <= x1)
    j = (patch.y >= y0) & (patch.y <= y1)
    return SizeGrid(patch.x[i], patch.y[j], patch.values[np.ix_(j, i)])


def _padded(
    size: SizeGrid, bounds: tuple[float, ...]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Return the grid's x, y and values, a row or column more where ``bounds`` pass."""
    minx, miny, maxx, maxy = bounds
    pad = 0.01 * max(maxx - minx, maxy - miny) + 1.0
    x, y, v = size.x, size.y, size.values
    if minx - pad < x[0]:
        x, v = np.concatenate([[minx - pad], x]), np.hstack([v[:, :1], v])
    if maxx + pad > x[-1]:
        x, v = np.concatenate([x, [maxx + pad]]), np.hstack([v, v[:, -1:]])
    if miny - pad < y[0]:
        y, v = np.concatenate([[miny - pad], y]), np.vstack([v[:1], v])
    if maxy + pad > y[-1]:
        y, v = np.concatenate([y, [maxy + pad]]), np.vstack([v, v[-1:]])
    return x, y, v


def crop_grid(grid: SizeGrid, bounds: tuple[float, ...], margin: int = 2) -> SizeGrid:
    """Return the part of ``grid`` covering ``bounds``, ``margin`` cells wider.

    Inside ``bounds`` it interpolates exactly as ``grid`` does: the cells there
    are the same cells.

    Examples
    --------
    >>> g = SizeGrid(np.arange(10.0), np.arange(5.0), np.ones((5, 10)))
    >>> c = crop_grid(g, (3.5, 1.0, 5.5, 2.0), margin=1)
    >>> c.x.tolist(), c.y.tolist()
    ([2.0, 3.0, 4.0, 5.0, 6.0, 7.0], [0.0, 1.0, 2.0, 3.0])
    """
    if not isinstance(grid, SizeGrid):  # a SphereSizeGrid is kept whole
        return grid
    x0, y0, x1, y1 = bounds
    i0 = max(int(np.searchsorted(grid.x, x0, side="right")) - 1 - margin, 0)
    i1 = min(int(np.searchsorted(grid.x, x1, side="left")) + 1 + margin, len(grid.x))
    j0 = max(int(np.searchsorted(grid.y, y0, side="right")) - 1 - margin, 0)
    j1 = min(int(np.searchsorted(grid.y, y1, side="left")) + 1 + margin, len(grid.y))
    i1, j1 = max(i1, i0 + 2), max(j1, j0 + 2)
    i0, j0 = min(i0, len(grid.x) - 2), min(j0, len(grid.y) - 2)
    x, y = grid.x[i0:i1], grid.y[j0:j1]
    # each patch cut to the crop: the crop's frame is on nodes of this grid,
    # and so on nodes of every patch (a patch's cells split this grid's)
    patches = tuple(
        cut for p in grid.patches if (cut := _cut_patch(p, x, y)) is not None
    )
    return SizeGrid(x, y, grid.values[j0:j1, i0:i1], patches=patches)
