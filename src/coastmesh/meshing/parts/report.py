"""How the water was cut into parts, and what each part cost."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from coastmesh.meshing.cleanup.report import CleanupReport
from coastmesh.meshing.parts.cuts import MIN_PART_TRIANGLES, OVERSIZE
from coastmesh.meshing.parts.tasks import PartMesh, PartTask
from coastmesh.types import Report

__all__ = ["PartsReport", "oversize_parts"]


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
    oversize : tuple of str
        Each part left holding over :data:`~coastmesh.meshing.parts.cuts.OVERSIZE`
        shares of the expected triangles, where it is and why it was not cut
        (:func:`oversize_parts`).
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
    oversize: tuple[str, ...] = ()

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
        expected = tuple(round(t.expected, 1) for t in tasks)
        return cls(
            requested,
            wanted,
            cuts,
            expected,
            tuple(len(p.triangles) for p in results),
            tuple(p.seconds for p in results),
            tuple(p.worker for p in results),
            centres,
            tuple(c.seconds for c in cleaned),
            cleanup,
            oversize_parts(expected, wanted, centres),
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
            "oversize": list(self.oversize),
        }

    def summary(self) -> str:
        """One line: parts, balance, and the projected speed-ups.

        The balance is the largest part over its share: all the triangles
        over the parts wanted (a cut crossing the water more than once makes
        more parts, some of them slivers, which a mean would count). Parts
        left over :data:`~coastmesh.meshing.parts.cuts.OVERSIZE` shares follow,
        with why (:attr:`oversize`).

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
            + "".join(f"; {why}" for why in self.oversize)
        )


def oversize_parts(
    expected: Sequence[float],
    wanted: int,
    centres: Sequence[tuple[float, float]] = (),
) -> tuple[str, ...]:
    """Say which parts hold over ``OVERSIZE`` shares of the expected triangles, and why.

    A share is the expected triangles over the parts ``wanted``, as the cuts
    measure it. The cuts try to cut every such part
    (:mod:`~coastmesh.meshing.parts.cuts`), so one is left so only if it
    holds under twice ``MIN_PART_TRIANGLES`` (too few to make two parts of)
    or no straight cut splits it: every line tried would make thin triangles
    where it crosses the part, and cut only where it crosses cleanly it
    leaves the part whole or nearly.

    Parameters
    ----------
    expected : sequence of float
        Each part's expected triangles.
    wanted : int
        The number of parts aimed at.
    centres : sequence of (float, float), optional
        A point inside each part (in the output CRS), named in the text.

    Examples
    --------
    >>> why = oversize_parts((30_000.0, 5_000.0, 5_000.0), 4, ((1.5, 2.0),) * 3)
    >>> why[0].split(": ")[0]
    'part 1 holds 3.00 shares (30,000 expected triangles; at 1.5, 2)'
    >>> oversize_parts((18_000.0, 2_000.0), 8)[0].split(": ")[1]
    'too few expected triangles to cut in two (under 2 x 10,000)'
    """
    if not expected:
        return ()
    share = float(sum(expected)) / max(int(wanted), 1)
    out = []
    for k, e in enumerate(expected):
        if e <= OVERSIZE * share:
            continue
        if e < 2 * MIN_PART_TRIANGLES:
            why = (
                "too few expected triangles to cut in two "
                f"(under 2 x {MIN_PART_TRIANGLES:,})"
            )
        else:
            why = (
                "no straight cut splits it without thin triangles, even where it "
                "crosses cleanly only"
            )
        at = f"; at {centres[k][0]:.6g}, {centres[k][1]:.6g}" if centres else ""
        out.append(
            f"part {k + 1} holds {e / share:.2f} shares ({e:,.0f} expected "
            f"triangles{at}): {why}"
        )
    return tuple(out)


def _count(n: int, noun: str) -> str:
    """Return ``"1 worker"``, ``"2 workers"``."""
    return f"{n} {noun}{'' if n == 1 else 's'}"
