"""How the water was cut into parts, and what each part cost."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from coastmesh.meshing.cleanup.report import CleanupReport
from coastmesh.meshing.parts.tasks import PartMesh, PartTask
from coastmesh.types import Report

__all__ = ["PartsReport"]


@dataclass(frozen=True, slots=True)
class PartsReport(Report):
    """How the water was cut into parts, and what each part cost.

    Attributes
    ----------
    requested : int or "auto"
        ``parts`` as given.
    wanted : int
        The number of parts aimed at (``"auto"`` resolved).
    cuts : tuple of ndarray of shape (k, 2)
        The pieces of cuts through the water, in the mesh's output CRS.
    expected, triangles, seconds : tuple
        Per part: expected and actual triangles, and Gmsh seconds.
    workers : tuple of str
        Per part: the host and process that meshed it.
    centres : tuple of (float, float)
        Per part: a point inside it, in the output CRS.
    cleanup_seconds : tuple of float
        Per part: the seconds its cleanup took where it was meshed (none if
        it was not cleaned).
    cleanup : CleanupReport or None
        The cleanup of the whole mesh, the parts' combined
        (:func:`~coastmesh.meshing.cleanup.report.combine`); None if the parts
        were not cleaned. It is there for one part too.
    """

    requested: int | str
    wanted: int
    cuts: tuple[NDArray[np.float64], ...]
    expected: tuple[float, ...]
    triangles: tuple[int, ...]
    seconds: tuple[float, ...]
    workers: tuple[str, ...]
    centres: tuple[tuple[float, float], ...] = ()
    cleanup_seconds: tuple[float, ...] = ()
    cleanup: CleanupReport | None = None

    @classmethod
    def of(
        cls,
        requested: int | str,
        wanted: int,
        tasks: Sequence[PartTask],
        results: Sequence[PartMesh],
        cuts: tuple[NDArray[np.float64], ...],
        centres: tuple[tuple[float, float], ...] = (),
        cleanup: CleanupReport | None = None,
    ) -> PartsReport:
        """Collect the report of a run (no tasks: one part)."""
        results = sorted(results, key=lambda p: p.index)
        cleaned = [p.cleanup for p in results if p.cleanup is not None]
        return cls(
            requested,
            wanted,
            cuts,
            tuple(round(t.expected, 1) for t in tasks),
            tuple(len(p.triangles) for p in results),
            tuple(p.seconds for p in results),
            tuple(p.worker for p in results),
            centres,
            tuple(c.seconds for c in cleaned),
            cleanup,
        )

    @property
    def parts(self) -> int:
        """The number of parts meshed (1 when the water was not cut)."""
        return max(len(self.triangles), 1)

    def projected_speedup(self, cores: int) -> float:
        """Return the meshing stage's speed-up on ``cores`` workers, from part times.

        A part's time is its Gmsh and cleanup seconds. The parts are scheduled
        longest first onto the least loaded worker (as a pool that hands out
        the next task to the first free worker does); the speed-up is the
        serial time over the busiest worker's time. It ignores start-up and
        data transfer, and is 1 for one part.

        Examples
        --------
        >>> r = PartsReport(4, 4, (), (1.0,) * 4, (1,) * 4, (3.0, 1.0, 1.0, 1.0), ())
        >>> r.projected_speedup(2), r.projected_speedup(4)
        (2.0, 2.0)
        """
        if not self.seconds:
            return 1.0
        times = np.add(self.seconds, self.cleanup_seconds or 0.0)
        loads = np.zeros(max(int(cores), 1))
        for t in sorted(times, reverse=True):
            loads[int(np.argmin(loads))] += t
        return float(times.sum() / loads.max())

    def to_dict(self) -> dict[str, Any]:
        """Return the report as JSON-ready values (the cuts as their count only)."""
        return {
            "requested": self.requested,
            "wanted": self.wanted,
            "parts": self.parts,
            "cut_pieces": len(self.cuts),
            "expected_triangles": list(self.expected),
            "triangles": list(self.triangles),
            "seconds": list(self.seconds),
            "cleanup_seconds": list(self.cleanup_seconds),
            "workers": sorted(set(self.workers)),
            "projected_speedup": {
                str(n): round(self.projected_speedup(n), 2) for n in (2, 8, 32)
            },
        }

    def summary(self) -> str:
        """One line: parts, balance, and the projected speed-ups.

        The balance is the largest part over its share: all the triangles
        over the parts wanted (a cut crossing the water more than once makes
        more parts, some of them slivers, which a mean would count).

        Examples
        --------
        >>> r = PartsReport(2, 2, (), (1.0,) * 3, (600, 10, 390), (3.0, 0.1, 2.0),
        ...                 ("a", "b", "a"))
        >>> head, tail = r.summary().split("), ")
        >>> head
        '3 parts of 2 wanted (10 to 600 triangles, the largest 1.20 x its share'
        >>> tail.split("; ")[0]
        '5.1 s of Gmsh and 0.0 s of cleanup on 2 workers'
        """
        if not self.seconds:
            return "1 part"
        most = max(self.triangles)
        share = sum(self.triangles) / max(self.wanted, 1)
        return (
            f"{self.parts} parts of {self.wanted} wanted ({min(self.triangles):,} "
            f"to {most:,} triangles, the largest {most / share:.2f} x its share), "
            f"{sum(self.seconds):.1f} s of Gmsh and "
            f"{sum(self.cleanup_seconds):.1f} s of cleanup on "
            f"{_count(len(set(self.workers)), 'worker')}; projected speed-up on "
            "8 / 32 cores "
            f"{self.projected_speedup(8):.1f} / {self.projected_speedup(32):.1f}"
        )


def _count(n: int, noun: str) -> str:
    """Return ``"1 worker"``, ``"2 workers"``."""
    return f"{n} {noun}{'' if n == 1 else 's'}"
