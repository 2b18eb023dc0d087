"""The figures drawn on worker processes are the figures drawn in this one."""

from __future__ import annotations

import warnings
from pathlib import Path

import pytest

from coastmesh.case import figures, parse_case, run_case
from coastmesh.case.figures import FigureJobs

EXAMPLE = Path(__file__).parents[2] / "examples" / "orkney" / "pentland_firth.toml"


def test_figures_on_processes_are_the_same_files(tmp_path, monkeypatch):
    monkeypatch.setattr(figures, "POOL_MIN_TRIANGLES", 0)  # a pool for this one too
    text = EXAMPLE.read_text().replace('h_min = "150 m"', 'h_min = "400 m"')
    case = parse_case(text, EXAMPLE)
    out = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for workers in (1, 2):
            out[workers] = run_case(
                case, output=tmp_path / str(workers), workers=workers
            )
    one, two = out[1], out[2]
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
    with (
        pytest.raises(AttributeError, match="no_such_figure"),
        FigureJobs(jobs, tmp_path, workers=2) as drawn,
    ):
        drawn.files()
    assert not list((tmp_path / "figures").iterdir())
