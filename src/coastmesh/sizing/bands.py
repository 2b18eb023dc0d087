"""The gradations of a size field, in bands of grid rows, as tasks of any runner.

The distance terms are most of a size field's time: each gradation densifies
its lines, builds a k-d tree of their vertices on the Earth and finds every
grid node's nearest vertex (:mod:`coastmesh.sizing.distance`). Each node's
size is a function of its own distances only, so the grid splits into bands
of rows with no halo, each a task (:func:`graded_band`) for the run's
:data:`~coastmesh.types.Runner`: by default only when it reaches more cores
than this machine has (a Dask cluster of several machines; see
:func:`band_count`).

A band's task carries its own nodes and, per gradation, only the vertices
that can be nearest to one of them: those in the band's earth-centred box
widened by the search's bound (the chord of ``d_hold + d_grade``). A vertex
outside that box is farther than the bound from every node of the band, where
the search stops anyway, so a band's distances are those of the whole grid,
bit for bit (tested), and the field is the same on any number of workers or
bands. One band is computed here.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import shapely
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.sizing.distance import (
    chord_bound,
    grid_nodes,
    line_vertices,
    nearest_arcs,
)
from coastmesh.sizing.gradation import gradation_size
from coastmesh.types import Runner, local_cores, runner_workers, serial_runner

if TYPE_CHECKING:
    from coastmesh.sizing.gradation import Gradation

__all__ = ["BandRunner", "BandTask", "band_count", "graded_band", "graded_sizes"]

#: Bands per worker: a few, so that one slow band does not hold the rest up.
BANDS_PER_WORKER = 2
#: A band has at least this many rows (its vertices' tree costs as the band's
#: box, widened by the search bound, holds vertices).
MIN_BAND_ROWS = 16


@dataclass(frozen=True, slots=True)
class BandTask:
    """One band of grid rows and what its sizes need.

    Attributes
    ----------
    rows : (int, int)
        The band's first row and the row after its last.
    nodes : ndarray of shape (rows * nx, 3)
        Its nodes, earth-centred, row by row.
    width : int
        Nodes per row (nx).
    vertices : tuple of ndarray of shape (k, 3)
        Per gradation, the earth-centred vertices that can be nearest to a
        node of the band (k may be 0).
    terms : tuple of (h_min, d_hold, d_grade)
        Per gradation, metres.
    h_max, resolution : float
        Metres.
    """

    rows: tuple[int, int]
    nodes: NDArray[np.float64]
    width: int
    vertices: tuple[NDArray[np.float64], ...]
    terms: tuple[tuple[float, float, float], ...]
    h_max: float
    resolution: float

    @property
    def label(self) -> str:
        """Names the band in an error."""
        return f"size field rows {self.rows[0]} to {self.rows[1] - 1}"

    @property
    def expected(self) -> float:
        """The task's cost, for handing out the longest first."""
        return float(len(self.nodes) + sum(len(v) for v in self.vertices))


#: The runner of :func:`graded_sizes`'s bands: :func:`graded_band` on each task.
BandRunner = Runner[BandTask, NDArray[np.float64]]


def graded_band(task: BandTask) -> NDArray[np.float64]:
    """Return the band's size (rows, nx): the minimum over its gradations."""
    size = np.full(len(task.nodes), float(task.h_max))
    for vertices, (h_min, d_hold, d_grade) in zip(
        task.vertices, task.terms, strict=True
    ):
        if len(vertices):
            distance = nearest_arcs(
                vertices,
                task.nodes,
                resolution=task.resolution,
                max_distance=d_hold + d_grade,
            )
        else:  # nothing within reach: as the whole grid's search finds there
            distance = np.full(len(task.nodes), np.inf)
        np.minimum(
            size,
            gradation_size(distance, h_min, task.h_max, d_hold, d_grade),
            out=size,
        )
    return size.reshape(-1, task.width)


def graded_sizes(
    x: NDArray[np.float64],
    y: NDArray[np.float64],
    gradations: list[Gradation],
    *,
    crs: CRS,
    h_max: float,
    resolution: float,
    runner: BandRunner | None = None,
    bands: int | None = None,
) -> NDArray[np.float64]:
    """Return the gradations' size (ny, nx) on the grid of nodes ``x``, ``y``.

    Parameters
    ----------
    x, y : ndarray
        The grid's node coordinates in ``crs``.
    gradations : list of Gradation
        Combined by minimum, each growing to ``h_max``; one with no lines is
        skipped.
    crs : pyproj.CRS
    h_max, resolution : float
        Metres; ``resolution`` is the distances' accuracy.
    runner : Runner, optional
        Where the bands run.
    bands : int, optional
        Bands of rows (at most one per :data:`MIN_BAND_ROWS` rows). Default:
        :func:`band_count`.

    Returns
    -------
    ndarray of shape (len(y), len(x))
        The same for any runner.
    """
    gradations = [g for g in gradations if _has_lines(g)]
    size = np.full((len(y), len(x)), float(h_max))
    if not gradations:
        return size
    nodes = grid_nodes(x, y, crs)
    vertices = [line_vertices(g.lines, crs, resolution) for g in gradations]
    bounds = [chord_bound(g.d_hold + g.d_grade, resolution) for g in gradations]
    terms = tuple((g.h_min, g.d_hold, g.d_grade) for g in gradations)
    count = band_count(runner) if bands is None else int(bands)
    count = max(min(count, len(y) // MIN_BAND_ROWS), 1)
    edges = np.linspace(0, len(y), count + 1).round().astype(int)
    tasks = []
    for r0, r1 in itertools.pairwise(edges):
        band = nodes[r0 * len(x) : r1 * len(x)]
        near = vertices if count == 1 else _within_reach(band, vertices, bounds)
        tasks.append(
            BandTask(
                (int(r0), int(r1)),
                band,
                len(x),
                tuple(near),
                terms,
                float(h_max),
                float(resolution),
            )
        )
    run = runner if count > 1 and runner is not None else serial_runner
    for task, band_size in zip(tasks, run(graded_band, tasks), strict=True):
        size[task.rows[0] : task.rows[1]] = band_size
    return size


def band_count(runner: Any) -> int:
    """Return the bands :func:`graded_sizes` makes by default for ``runner``.

    One, computed here, unless the runner reaches more workers than this
    machine has cores (a Dask cluster of several machines): then
    :data:`BANDS_PER_WORKER` per worker. On one machine the k-d tree's queries
    already run on every core (threads); measured on the NW-shelf fine grid
    (837,000 nodes, 4 gradations, 2 cores), 4 bands on 2 worker processes took
    7.6 s against 5.8 s for one band here: each band builds its own trees
    over the vertices within reach, about half of them each.
    """
    workers = runner_workers(runner)
    return BANDS_PER_WORKER * workers if workers > local_cores() else 1


def _within_reach(
    band: NDArray[np.float64],
    vertices: list[NDArray[np.float64]],
    bounds: list[float],
) -> list[NDArray[np.float64]]:
    """Per gradation, its vertices in the band's box widened by the search bound."""
    low, high = band.min(axis=0), band.max(axis=0)
    near = []
    for v, bound in zip(vertices, bounds, strict=True):
        pad = bound * (1 + 1e-9) + 1.0  # keeps every vertex within bound
        near.append(v[((v >= low - pad) & (v <= high + pad)).all(axis=1)])
    return near


def _has_lines(g: Gradation) -> bool:
    lines = np.asarray(g.lines, dtype=object)
    return len(lines) > 0 and not shapely.is_empty(lines).all()
