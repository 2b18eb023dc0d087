"""``[[mesh_size.gradations]]``: the paper's gradations from named lines.

The size is ``h_min`` at the named ``lines`` (shoreline sets, open boundaries
and ``[[structures]]``, as they lie on the domain boundary, and the outlines
of ``[[farms]]``). It is kept for ``d_hold``, then
grows linearly to ``h_max`` over ``d_grade``. Several gradations combine by their
minimum. Distances are true distances on the Earth (great-circle distances on a
global case's grid).
"""

from __future__ import annotations

import warnings
from collections.abc import Set as AbstractSet
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import shapely

from coastmesh.case import schema
from coastmesh.case.schema import key
from coastmesh.case.terms.base import SizeCase, SizeTerm
from coastmesh.errors import CoastmeshWarning, ConfigError
from coastmesh.sizing.combine import TermSizes
from coastmesh.sizing.gradation import Gradation
from coastmesh.sizing.grid import Grid

if TYPE_CHECKING:
    from coastmesh.case.config import CaseConfig

__all__ = ["GradationConfig", "Gradations"]


@dataclass(frozen=True)
class GradationConfig:
    """One ``[[mesh_size.gradations]]`` entry."""

    lines: tuple[str, ...] = key(
        check=schema.names,
        doc="the shoreline sets, open boundaries, structures and farms graded "
        "from, by name",
    )
    h_min: float = key(
        check=schema.length(), unit="length", doc="the size at the lines"
    )
    d_grade: float = key(
        check=schema.length(),
        unit="length",
        doc="the distance over which the size then grows linearly to `h_max`",
    )
    d_hold: float = key(
        0.0,
        check=schema.length(positive=False),
        unit="length",
        doc="the distance over which `h_min` holds first",
    )


class Gradations(SizeTerm[tuple[GradationConfig, ...]]):
    """The term of ``[mesh_size.gradations]``."""

    key = "gradations"
    config = GradationConfig
    many = True
    default = ()
    doc = "the paper's gradations from named lines (below)"
    floors = True

    def check(
        self,
        settings: tuple[GradationConfig, ...],
        case: CaseConfig,
        *,
        label: str,
        lines: AbstractSet[str],
    ) -> None:
        """Every name in a gradation's ``lines`` is a line of the case."""
        for k, g in enumerate(settings):
            for n in g.lines:
                if n not in lines:
                    raise ConfigError(
                        f"{label}: mesh_size.gradations[{k}].lines: {n!r} is not a "
                        "shoreline set, open boundary, farm or structure; known: "
                        f"{sorted(lines)}"
                    )

    def smallest(self, settings: tuple[GradationConfig, ...]) -> float | None:
        """Return the smallest gradation's ``h_min``."""
        return min((g.h_min for g in settings), default=None)

    def sizes(self, grid: Grid, case: SizeCase) -> TermSizes:
        """Grade the size from each gradation's lines (domain segments by name).

        A name may also be one of ``case.lines``: a farm's outline.

        A gradation whose lines have no edge on the domain's boundary is
        skipped, with a warning.
        """
        graded = []
        for k, g in enumerate(self.settings(case)):
            wanted = set(g.lines)
            lines = [
                shapely.LineString(s.coords)
                for s in case.domain.segments
                if s.name in wanted
            ]
            lines += [case.lines[n] for n in sorted(wanted & set(case.lines))]
            if not lines:
                warnings.warn(
                    f"mesh_size.gradations[{k}]: {sorted(wanted)} have no edges on "
                    "the domain boundary; the gradation is skipped",
                    CoastmeshWarning,
                    stacklevel=2,
                )
                continue
            graded.append(
                Gradation(
                    np.array(lines, dtype=object),
                    h_min=g.h_min,
                    d_hold=g.d_hold,
                    d_grade=g.d_grade,
                    name=",".join(g.lines),
                )
            )
        upper = grid.graded(
            graded,
            lines_crs=case.domain.crs,
            h_max=case.config.size.h_max,
            runner=case.runner,
        )
        return TermSizes(upper=upper, history=f"{len(graded)} gradations")
