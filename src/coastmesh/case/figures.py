"""A case's figures: what to draw, drawn here or on processes, early if it can.

Each figure is a job: the name of a :mod:`coastmesh.plot` function and its
arguments, rendered to PNG bytes (:func:`render`) and saved into
``figures/`` of the output folder when the case is written. With ``workers >
1`` and a mesh of at least :data:`POOL_MIN_TRIANGLES` triangles, the jobs are
drawn on a pool of that many processes (:mod:`coastmesh.case.processes`),
the longest first: matplotlib draws in one thread, and on the NW-shelf fine
mesh the nine figures take about 20 s one after the other.

:func:`coastmesh.run_case` hands its :class:`FigureJobs` to the build, which
starts each figure as soon as what it shows is final (:func:`setup_jobs` once
the size field is made, :func:`parts_jobs` once the water is meshed,
:func:`quality_jobs` once the mesh is measured), so the pool draws while this
process prepares the parts, measures the mesh and writes its files. The
:func:`mesh_jobs` start once the mesh is final: it has its depths, and the
time-step relief, which moves nodes of most meshes (``world.toml``,
Vestfjorden), has run. Started before it, they were drawn twice on those, and
the first drawings held the pool's processes while the second waited. The
files are the same whatever the number of workers, and whenever each figure
was started.
"""

from __future__ import annotations

import io
import os
from concurrent.futures import Future, ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from coastmesh.case.config import CaseConfig
from coastmesh.case.pipeline import strategy_of
from coastmesh.case.pipeline.depth import relief_due
from coastmesh.case.pipeline.farms import turbine_rows
from coastmesh.case.pipeline.state import (
    CaseRun,
    DepthRun,
    FinishedRun,
    MeshedRun,
    SizedRun,
)
from coastmesh.case.processes import GUARD, process_context
from coastmesh.errors import CoastmeshError
from coastmesh.geometry import reproject_points
from coastmesh.sizing.courant import CourantReport

if TYPE_CHECKING:
    import xarray as xr
    from pyproj import CRS

    from coastmesh.case.result import CaseResult
    from coastmesh.depth import DepthReport
    from coastmesh.meshing import PartsReport, QualityReport
    from coastmesh.types import Domain, Mesh

__all__ = [
    "POOL_MIN_TRIANGLES",
    "FigureJobs",
    "figure_jobs",
    "mesh_jobs",
    "parts_jobs",
    "quality_jobs",
    "render",
    "setup_jobs",
]

#: meshes with fewer triangles have their figures drawn in this process:
#: starting the worker processes (1-2 s each when spawned) and sending each
#: figure its data would cost more than it saves
POOL_MIN_TRIANGLES = 200_000
#: the figures in the order they are started on the pool, longest first; as
#: drawn alone on world.toml (s): time_step 4.4, depth_rules 3.0, parts 2.6,
#: channels 1.9, domain 1.6, depth 1.3, mesh_mercator 1.3, globe 1.1, size 0.9,
#: quality 0.4, mesh 0.4 (depth_rules, last before, ended the run 2 s after
#: the files were written)
_SLOW_FIRST = (
    "time_step",
    "depth_rules",
    "parts",
    "channels",
    "domain",
    "depth",
    "mesh_mercator",
    "globe",
    "size",
    "quality",
    "mesh",
)
#: the order of the figures in the case's list of files
_ORDER = (
    "domain",
    "mesh",
    "size",
    "channels",
    "parts",
    "quality",
    "depth",
    "depth_sources",
    "depth_rules",
    "time_step",
    "site",
    "globe",
    "mesh_mercator",
)

#: ``(stem, plot function, args, kwargs)``: the arguments only passed on to it.
Job = tuple[str, str, tuple[object, ...], dict[str, object]]


def setup_jobs(
    name: str,
    domain: Domain,
    size: xr.DataArray,
    *,
    channel_width: xr.DataArray | None = None,
    channels: object = None,
) -> list[Job]:
    """Return the figures of what is meshed: the domain, size field and channels.

    ``channels`` is the size field's channel report, drawn with
    ``channel_width`` (none without it).
    """
    jobs: list[Job] = [
        ("domain", "domain_figure", (domain,), {"title": f"{name}: domain"}),
        ("size", "size_figure", (size,), {"title": f"{name}: element size"}),
    ]
    if channel_width is not None:
        jobs.append(
            (
                "channels",
                "channel_figure",
                (channel_width,),
                {"report": channels, "title": f"{name}: width of the water"},
            )
        )
    return jobs


def parts_jobs(
    name: str, domain: Domain, parts: PartsReport | None, crs: CRS | None
) -> list[Job]:
    """Return the figure of the parts, in ``crs`` (the mesh's); none for one part."""
    if parts is None or parts.parts < 2:
        return []
    title = f"{name}: {parts.summary()}"
    return [("parts", "parts_figure", (domain, parts), {"crs": crs, "title": title})]


def mesh_jobs(
    name: str,
    mesh: Mesh,
    domain: Domain,
    config: CaseConfig,
    depth: DepthReport | None = None,
    courant: CourantReport | None = None,
) -> list[Job]:
    """Return the figures of the finished mesh: mesh, depth, time step, globe.

    And the detail figure, with ``[output] detail``. ``depth`` is the depth
    report (its ``sources`` name the bathymetry of each node); ``courant`` the
    Courant term's report (the model's time step).
    """
    names = {s.physical_id: s.name for s in domain.segments}
    jobs: list[Job] = [
        ("mesh", "mesh_figure", (mesh,), {"names": names, "title": name})
    ]
    if "depth" in mesh.point_data:
        jobs.append(("depth", "depth_figure", (mesh,), {"title": f"{name}: depth"}))
        if "depth_source" in mesh.point_data and depth:
            jobs.append(
                (
                    "depth_sources",
                    "depth_source_figure",
                    (mesh, depth.sources),
                    {"title": f"{name}: bathymetry source of each node"},
                )
            )
        if depth is not None and depth.rules is not None:
            jobs.append(
                (
                    "depth_rules",
                    "depth_rule_figure",
                    (mesh, depth.rules),
                    {"title": f"{name}: what each node's depth is"},
                )
            )
        jobs.append(
            (
                "time_step",
                "time_step_figure",
                (mesh,),
                {
                    "dt": None if courant is None else courant.dt,
                    "velocity": 0.0 if courant is None else courant.velocity,
                    "title": f"{name}: time step",
                },
            )
        )
    box = config.outputs.detail
    if strategy_of(config).on_sphere:
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
    if box is not None:
        jobs.append(
            (
                "mesh_mercator",
                "mercator_figure",
                (mesh,),
                {"detail": box, "names": names, "title": name},
            )
        )
    return jobs


def quality_jobs(name: str, mesh: Mesh, quality: QualityReport | None) -> list[Job]:
    """Return the figure of the mesh's quality report (none without one)."""
    if quality is None:
        return []
    title = f"{name}: element quality"
    return [("quality", "quality_figure", (mesh, quality), {"title": title})]


def figure_jobs(result: CaseResult) -> list[Job]:
    """Return ``(stem, plot function, args, kwargs)`` of each figure of a case.

    In the order of the case's list of files.
    """
    report = result.report
    courant = report.size_field.courant
    jobs = [
        *setup_jobs(
            result.name,
            result.domain,
            result.size,
            channel_width=result.channel_width,
            channels=report.size_field.channels,
        ),
        *parts_jobs(result.name, result.domain, report.parts, result.mesh.crs),
        *mesh_jobs(
            result.name,
            result.mesh,
            result.domain,
            result.config,
            report.depth,
            courant if isinstance(courant, CourantReport) else None,
        ),
        *quality_jobs(result.name, result.mesh, report.quality),
        *site_jobs(result),
    ]
    return sorted(jobs, key=lambda job: _ORDER.index(job[0]))


def site_jobs(result: CaseResult) -> list[Job]:
    """Return the site figure of a case with farms or turbines; none without."""
    site, mesh = result.site, result.mesh
    if site is None or (
        not site.turbines and len(mesh.region_ids) < 2 and not mesh.lines
    ):
        return []
    rows = turbine_rows(site, mesh) if site.turbines else []
    turbines = [(r["name"], float(r["x"]), float(r["y"])) for r in rows]
    title = f"{result.name}: the site"
    wakes = [
        reproject_points(np.asarray(band.exterior.coords), site.crs, mesh.crs)
        for _, band, _ in site.wakes
    ]
    kwargs: dict[str, object] = {"title": title, "wakes": wakes}
    return [("site", "site_figure", (mesh, turbines), kwargs)]


def render(function: str, args: tuple[object, ...], kwargs: dict[str, object]) -> bytes:
    """Draw one figure with ``coastmesh.plot.<function>``; return it as PNG."""
    from coastmesh import plot
    from coastmesh.plot.base import FIGURE_DPI

    figure = getattr(plot, function)(*args, **kwargs)
    buffer = io.BytesIO()  # a Figure without pyplot: freed when it goes
    figure.savefig(buffer, format="png", dpi=FIGURE_DPI)  # as save_figure
    return buffer.getvalue()


#: How much lower the figure processes' priority is (Unix ``nice``).
NICE = 10


def _died() -> CoastmeshError:
    """Return the error for a figure process that died (as in an unguarded script)."""
    return CoastmeshError(
        "a process drawing the figures died; nothing was written. If this runs "
        f"from a script: {GUARD}"
    )


def _in_the_background() -> None:
    """Lower this process's priority: the figures take only the idle cores.

    Drawing is never what the run waits for until the files are written: while
    the mesh is made and measured, the meshing workers and this run's own
    process go first.
    """
    if hasattr(os, "nice"):  # Unix
        os.nice(NICE)


class FigureJobs:
    """Draw a case's figures, on a pool of processes for a large mesh.

    ``with FigureJobs(workers) as figures:`` then :meth:`start` figures as
    soon as they can be drawn (on the pool, started with the first figure of
    a mesh of :data:`POOL_MIN_TRIANGLES` or more; with one worker or a small
    mesh it does nothing) and :meth:`save` them into the output folder:
    it draws those not started (on the pool, or here), waits for the rest and
    writes them. An error in any figure is raised by :meth:`save`; leaving the
    ``with`` block stops the pool.
    """

    def __init__(self, workers: int = 1) -> None:
        self.workers = int(workers)
        self.pool: ProcessPoolExecutor | None = None
        self.futures: dict[str, Future[bytes]] = {}
        #: what :meth:`follow` started figures of, by group
        self.followed: dict[str, object] = {}

    def __enter__(self) -> FigureJobs:
        return self

    def start(self, jobs: list[Job], triangles: int, *, again: bool = False) -> None:
        """Start drawing ``jobs`` on the pool, for a mesh of ``triangles``.

        A figure started already is not started again, unless ``again``: then
        its earlier drawing is dropped (a figure started before it was sure
        that what it shows would not change, and it did).
        """
        if again:
            for stem, *_ in jobs:
                future = self.futures.pop(stem, None)
                if future is not None:
                    future.cancel()  # if it runs, it ends, and is not waited for
        if self.workers < 2 or triangles < POOL_MIN_TRIANGLES:
            return
        if self.pool is None:
            self.pool = ProcessPoolExecutor(
                self.workers,
                mp_context=process_context(),
                initializer=_in_the_background,
            )
        rank = {stem: i for i, stem in enumerate(_SLOW_FIRST)}
        for job in sorted(jobs, key=lambda job: rank.get(job[0], len(rank))):
            if job[0] not in self.futures:
                try:
                    self.futures[job[0]] = self.pool.submit(render, *job[1:])
                except BrokenProcessPool as exc:
                    raise _died() from exc

    def follow(self, run: CaseRun) -> None:
        """Start the figures a run can draw now that a stage is done; each once.

        The domain, size and channel figures once the size field is made; the
        parts figure once the water is meshed; the mesh's figures once it is
        final (it has its depths and the time-step relief has run; without
        ``[bathymetry]``, once it is made), and again should it change after
        all; the quality figure once it is measured.
        """
        if not isinstance(run, SizedRun):
            return
        name, domain = run.config.name, run.domain
        if "setup" not in self.followed:
            self.followed["setup"] = run.size
            field = run.size.field
            cell = run.size.grid.cell_m
            self.start(
                setup_jobs(
                    name,
                    domain.domain,
                    field,
                    channel_width=run.size.layers.get("width"),
                    channels=run.size.report.channels,
                ),
                int((4 / np.sqrt(3) * cell**2 / field.values**2).sum()),
            )
        if not isinstance(run, MeshedRun):
            return
        state = run.mesh
        triangles = len(state.mesh.triangles)
        if "parts" not in self.followed:
            self.followed["parts"] = state.parts
            jobs = parts_jobs(name, domain.domain, state.parts, state.mesh.crs)
            self.start(jobs, triangles)
        depths = run.depth if isinstance(run, DepthRun) else None
        relieved = depths is not None and (
            depths.relief is not None or not relief_due(run.config)
        )
        final = run.config.bathymetry is None or relieved
        drawn = self.followed.get("mesh")
        if final and drawn is not state.mesh:
            self.followed["mesh"] = state.mesh
            depth = None if depths is None else depths.report
            jobs = mesh_jobs(
                name, state.mesh, domain.domain, run.config, depth, run.time_step
            )
            self.start(jobs, triangles, again=drawn is not None)
        quality = run.quality if isinstance(run, FinishedRun) else None
        if quality is not None and "quality" not in self.followed:
            self.followed["quality"] = quality
            self.start(quality_jobs(name, state.mesh, quality), triangles)

    def save(self, jobs: list[Job], folder: Path, triangles: int) -> list[str]:
        """Draw ``jobs`` into ``folder/figures``; return their names, relative."""
        if not jobs:
            return []
        self.start(jobs, triangles)
        (folder / "figures").mkdir()
        for job in jobs:
            stem = job[0]
            future = self.futures.get(stem)
            try:
                png = render(*job[1:]) if future is None else future.result()
            except BrokenProcessPool as exc:
                raise _died() from exc
            (folder / "figures" / f"{stem}.png").write_bytes(png)
        return [f"figures/{stem}.png" for stem, *_ in jobs]

    def __exit__(self, *exc: object) -> None:
        if self.pool is not None:
            self.pool.shutdown(wait=True, cancel_futures=True)
