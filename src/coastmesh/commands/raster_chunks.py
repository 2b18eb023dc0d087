"""The chunks of a streamed raster, and the two tasks run on each.

:func:`plan_chunks` cuts a grid into chunks, rectangles of whole output tiles:
whole rows of the grid if they fit the memory budget, else squares. A task
holds its chunk and the overlap, at most about ``_BYTES_PER_CELL`` bytes a cell;
the chunks are as large as the budget allows. They depend on the grid, the
window and the budget, never on the workers.
:func:`gram_task` and :func:`rebuild_task` are the two passes of the raster PCA
(:mod:`coastmesh.pca.chunks`) on one chunk, reading its cells from the file:
a task is given a :class:`~coastmesh.io.rasters.raster_stream.RasterSource` and its
rows and columns, never the data. :mod:`coastmesh.commands.raster_stream` runs
them on Dask.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from coastmesh.errors import ConfigError, InputDataError
from coastmesh.io import RasterSource, encode_cells, read_cells
from coastmesh.pca import chunk_gram, chunk_rebuild

__all__ = [
    "MEMORY_MB",
    "STATS",
    "ChunkPlan",
    "gram_task",
    "plan_chunks",
    "rebuild_task",
]

#: Default working memory of each worker thread, in megabytes.
MEMORY_MB = 768
# Peak working memory of a task per cell of its block (read, kernel, encode):
# measured 90 to 155 bytes on chunks of 0.5 to 4 million cells; with a margin.
_BYTES_PER_CELL = 160
# Chunks per grid at least (if each keeps _MIN_ROWS rows), so that all cores get
# work; a fixed number, as the chunks must not depend on the workers.
_MIN_CHUNKS, _MIN_ROWS = 4, 64
_TILE = 256  # largest output tile side, in cells
#: Numbers rebuild_task reports: covered, changed, sum of squared changes, largest
STATS = 4


@dataclass(frozen=True, slots=True)
class ChunkPlan:
    """How a grid is cut into chunks, and the output's tiles.

    Attributes
    ----------
    rows, columns : tuple of int
        Edges of the chunks: ``0 = rows[0] < rows[1] < ... = ny``, same for
        columns.
    tile : (int, int)
        Rows and columns of the output's tiles: multiples of 16 up to 256; the
        chunks are whole tiles.
    """

    rows: tuple[int, ...]
    columns: tuple[int, ...]
    tile: tuple[int, int]

    @property
    def chunks(self) -> list[tuple[tuple[int, int], tuple[int, int]]]:
        """``((r0, r1), (c0, c1))`` of each chunk, row by row."""
        return [
            ((r0, r1), (c0, c1))
            for r0, r1 in zip(self.rows, self.rows[1:], strict=False)
            for c0, c1 in zip(self.columns, self.columns[1:], strict=False)
        ]


def plan_chunks(
    shape: tuple[int, int],
    window: tuple[int, int],
    *,
    memory_mb: float = MEMORY_MB,
    rows: int | None = None,
    columns: int | None = None,
) -> ChunkPlan:
    """Cut a grid into chunks that fit a memory budget.

    Parameters
    ----------
    shape : (int, int)
        Rows and columns of the grid.
    window : (int, int)
        Window rows and columns.
    memory_mb : float, default :data:`MEMORY_MB`
        Working memory of one task, in megabytes.
    rows, columns : int, optional
        Rows and columns of a chunk (the last ones may be smaller), instead of
        working them out from ``memory_mb``: multiples of 16, or the whole grid.

    Returns
    -------
    ChunkPlan

    Raises
    ------
    ConfigError
        If ``rows`` or ``columns`` is neither a multiple of 16 nor the whole grid.

    Examples
    --------
    >>> plan = plan_chunks((20000, 20000), (8, 8))  # 768 MB a task
    >>> len(plan.chunks), plan.rows[:3], plan.columns[:3], plan.tile
    (90, (0, 2304, 4608), (0, 2048, 4096), (256, 256))
    >>> plan_chunks((1000, 900), (8, 8)).chunks  # whole rows, 4 chunks to share
    [((0, 256), (0, 900)), ((256, 512), (0, 900)), ((512, 768), (0, 900)), ...]
    >>> plan_chunks((40, 50), (4, 4), rows=16, columns=32).rows
    (0, 16, 32, 40)
    """
    ny, nx = shape
    wy, wx = window
    cells = memory_mb * 2**20 / _BYTES_PER_CELL
    if columns is None:
        side = math.isqrt(int(cells))
        wide = nx + 2 * wx > 2 * side  # whole rows would make thin strips
        columns = _bands(nx, side - 2 * wx, _TILE) if wide else nx
    if rows is None:
        fit = max(1, int(cells // (min(columns, nx) + 2 * wx)) - 2 * (wy - 1))
        unit = _TILE if fit >= _TILE else max(16, 1 << (fit.bit_length() - 1))
        across = math.ceil(nx / columns)
        share = max(_MIN_ROWS, math.ceil(ny / math.ceil(_MIN_CHUNKS / across)))
        rows = _bands(ny, min(fit, math.ceil(share / unit) * unit), unit)
    tile = (_tile(rows, ny, "rows"), _tile(columns, nx, "columns"))
    return ChunkPlan(_edges(ny, rows), _edges(nx, columns), tile)


def _bands(n: int, limit: int, unit: int) -> int:
    """Return a band size, a multiple of ``unit`` up to ``limit``, cutting ``n`` evenly.

    The bands are as equal as whole units allow; at least one unit.
    """
    limit = max(unit, limit // unit * unit)
    band = math.ceil(n / math.ceil(n / limit))
    return min(n, math.ceil(band / unit) * unit)


def _tile(size: int, n: int, what: str) -> int:
    """Return the tile side for chunks of ``size`` cells along a side of ``n``."""
    if size >= n:
        return _TILE
    for tile in range(_TILE, 15, -16):
        if size % tile == 0:
            return tile
    raise ConfigError(
        f"chunk {what} = {size}: must be a multiple of 16 (whole output tiles), "
        f"or the whole grid ({n})"
    )


def _edges(n: int, size: int) -> tuple[int, ...]:
    if size < 1:
        raise ConfigError(f"chunk size = {size}: must be >= 1")
    return (*range(0, n, size), n)


def gram_task(
    source: RasterSource,
    rows: tuple[int, int],
    columns: tuple[int, int],
    window: tuple[int, int],
) -> NDArray[np.float64]:
    """Pass 1 on a chunk: lag products, partitions, missing cells.

    Returns one row: the ``L x L`` sum, the partitions, the missing cells of the
    chunk itself, then the valid cells of the block read and their mean (the
    first chunk with valid cells gives pass 2 its shift).
    """
    (r0, r1), (c0, c1) = rows, columns
    wy, wx = window
    block = read_cells(
        source,
        (r0, min(source.height, r1 + wy - 1)),
        (c0, min(source.width, c1 + wx - 1)),
    )
    if np.isinf(block).any():
        row, col = np.argwhere(np.isinf(block))[0]
        raise InputDataError(
            f"cell (row {r0 + row}, column {c0 + col}) is {block[row, col]}; "
            "only finite values or nodata are allowed",
            path=source.source,
        )
    valid = np.isfinite(block)
    n_valid = int(valid.sum())
    mean = float(block[valid].mean()) if n_valid else 0.0
    gram, count = chunk_gram(block, window, shift=mean)
    missing = (r1 - r0) * (c1 - c0) - int(valid[: r1 - r0, : c1 - c0].sum())
    return np.concatenate([gram.ravel(), [count, missing, n_valid, mean]])[None]


def rebuild_task(
    source: RasterSource,
    rows: tuple[int, int],
    columns: tuple[int, int],
    window: tuple[int, int],
    vectors: NDArray[np.float64] | None,
    shift: float,
    nodata: float | None,
    name: str,
) -> tuple[NDArray, NDArray[np.float64]]:
    """Pass 2 on a chunk: its encoded cells, and what changed."""
    (r0, r1), (c0, c1) = rows, columns
    wy, wx = window
    top, left = max(0, r0 - wy + 1), max(0, c0 - wx + 1)
    block = read_cells(
        source,
        (top, min(source.height, r1 + wy - 1)),
        (left, min(source.width, c1 + wx - 1)),
    )
    own = (slice(r0 - top, r1 - top), slice(c0 - left, c1 - left))
    before = block[own]
    if vectors is None:  # no partition anywhere: every cell keeps its value
        after, cover = before, np.zeros(before.shape, dtype=np.int64)
    else:
        after, cover = chunk_rebuild(
            block, window, vectors, shift=shift, rows=own[0], columns=own[1]
        )
    valid = np.isfinite(before)
    change = np.abs(after[valid] - before[valid])
    stats = np.array(
        [
            np.count_nonzero(cover),
            np.count_nonzero(change),
            float(np.dot(change, change)),
            float(change.max()) if change.size else 0.0,
        ]
    )
    return encode_cells(after, source.dtype, nodata, name), stats
