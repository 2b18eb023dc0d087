"""The figures drawn on worker processes are the figures drawn in this one."""

from __future__ import annotations

import contextlib
import os
import warnings
from pathlib import Path

import pytest

from coastmesh import plot
from coastmesh.case import figures, parse_case, run_case
from coastmesh.case.figures import FigureJobs

EXAMPLE = Path(__file__).parents[2] / "examples" / "orkney" / "pentland_firth.toml"


def _on_1_and_2_workers(tmp_path):
    """Run the coarse Orkney case on 1 and on 2 workers; return both results."""
    text = EXAMPLE.read_text().replace('h_min = "150 m"', 'h_min = "400 m"')
    case = parse_case(text, EXAMPLE)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return [
            run_case(case, output=tmp_path / str(workers), workers=workers)
            for workers in (1, 2)
        ]


@pytest.mark.slow
def test_figures_on_processes_are_the_same_files(tmp_path, monkeypatch):
    monkeypatch.setattr(figures, "POOL_MIN_TRIANGLES", 0)  # a pool for this one too
    one, two = _on_1_and_2_workers(tmp_path)
    assert one.files == two.files
    pngs = [f for f in one.files if f.startswith("figures/")]
    assert len(pngs) >= 6
    for name in one.files:
        if name in ("report.json", "summary.txt") or name.endswith(".gpkg"):
            continue  # they hold the run's times
        assert (one.output / name).read_bytes() == (two.output / name).read_bytes(), (
            name
        )


def test_a_figure_that_fails_on_a_worker_fails_the_write(tmp_path):
    jobs = [("bad", "no_such_figure", (), {}), ("also", "no_such_figure", (), {})]
    big = figures.POOL_MIN_TRIANGLES
    with (
        pytest.raises(AttributeError, match="no_such_figure"),
        FigureJobs(2) as drawn,
    ):
        drawn.start(jobs, big)
        assert drawn.pool is not None
        if hasattr(os, "nice"):  # the pool takes only idle cores
            niceness = drawn.pool.submit(os.nice, 0).result()
            assert niceness == min(os.nice(0) + figures.NICE, 19)
        drawn.save(jobs, tmp_path, big)
    assert not list((tmp_path / "figures").iterdir())


def test_small_meshes_and_one_worker_draw_here(tmp_path):
    jobs = [("bad", "no_such_figure", (), {})]
    for workers, triangles in ((1, 10**9), (2, figures.POOL_MIN_TRIANGLES - 1)):
        with FigureJobs(workers) as drawn:
            drawn.start(jobs, triangles)
            assert drawn.pool is None and not drawn.futures
            with pytest.raises(AttributeError, match="no_such_figure"):
                drawn.save(jobs, tmp_path, triangles)  # drawn here: it fails here
            (tmp_path / "figures").rmdir()


@pytest.mark.slow
def test_each_figure_starts_once_what_it_shows_is_made(tmp_path, monkeypatch):
    """With a pool, run_case starts the figures as the case is built.

    Those of the domain and size field once it is made, before the meshing; those
    of the mesh once it is final: it has its depths and its time step was
    relieved (which changes this mesh: started before, they were drawn twice);
    the quality figure once it is measured; none is drawn twice.
    """
    monkeypatch.setattr(figures, "POOL_MIN_TRIANGLES", 0)
    events: list[str] = []
    start = FigureJobs.start

    def recorded(self, jobs, triangles, **kwargs):
        if jobs:
            events.append("start " + " ".join(sorted(j[0] for j in jobs)))
        start(self, jobs, triangles, **kwargs)

    monkeypatch.setattr(FigureJobs, "start", recorded)
    drawn: list[str] = []  # what this process draws (the pool's are spawned)
    for name in plot.__all__:
        if name.endswith("_figure"):
            function = getattr(plot, name)
            monkeypatch.setattr(
                plot,
                name,
                lambda *a, _f=function, _n=name, **k: drawn.append(_n) or _f(*a, **k),
            )

    @contextlib.contextmanager
    def stage(label):
        events.append(label)
        yield lambda done, total: None

    text = EXAMPLE.read_text().replace('h_min = "150 m"', 'h_min = "400 m"')
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = run_case(
            parse_case(text, EXAMPLE), output=tmp_path / "o", workers=2, stage=stage
        )
    starts = [e for e in events if e.startswith("start ")]  # none: no parts
    mesh_figures = "start depth depth_rules mesh time_step"
    expected = ["start channels domain size", mesh_figures, "start quality"]
    assert starts[: len(expected)] == expected, events
    last = len(expected) - 1
    at = events.index
    assert at("size field") < at(starts[0]) < at("meshing")
    assert at("depth at the nodes") < at("time step") < at(starts[1])
    assert at(starts[1]) < at("mesh quality") < at(starts[last])
    assert at(starts[last]) < at("writing outputs") < at(starts[last + 1])  # all
    assert drawn == []  # every figure was drawn on the pool, once
    pngs = sorted(f for f in result.files if f.startswith("figures/"))
    assert pngs == [
        f"figures/{s}.png"
        for s in sorted(
            ["channels", "domain", "size", "depth", "depth_rules", "mesh", "time_step"]
            + ["quality"]
        )
    ]


def test_a_figure_started_again_is_drawn_from_its_new_arguments(tmp_path):
    from conftest import one_triangle

    mesh = one_triangle("EPSG:32630")
    big = figures.POOL_MIN_TRIANGLES

    def job(title):
        return [("mesh", "mesh_figure", (mesh,), {"title": title})]

    for again, title in ((True, "second"), (False, "first")):
        with FigureJobs(2) as drawn:
            drawn.start(job("first"), big)
            drawn.start(job("second"), big, again=again)
            folder = tmp_path / title
            folder.mkdir()
            drawn.save(job("second"), folder, big)
        png = (folder / "figures" / "mesh.png").read_bytes()
        assert png == figures.render("mesh_figure", (mesh,), {"title": title})


@pytest.mark.slow
def test_figures_follow_a_relief_that_changes_the_mesh(tmp_path, monkeypatch):
    """The mesh's figures show the mesh as the time-step relief changed it.

    They start once the relief has run; the files must be those of one worker.
    """
    import dataclasses

    from coastmesh.case.pipeline import depth

    monkeypatch.setattr(figures, "POOL_MIN_TRIANGLES", 0)
    relieve = depth.relieve_time_step

    def changing(mesh, **kwargs):
        """A relief that moves every node a little (and is accepted)."""
        relieved, report = relieve(mesh, **kwargs)
        moved = dataclasses.replace(relieved, points=relieved.points * 1.00001)
        return moved, dataclasses.replace(report, accepted=True)

    monkeypatch.setattr(depth, "relieve_time_step", changing)
    one, two = _on_1_and_2_workers(tmp_path)
    for stem in ("depth", "time_step", "mesh"):
        name = f"figures/{stem}.png"
        assert (one.output / name).read_bytes() == (two.output / name).read_bytes()
