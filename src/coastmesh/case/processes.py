"""The local worker processes' start: forked from a server that imported once.

A spawned worker starts Python and imports numpy, shapely, Gmsh and, for the
figures, matplotlib: about 0.7 CPU s for a meshing worker and 1.3 s for a
figure worker, on each of them, while the run's own work wants those cores.
Where the platform has it (Linux, macOS), the workers are forked instead from
multiprocessing's fork server, which imports that stack once (:data:`PRELOAD`)
and is started as a run with more than one worker begins
(:func:`start_server`), while this process reads its shorelines on one core.
The server has no threads of this process (it is started clean, as a spawned
process is), so the forked workers are as clean as spawned ones, and they
compute the same bytes. Elsewhere (Windows) the workers are spawned.
"""

from __future__ import annotations

import multiprocessing
from multiprocessing.context import BaseContext

__all__ = ["GUARD", "PRELOAD", "check_main", "process_context", "start_server"]

#: What the fork server imports before it forks a worker: what mesh_part
#: and the figures import (matplotlib's Agg canvas with coastmesh.plot).
PRELOAD = (
    "coastmesh.meshing.parts.tasks",
    "gmsh",
    "coastmesh.case.figures",
    "coastmesh.plot",
    "matplotlib.backends.backend_agg",
)


#: What a worker that is importing the user's script again says.
GUARD = (
    "a worker process started by coastmesh ran your script again: Python starts "
    "worker processes by importing the main script, so a script that builds a "
    'case must do it under `if __name__ == "__main__":` (or pass workers=1)'
)


def check_main() -> None:
    """Stop a worker that is importing the user's script: raise RuntimeError.

    A worker started by spawning, or by the fork server, imports the main
    script before its task; one without ``if __name__ == "__main__":`` would
    build the case again there, and start workers of its own.
    """
    if getattr(multiprocessing.current_process(), "_inheriting", False):
        raise RuntimeError(GUARD)


def process_context() -> BaseContext:
    """Return the start method's context for local worker pools.

    ``forkserver`` with :data:`PRELOAD` where the platform has it, else
    ``spawn``.
    """
    if "forkserver" not in multiprocessing.get_all_start_methods():
        return multiprocessing.get_context("spawn")
    context = multiprocessing.get_context("forkserver")
    context.set_forkserver_preload(list(PRELOAD))  # used when the server starts
    return context


def start_server() -> None:
    """Start the fork server now (it imports :data:`PRELOAD` on its own core).

    Raises
    ------
    RuntimeError
        In a worker importing a script that has no ``__main__`` guard
        (:func:`check_main`).
    """
    check_main()
    context = process_context()
    if context.get_start_method() == "forkserver":
        from multiprocessing import forkserver

        forkserver.ensure_running()
