"""Where parts are meshed: a local pool that survives a dying worker, Dask."""

from __future__ import annotations

import functools
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

from coastmesh.case.executor import open_runner
from coastmesh.errors import ConfigError, MeshingError


def _square(x):
    return x * x


def _die_once(marker: str) -> str:
    """Kill this worker the first time any worker runs it."""
    try:
        fd = os.open(marker, os.O_CREAT | os.O_EXCL)
    except FileExistsError:
        return "ok"
    os.close(fd)
    os._exit(3)


def _die(_):
    os._exit(3)


def _pid(_):
    time.sleep(0.05)  # long enough that both workers take tasks
    return os.getpid()


def _note_pid(path: str, count: int) -> None:
    """Note this process; wait until ``count`` processes have (one call each)."""
    with open(path, "a") as f:
        f.write(f"{os.getpid()}\n")
    until = time.monotonic() + 60
    while len(set(Path(path).read_text().split())) < count:
        assert time.monotonic() < until, "the workers were not all started"
        time.sleep(0.01)


def test_the_pool_returns_results_in_order_whatever_finishes_first():
    with open_runner(2) as run:
        assert run(_square, list(range(7))) == [x * x for x in range(7)]
    with open_runner(1) as run:  # one worker: this process
        assert run(_square, [3]) == [9]


def test_workers_started_ahead_run_the_next_tasks(tmp_path):
    ready = tmp_path / "ready"
    with open_runner(2) as run:
        run.warm(5, functools.partial(_note_pid, str(ready), 2))  # 2: the workers
        run.warm(5, functools.partial(_note_pid, str(ready), 2))  # started already
        pids = run(_pid, list(range(6)))
        started = {int(p) for p in ready.read_text().split()}
        assert len(started) == 2 and set(pids) <= started
        assert set(run(_pid, list(range(4)))).isdisjoint(started)  # a new pool
    few = tmp_path / "few"
    with open_runner(3) as run:  # two started ahead, three tasks: not used
        run.warm(2, functools.partial(_note_pid, str(few), 2))
        _note_pid(str(few), 3)  # this process third: once both have started
        pids = run(_pid, list(range(3)))
        assert set(pids).isdisjoint(int(p) for p in few.read_text().split())
    with open_runner(1) as run:
        assert not hasattr(run, "warm")  # this process: nothing to start


def test_a_dying_worker_is_replaced_and_its_task_run_again(tmp_path):
    marker = str(tmp_path / "died")
    with open_runner(2) as run:
        assert run(_die_once, [marker, marker, marker]) == ["ok"] * 3
    assert Path(marker).exists()


def test_a_task_that_always_kills_its_worker_is_named():
    with (
        open_runner(2) as run,
        pytest.raises(MeshingError, match="died twice while meshing task") as info,
    ):
        run(_die, [0, 1])
    assert "task 1 of 2" in str(info.value) and "task 2 of 2" in str(info.value)
    assert "__main__" in str(info.value)  # the advice for scripts


def test_an_unreachable_scheduler_is_a_clear_error_within_the_timeout():
    started = time.perf_counter()
    with (
        pytest.raises(ConfigError, match=r"tcp://127.0.0.1:9.*no Dask scheduler"),
        open_runner(2, "tcp://127.0.0.1:9", timeout=2),
    ):
        pass
    assert time.perf_counter() - started < 15


@pytest.fixture(scope="module")
def cluster():
    """Two Dask worker processes whose nannies restart them when they die.

    A task that kills its worker is retried elsewhere until it has killed
    ``allowed-failures`` + 1 workers (here 2, to keep the test short).
    """
    import dask
    from distributed import LocalCluster

    with (
        dask.config.set({"distributed.scheduler.allowed-failures": 1}),
        LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
        ) as local,
    ):
        yield local.scheduler_address


def test_a_dask_worker_that_dies_has_its_task_run_again(cluster, tmp_path):
    marker = str(tmp_path / "died")
    with open_runner(1, cluster) as run:
        assert run(_die_once, [marker, marker, marker]) == ["ok"] * 3
    assert Path(marker).exists()  # a worker did die


def test_a_task_that_kills_every_dask_worker_it_meets_is_named(cluster):
    with (
        open_runner(1, cluster) as run,
        pytest.raises(MeshingError, match=r"task [12] of 2: the Dask workers running"),
    ):
        run(_die, [0, 1])
    with open_runner(1, cluster) as run:  # the nannies brought the workers back
        assert run(_square, [2, 3]) == [4, 9]


_UNGUARDED = """
import gc, time
from coastmesh.case.executor import open_runner
from coastmesh.case.processes import start_server

start_server()
with open_runner(2) as run:
    run.warm(2, gc.collect)  # started ahead: they die before their tasks come
    time.sleep(1.0)
    print(run(abs, [-1, -2, -3]))
"""


def test_a_script_without_a_main_guard_is_told_to_add_one(tmp_path):
    script = tmp_path / "unguarded.py"
    script.write_text(_UNGUARDED)
    done = subprocess.run(
        [sys.executable, str(script)],
        check=False,
        capture_output=True,
        text=True,
        timeout=120,
        cwd=tmp_path,
    )
    assert done.returncode != 0
    last = done.stderr.strip().splitlines()[-1]
    assert last.startswith("coastmesh.errors.MeshingError: a worker process died")
    assert 'must do it under `if __name__ == "__main__":`' in last
    assert "An attempt has been made to start a new process" not in done.stderr
