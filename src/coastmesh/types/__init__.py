"""The core data types of coastmesh, shared by every stage.

=========================  ===================================================
:class:`Features`          vector features: geometries, CRS, attributes, ids
:class:`BoundarySegment`   a piece of a domain boundary with its physical id
:class:`Domain`            a polygon to mesh and its tagged boundary segments
:class:`SizeGrid`          target edge lengths (metres) on a regular grid
:class:`Mesh`              triangles, tagged boundary edges, node data, regions
:class:`MeshLine`          a line inside a mesh whose edges are mesh edges
:data:`Progress`           ``progress(done, total)`` callbacks of long work
:data:`StageFactory`       ``stage(label)``: a context manager per run stage
:func:`quiet_stage`        the :data:`StageFactory` that shows nothing
:data:`Runner`             ``runner(fn, items)``: where independent tasks run
:func:`serial_runner`      the :data:`Runner` that runs them here, in order
:class:`Report`            base of every report: ``to_dict()`` and ``summary()``
=========================  ===================================================

Types are few, immutable and validated when built. Constructors never read
files: the readers in :mod:`coastmesh.io` return these types.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Callable, Iterator, Sequence
from typing import Any, TypeVar

from coastmesh.types.domain import SEGMENT_KINDS, BoundarySegment, Domain
from coastmesh.types.features import Features
from coastmesh.types.mesh import Mesh, MeshLine, SizeGrid
from coastmesh.types.report import Report

__all__ = [
    "SEGMENT_KINDS",
    "BoundarySegment",
    "Domain",
    "Features",
    "Mesh",
    "MeshLine",
    "Progress",
    "Report",
    "Runner",
    "SizeGrid",
    "StageFactory",
    "local_cores",
    "quiet_stage",
    "runner_workers",
    "serial_runner",
]

#: A callback of long work: ``progress(done, total)``, in any units.
Progress = Callable[[int, int], None]
#: ``stage(label)`` returns a context manager that yields a :data:`Progress`;
#: whole runs enter one per stage (the command line draws a bar for each).
StageFactory = Callable[[str], contextlib.AbstractContextManager[Progress]]


@contextlib.contextmanager
def quiet_stage(label: str) -> Iterator[Progress]:
    """Enter a stage that shows nothing: the default :data:`StageFactory`.

    Examples
    --------
    >>> with quiet_stage("meshing") as progress:
    ...     progress(1, 2)
    """
    yield lambda done, total: None


T = TypeVar("T")
R = TypeVar("R")
#: Runs ``fn`` on every item and returns the results in the items' order,
#: wherever it runs them (:func:`coastmesh.case.executor.open_runner`: here, a
#: local process pool or a Dask cluster). A runner may carry ``workers``, the
#: number of tasks it runs at once, for work that splits as finely as it likes.
Runner = Callable[[Callable[[T], R], Sequence[T]], list[R]]


def serial_runner(fn: Callable[[T], R], items: Sequence[T]) -> list[R]:
    """Run the tasks one after the other in this process.

    Examples
    --------
    >>> serial_runner(abs, [-1, 2])
    [1, 2]
    """
    return [fn(item) for item in items]


def local_cores() -> int:
    """Return the cores this process may use (all of the machine's off Linux)."""
    affinity = getattr(os, "sched_getaffinity", None)
    return len(affinity(0)) if affinity else os.cpu_count() or 1


def runner_workers(runner: Any) -> int:
    """Return how many tasks ``runner`` runs at once (1 unless it says more)."""
    workers = getattr(runner, "workers", 1)
    return workers if isinstance(workers, int) and workers >= 1 else 1
