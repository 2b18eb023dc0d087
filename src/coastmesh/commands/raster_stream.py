"""``simplify-raster`` out of core: chunks of the grid as Dask tasks, bounded memory.

The grid is cut into chunks (:func:`~coastmesh.commands.raster_chunks.
plan_chunks`), and the two passes of the raster PCA run as one task per chunk
(:mod:`coastmesh.commands.raster_chunks`). A task is given the file's path and
its rows and columns, never the data, and reads its own cells, so it can run on
any thread, process or machine that sees the file.

1. **Covariance.** One task per chunk returns the lag products and counts of
   the windows starting in it: a row of a ``dask.array``, summed by a tree
   reduction in a fixed order (``split_every``), so the sum, and the result, do
   not depend on how many workers there are or which finished first.
2. **Modes**, once, from the sum.
3. **Reconstruction.** One task per chunk rebuilds its cells and encodes them
   in the file's type. At most twice as many tasks as worker threads are under
   way; each result is written into the GeoTIFF as soon as it is ready (chunks
   are whole tiles, so each tile is written once), then dropped.

The tasks run on a local Dask cluster of threads in this process (numpy,
scipy's FFTs and GDAL release the GIL), or on a Dask cluster given its
scheduler's address.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Generator, Iterator, Sequence
from contextlib import closing, contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from coastmesh.commands.raster_chunks import (
    STATS,
    ChunkPlan,
    gram_task,
    plan_chunks,
    rebuild_task,
)
from coastmesh.errors import CoastmeshError, FormatError
from coastmesh.io import RasterSource, RasterWriter
from coastmesh.pca import chunk_modes, single_threaded_blas
from coastmesh.types import Progress

__all__ = ["StreamTotals", "open_client", "stream_raster"]

logger = logging.getLogger(__name__)

_SPLIT_EVERY = 8  # partial sums combined per node of the reduction tree
#: Seconds between looks at the chunks under way (:func:`_finished`).
_POLL = 0.05


@dataclass(frozen=True, slots=True)
class StreamTotals:
    """What the reconstruction changed, summed over the chunks.

    Attributes
    ----------
    chunks : int
        Chunks the grid was cut into.
    cells_missing, cells_covered, cells_changed : int
        As in :class:`~coastmesh.commands.RasterReport`.
    square_change : float
        Sum of the squared changes over the valid cells (units squared).
    max_change : float
        Largest absolute change.
    """

    chunks: int
    cells_missing: int
    cells_covered: int
    cells_changed: int
    square_change: float
    max_change: float


@contextmanager
def open_client(workers: int, scheduler: str | None = None) -> Iterator[Any]:
    """Yield a Dask client: of ``scheduler``'s cluster, or of threads in this process.

    Parameters
    ----------
    workers : int
        Threads of the local cluster (ignored with ``scheduler``).
    scheduler : str, optional
        A Dask scheduler's address, e.g. ``"tcp://10.0.0.5:8786"``.

    Raises
    ------
    ConfigError
        If the scheduler does not answer, or has no workers, in time
        (:data:`coastmesh.case.executor.SCHEDULER_TIMEOUT`).
    """
    if scheduler is not None:
        from coastmesh.case.executor import connect_scheduler

        client = connect_scheduler(scheduler, work="work")
        try:
            yield client
        finally:
            client.close()
        return
    from distributed import Client, LocalCluster

    with (
        LocalCluster(
            n_workers=1,
            threads_per_worker=workers,
            processes=False,
            dashboard_address="127.0.0.1:0",  # its HTTP routes: any free local port
            memory_limit=0,  # the chunks set the memory; no pausing or spilling
        ) as cluster,
        Client(cluster, set_as_default=False) as client,
        single_threaded_blas(),  # the tasks' matrices are small; threads are used
    ):
        yield client


def stream_raster(
    source: RasterSource,
    target: Path,
    *,
    window: tuple[int, int],
    modes: int,
    client: Any,
    crs: str | None,
    notes: dict[str, str],
    plan: ChunkPlan | None = None,
    threads: int = 1,
    progress: Progress | None = None,
) -> StreamTotals:
    """Approximate a raster by PCA, chunk by chunk on Dask, into a GeoTIFF.

    Parameters
    ----------
    source : RasterSource
        The input and its window.
    target : pathlib.Path
        The GeoTIFF to write (a staging path: it is complete only on return).
    window : (int, int)
        Window rows and columns.
    modes : int
        Leading modes kept.
    client : distributed.Client
        Where the tasks run (:func:`open_client`).
    crs : str or None
        The output's CRS (WKT).
    notes : dict
        Tags of the output (history, provenance).
    plan : ChunkPlan, optional
        The chunks; default :func:`plan_chunks` with its default memory.
    threads : int, default 1
        Threads GDAL compresses the output on.
    progress : callable, optional
        Called as ``progress(done, total)`` after each chunk of each pass.

    Returns
    -------
    StreamTotals

    Raises
    ------
    InputDataError
        If a cell is infinite.
    FormatError
        If the raster has missing cells, an integer type and no nodata value.
    CoastmeshError
        If the Dask workers running a chunk died (Dask runs a lost worker's
        tasks again first). The error of a task that raises is raised as is.
    """
    import dask
    import dask.array as da

    plan = plan or plan_chunks(source.shape, window)
    chunks = plan.chunks
    report = progress or (lambda done, total: None)
    steps = 2 * len(chunks)
    logger.debug("%s: %d chunks, tiles %s", source.source, len(chunks), plan.tile)
    vectors, shift, missing = _modes(
        source, chunks, window, modes, client, (report, steps)
    )
    nodata = _output_nodata(source, missing, target)

    rebuild = dask.delayed(rebuild_task, pure=True, nout=2)
    pieces = []
    for rows, columns in chunks:
        values, stats = rebuild(
            source, rows, columns, window, vectors, shift, nodata, target.name
        )
        shape = (rows[1] - rows[0], columns[1] - columns[0])
        pieces.append(
            [
                da.from_delayed(values, shape, source.dtype),
                da.from_delayed(stats, (STATS,), np.float64),
            ]
        )
    limit = 2 * max(1, sum(client.nthreads().values()))
    stats_of = np.zeros((len(chunks), STATS))  # summed in chunk order at the end
    with RasterWriter(
        target,
        shape=source.shape,
        transform=source.transform,
        crs=crs,
        dtype=source.dtype,
        nodata=nodata,
        tile=plan.tile,
        notes=notes,
        name=source.name,
        threads=threads,
    ) as writer:
        with closing(_computed(client, pieces, limit)) as results:
            for done, (i, (values, stats)) in enumerate(results, len(chunks) + 1):
                (r0, _), (c0, _) = chunks[i]
                writer.write(values, row=r0, column=c0)
                stats_of[i] = stats
                report(done, steps)
    return StreamTotals(
        chunks=len(chunks),
        cells_missing=missing,
        cells_covered=int(stats_of[:, 0].sum()),
        cells_changed=int(stats_of[:, 1].sum()),
        square_change=float(stats_of[:, 2].sum()),
        max_change=float(stats_of[:, 3].max()),
    )


def _modes(
    source: RasterSource,
    chunks: list,
    window: tuple[int, int],
    modes: int,
    client: Any,
    progress: tuple[Progress, int],
) -> tuple[Any, float, int]:
    """Run the first pass: the windows' covariance over every chunk, its modes.

    Returns the leading eigenvectors (None if no window has data), the shift
    the values were centred on, and the count of missing cells.
    """
    import dask
    import dask.array as da

    size = window[0] * window[1]
    gram = dask.delayed(gram_task, pure=True)
    parts = da.concatenate(
        [
            da.from_delayed(
                gram(source, rows, columns, window),
                shape=(1, size * size + 4),
                dtype=np.float64,
            )
            for rows, columns in chunks
        ]
    )
    parts = client.persist(parts)  # the cluster keeps the rows until summed
    _wait(client, parts, *progress)
    sums = parts[:, : size * size + 2].sum(axis=0, split_every=_SPLIT_EVERY)
    sums, firsts = client.compute([sums, parts[:, size * size + 2 :]], sync=True)
    del parts
    count, missing = int(sums[-2]), int(sums[-1])
    vectors = None
    if count:
        vectors = chunk_modes(sums[: size * size].reshape(size, size), count, modes)
    has_data = firsts[:, 0] > 0
    shift = float(firsts[np.argmax(has_data), 1]) if has_data.any() else 0.0
    return vectors, shift, missing


def _wait(client: Any, persisted: Any, report: Progress, steps: int) -> None:
    """Wait for a persisted collection's tasks, reporting each; raise an error."""
    from distributed import futures_of

    futures = futures_of(persisted)
    pending, count = list(futures), 0
    try:
        while pending:
            done = _finished(pending)
            for future in done:
                if future.status == "error":
                    _result(future)  # raises the task's exception
                count += 1
                report(count, steps)
            gone = {id(f) for f in done}
            pending = [f for f in pending if id(f) not in gone]
    except BaseException:
        client.cancel(futures)
        raise


def _finished(futures: Sequence[Any]) -> list[Any]:
    """Wait until some of ``futures`` are done; return those, in their order.

    Each future's own state is looked at every :data:`_POLL` seconds, where
    ``distributed.as_completed`` tracks the futures with callbacks on one
    client's event loop: the test suite, which has a second client in the
    process (a fixture's beside the command's), hung once in its wait.
    """
    while True:
        done = [future for future in futures if future.done()]
        if done:
            return done
        time.sleep(_POLL)


def _result(future: Any) -> Any:
    """Return a future's result; a task whose workers died is a CoastmeshError."""
    from distributed import KilledWorker

    try:
        return future.result()
    except KilledWorker as exc:
        raise CoastmeshError(
            f"the Dask workers running a chunk died ({exc}); nothing was written"
        ) from exc


def _computed(
    client: Any, items: Sequence[list[Any]], limit: int
) -> Generator[tuple[int, list[Any]], None, None]:
    """Yield ``(index, results)`` for each list of collections as it is computed.

    At most ``limit`` items are under way. A task's error is raised here, and
    the items not yet done are cancelled.
    """
    queue = iter(enumerate(items))
    running: dict[str, tuple[int, list[Any]]] = {}

    def submit() -> None:
        item = next(queue, None)
        if item is not None:
            futures = client.compute(item[1])
            running[futures[0].key] = (item[0], futures)

    for _ in range(limit):
        submit()
    try:
        while running:
            for future in _finished([futures[0] for _, futures in running.values()]):
                index, futures = running.pop(future.key)
                results = [_result(f) for f in futures]
                submit()
                yield index, results
    finally:
        client.cancel([f for _, futures in running.values() for f in futures])


def _output_nodata(source: RasterSource, missing: int, target: Path) -> float | None:
    """Return the output's nodata: the input's, else NaN if cells are missing."""
    if not missing or source.nodata is not None:
        return source.nodata
    if np.dtype(source.dtype).kind != "f":
        raise FormatError(
            f"{target.name}: {missing} cells are missing but dtype {source.dtype} "
            "has no nodata value"
        )
    return float("nan")
