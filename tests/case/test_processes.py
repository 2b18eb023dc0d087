"""The local workers' start: forked from a fork server that imported once."""

from __future__ import annotations

import importlib
import multiprocessing
import os
import sys
from concurrent.futures import ProcessPoolExecutor

import pytest

from coastmesh.case import processes

FORKSERVER = "forkserver" in multiprocessing.get_all_start_methods()


def _state(_):
    """What a worker had imported before its task, and who started it."""
    return os.getppid(), {name: name in sys.modules for name in processes.PRELOAD}


@pytest.mark.parametrize("name", processes.PRELOAD)
def test_every_module_the_server_preloads_imports(name):
    # the fork server skips a preload that fails to import, silently: then
    # each worker would import it again, and nothing would say so
    importlib.import_module(name)


@pytest.mark.skipif(not FORKSERVER, reason="no fork server on this platform")
def test_workers_fork_from_a_server_that_imported_the_stack():
    processes.start_server()
    context = processes.process_context()
    assert context.get_start_method() == "forkserver"
    with ProcessPoolExecutor(2, mp_context=context) as pool:
        states = list(pool.map(_state, range(4)))
    parents = {parent for parent, _ in states}
    assert os.getpid() not in parents  # the server's children, not this one's
    assert all(all(loaded.values()) for _, loaded in states), states


def test_without_a_fork_server_the_workers_are_spawned(monkeypatch):
    monkeypatch.setattr(multiprocessing, "get_all_start_methods", lambda: ["spawn"])
    assert processes.process_context().get_start_method() == "spawn"
    processes.start_server()  # nothing to start
