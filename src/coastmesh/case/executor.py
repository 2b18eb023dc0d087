"""Where the parts of a mesh are made: here, a local process pool, or Dask.

:func:`open_runner` yields a :class:`TaskRunner`,
``runner(fn, tasks) -> [fn(t) for t in tasks]``, that computes the tasks

- one after the other in this process, with one worker;
- in a local pool of worker processes (:class:`concurrent.futures.
  ProcessPoolExecutor`, started on first use, so a one-part case starts none,
  or ahead of it by ``runner.warm(count, ready)``, which the meshing calls
  once it expects parts, so that the processes have started and imported
  what they need by the time the parts are ready);
- or as tasks on a Dask distributed cluster, given a scheduler address.

Nothing here schedules: the pool and Dask do. Results come back in the tasks'
order, whatever order they finish in, so the mesh does not depend on the
executor. Tasks are handed out longest first (their ``expected`` triangles),
which keeps the workers evenly loaded.

A local worker that dies is replaced and its task run again, once; Dask
re-runs the tasks of a lost worker itself (``distributed.scheduler.
allowed-failures``), which it can because each task carries its own part
(tested by killing workers of a ``LocalCluster``). A task that still fails
stops the run with the part named, before anything is written.
"""

from __future__ import annotations

import logging
import warnings
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from contextlib import contextmanager
from typing import TYPE_CHECKING, Protocol, TypeVar

from coastmesh.case.processes import GUARD, check_main, process_context
from coastmesh.errors import ConfigError, MeshingError
from coastmesh.meshing.parts.tasks import serial_runner

if TYPE_CHECKING:
    from distributed import Client

__all__ = ["SCHEDULER_TIMEOUT", "TaskRunner", "connect_scheduler", "open_runner"]

logger = logging.getLogger(__name__)
T = TypeVar("T")
R = TypeVar("R")


class TaskRunner(Protocol):
    """A :data:`~coastmesh.types.Runner` of any tasks: what :func:`open_runner` yields.

    ``runner(fn, items) -> [fn(item) for item in items]``, whatever ``fn``
    takes and returns, so one runner serves the parts, the boundary batches and
    the bands of the size terms (each a ``Runner[task, result]``).
    """

    def __call__(self, fn: Callable[[T], R], items: Sequence[T], /) -> list[R]:
        """Return ``[fn(item) for item in items]``, in the items' order."""
        ...


#: Seconds to wait for a Dask scheduler to answer and to have a worker.
SCHEDULER_TIMEOUT = 20.0


@contextmanager
def open_runner(
    workers: int, scheduler: str | None = None, *, timeout: float | None = None
) -> Iterator[TaskRunner]:
    """Yield a runner for the parts' tasks; close what it opened on exit.

    Parameters
    ----------
    workers : int
        Local worker processes (>= 1); 1 runs the tasks in this process.
        Ignored with ``scheduler``: the cluster has its own workers.
    scheduler : str, optional
        The address of a Dask distributed scheduler, e.g.
        ``"tcp://10.0.0.5:8786"``.
    timeout : float, optional
        Seconds to wait for the scheduler and for at least one worker; default
        :data:`SCHEDULER_TIMEOUT`.

    Raises
    ------
    ConfigError
        If the scheduler cannot be reached, or has no workers, within
        ``timeout`` seconds.

    Examples
    --------
    >>> with open_runner(1) as run:
    ...     run(abs, [-1, 2, -3])
    [1, 2, 3]
    """
    check_main()  # a worker importing the user's script again: stop at once
    if scheduler is not None:
        client = _connect(scheduler, timeout or SCHEDULER_TIMEOUT)
        try:
            yield _dask_runner(client)
        finally:
            client.close()  # type: ignore[no-untyped-call]  # unannotated (distributed)
        return
    if workers == 1:
        yield serial_runner
        return
    pools: list[ProcessPoolExecutor] = []
    try:
        yield _pool_runner(workers, pools)
    finally:
        for pool in pools:
            pool.shutdown(wait=True, cancel_futures=True)


def _label(item: object, index: int, count: int) -> str:
    return getattr(item, "label", f"task {index + 1} of {count}")


def _longest_first(items: Sequence[object]) -> list[int]:
    return sorted(
        range(len(items)), key=lambda i: (-float(getattr(items[i], "expected", 0)), i)
    )


def _pool_runner(workers: int, pools: list[ProcessPoolExecutor]) -> TaskRunner:
    """Return a runner on a local process pool, replaced once if a worker dies."""

    def new_pool(n: int) -> ProcessPoolExecutor:
        # forked from a clean server, or spawned: no copy of this process's threads
        pool = ProcessPoolExecutor(max_workers=n, mp_context=process_context())
        pools.append(pool)
        return pool

    ahead: list[tuple[ProcessPoolExecutor, int]] = []  # from warm, for next run

    def warm(count: int, ready: Callable[[], object]) -> None:
        """Start ``min(workers, count)`` processes now, each calling ``ready``."""
        if not ahead:
            started = min(workers, count)
            pool = new_pool(started)
            for _ in range(started):  # a process is started per task waiting
                pool.submit(ready)
            ahead.append((pool, started))

    def pool_for(tasks: int) -> ProcessPoolExecutor:
        """Return the pool started ahead if it has enough processes, else a new one."""
        wanted = min(workers, tasks)
        if ahead:
            pool, started = ahead.pop()
            if started >= wanted:
                return pool
            pool.shutdown(wait=False, cancel_futures=True)  # too few: not used
        return new_pool(wanted)

    def run(fn: Callable[[T], R], items: Sequence[T]) -> list[R]:
        if len(items) <= 1:
            return [fn(item) for item in items]
        results: dict[int, R] = {}
        todo = _longest_first(items)
        for attempt in range(2):
            pool = pool_for(len(todo))
            futures, broken = {}, []
            for i in todo:
                try:
                    futures[i] = pool.submit(fn, items[i])
                except BrokenProcessPool:  # a worker started ahead died already
                    broken.append(i)
            for i, future in futures.items():
                try:
                    results[i] = future.result()
                except BrokenProcessPool:
                    broken.append(i)  # this one, or one beside it, killed it
            pool.shutdown(wait=True, cancel_futures=True)
            if not broken:
                break
            if attempt == 1:
                names = "; ".join(_label(items[i], i, len(items)) for i in broken[:3])
                more = f" and {len(broken) - 3} more" if len(broken) > 3 else ""
                raise MeshingError(
                    f"a worker process died twice while meshing {names}{more}; "
                    f"nothing was written. If this runs from a script: {GUARD}"
                )
            logger.warning("a worker process died; running %d parts again", len(broken))
            todo = broken
        return [results[i] for i in range(len(items))]

    run.workers = workers  # type: ignore[attr-defined]
    run.warm = warm  # type: ignore[attr-defined]
    return run


def connect_scheduler(
    address: str, *, timeout: float | None = None, work: str = "mesh"
) -> Client:
    """Return a :class:`distributed.Client` of a scheduler that has a worker.

    Parameters
    ----------
    address : str
        The scheduler's address, e.g. ``"tcp://10.0.0.5:8786"``.
    timeout : float, optional
        Seconds to wait for the scheduler and for at least one worker; default
        :data:`SCHEDULER_TIMEOUT`.
    work : str, default "mesh"
        What the caller does, for the advice in the error message.

    Returns
    -------
    distributed.Client
        Not set as the default client; close it when done.

    Raises
    ------
    ConfigError
        If the scheduler cannot be reached, or has no workers, within
        ``timeout`` seconds.
    """
    return _connect(address, timeout or SCHEDULER_TIMEOUT, work)


def _connect(address: str, timeout: float, work: str = "mesh") -> Client:
    """Connect to a Dask scheduler that has at least one worker."""
    from distributed import Client

    advice = (
        "start one with `dask scheduler` and workers with `dask worker ADDRESS "
        f"--nthreads 1`, or leave the scheduler out to {work} on this machine"
    )
    try:
        # distributed annotates neither Client() nor its close() and cancel()
        client = Client(  # type: ignore[no-untyped-call]
            address, timeout=f"{timeout}s", set_as_default=False
        )
    except (OSError, TimeoutError, ValueError) as exc:
        raise ConfigError(
            f"scheduler = {address!r}: no Dask scheduler answered within "
            f"{timeout:g} s ({exc}); {advice}"
        ) from None
    try:
        client.wait_for_workers(1, timeout=timeout)
    except (OSError, TimeoutError) as exc:
        client.close()  # type: ignore[no-untyped-call]
        raise ConfigError(
            f"scheduler = {address!r}: the scheduler has no workers after "
            f"{timeout:g} s ({exc}); {advice}"
        ) from None
    logger.info(
        "Dask scheduler %s: %d workers",
        address,
        len(client.scheduler_info().get("workers", {})),
    )
    return client


def _dask_runner(client: Client) -> TaskRunner:
    """Return a runner on a Dask cluster: one task per item, its data inside it."""
    from distributed import KilledWorker

    def run(fn: Callable[[T], R], items: Sequence[T]) -> list[R]:
        order = _longest_first(items)
        # Each task carries its own part. Scattered data would live on one
        # worker only: if that worker died, the part could not be run again.
        with warnings.catch_warnings():
            warnings.filterwarnings("ignore", "Sending large graph", UserWarning)
            futures = {
                i: client.submit(
                    fn, items[i], pure=False, priority=len(order) - rank, retries=1
                )
                for rank, i in enumerate(order)
            }
        results = {}
        try:
            for i, future in futures.items():
                try:
                    results[i] = future.result()
                except KilledWorker as exc:
                    raise MeshingError(
                        f"{_label(items[i], i, len(items))}: the Dask workers "
                        f"running it died ({exc}); nothing was written"
                    ) from exc
        finally:
            client.cancel(list(futures.values()))  # type: ignore[no-untyped-call]
        return [results[i] for i in range(len(items))]

    workers = client.scheduler_info()["workers"].values()
    threads = [w.get("nthreads", 1) for w in workers]
    run.workers = max(sum(threads), 1)  # type: ignore[attr-defined]
    return run
