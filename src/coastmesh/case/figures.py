"""A case's figures: what to draw, drawn one after the other or on processes.

Each figure is a job: the name of a :mod:`coastmesh.plot` function and its
arguments. With ``workers > 1`` and a mesh of at least
:data:`POOL_MIN_TRIANGLES` triangles, the jobs are drawn on a pool of that many
spawned processes (matplotlib draws in one thread: on the NW-shelf fine mesh
the nine figures take 40 s one after the other), the longest first, while the
calling process writes the mesh files; the files are the same either way.
"""

from __future__ import annotations

import multiprocessing
from concurrent.futures import Future, ProcessPoolExecutor
from pathlib import Path
from typing import TYPE_CHECKING, Any

from coastmesh.case.config import OutputConfig

if TYPE_CHECKING:
    from coastmesh.case.result import CaseResult

__all__ = ["POOL_MIN_TRIANGLES", "FigureJobs", "figure_jobs"]

#: meshes with fewer triangles have their figures drawn in this process:
#: starting the worker processes (1-2 s each) would cost more than it saves
POOL_MIN_TRIANGLES = 200_000
#: the figures that draw every triangle first: they take longest
_SLOW_FIRST = ("time_step", "quality", "domain", "parts", "mesh_mercator")

Job = tuple[str, str, tuple[Any, ...], dict[str, Any]]


def figure_jobs(result: CaseResult, outputs: OutputConfig) -> list[Job]:
    """Return ``(stem, plot function, args, kwargs)`` of each figure to draw."""
    mesh, name, quality = result.mesh, result.name, result.report.quality
    names = {s.physical_id: s.name for s in result.domain.segments}
    jobs: list[Job] = [
        ("domain", "domain_figure", (result.domain,), {"title": f"{name}: domain"}),
        ("mesh", "mesh_figure", (mesh,), {"names": names, "title": name}),
        ("size", "size_figure", (result.size,), {"title": f"{name}: element size"}),
    ]
    if result.channel_width is not None:
        jobs.append(
            (
                "channels",
                "channel_figure",
                (result.channel_width,),
                {
                    "report": result.report.size_field.channels,
                    "title": f"{name}: width of the water",
                },
            )
        )
    parts = result.report.parts
    if parts is not None and parts.parts > 1:
        title = f"{name}: {parts.summary()}"
        jobs.append(
            (
                "parts",
                "parts_figure",
                (result.domain, parts),
                {"crs": mesh.crs, "title": title},
            )
        )
    if quality is not None:
        title = f"{name}: element quality"
        jobs.append(("quality", "quality_figure", (mesh, quality), {"title": title}))
    if "depth" in mesh.point_data:
        courant = result.config.size.courant
        jobs += [
            ("depth", "depth_figure", (mesh,), {"title": f"{name}: depth"}),
            *(
                [
                    (
                        "depth_sources",
                        "depth_source_figure",
                        (mesh, result.report.depth.sources),
                        {"title": f"{name}: bathymetry source of each node"},
                    )
                ]
                if "depth_source" in mesh.point_data and result.report.depth
                else []
            ),
            (
                "time_step",
                "time_step_figure",
                (mesh,),
                {
                    "dt": None if courant is None else courant.dt,
                    "velocity": 0.0 if courant is None else courant.velocity,
                    "title": f"{name}: time step",
                },
            ),
        ]
    if result.config.domain.kind == "global":
        box = outputs.detail
        # the detail box (a region of interest) low in the view, else the Atlantic
        centre = (
            (0.0, 30.0)
            if box is None
            else ((box[0] + box[2]) / 2, max((box[1] + box[3]) / 2 - 20.0, -60.0))
        )
        jobs.append(
            ("globe", "globe_figure", (mesh,), {"centre": centre, "names": names,
                                                "title": name})
        )  # fmt: skip
    if outputs.detail is not None:
        jobs.append(
            (
                "mesh_mercator",
                "mercator_figure",
                (mesh,),
                {"detail": outputs.detail, "names": names, "title": name},
            )
        )
    return jobs


def draw(path: Path, function: str, args: tuple, kwargs: dict[str, Any]) -> None:
    """Draw one figure with ``coastmesh.plot.<function>`` and save it as ``path``."""
    from coastmesh import plot

    plot.save_figure(getattr(plot, function)(*args, **kwargs), path)


class FigureJobs:
    """Draw a case's figures into ``folder/figures``.

    ``with FigureJobs(jobs, folder, workers) as figures: ...`` starts the jobs
    on a pool when entered (``workers > 1``) and lets the caller work meanwhile;
    :meth:`files` waits for them (drawing them here if ``workers`` is 1) and
    returns their names. An error in any job is raised by :meth:`files`.
    """

    def __init__(self, jobs: list[Job], folder: Path, workers: int = 1) -> None:
        self.jobs, self.folder = jobs, folder / "figures"
        self.workers = min(int(workers), len(jobs))
        self.pool: ProcessPoolExecutor | None = None
        self.futures: dict[str, Future] = {}

    def __enter__(self) -> FigureJobs:
        if self.jobs:
            self.folder.mkdir()
        if self.workers > 1:
            self.pool = ProcessPoolExecutor(
                self.workers, mp_context=multiprocessing.get_context("spawn")
            )
            rank = {stem: i for i, stem in enumerate(_SLOW_FIRST)}
            for stem, function, args, kwargs in sorted(
                self.jobs, key=lambda job: rank.get(job[0], len(rank))
            ):
                path = self.folder / f"{stem}.png"
                self.futures[stem] = self.pool.submit(
                    draw, path, function, args, kwargs
                )
        return self

    def files(self) -> list[str]:
        """Wait for every figure; return their names, relative to the output."""
        for stem, function, args, kwargs in self.jobs:
            if stem in self.futures:
                self.futures[stem].result()
            else:
                draw(self.folder / f"{stem}.png", function, args, kwargs)
        return [f"figures/{stem}.png" for stem, *_ in self.jobs]

    def __exit__(self, *exc: object) -> None:
        if self.pool is not None:
            self.pool.shutdown(wait=True, cancel_futures=True)
