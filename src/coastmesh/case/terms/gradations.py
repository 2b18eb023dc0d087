"""``[[mesh_size.gradations]]``: the paper's gradations from named lines.

The size is ``h_min`` at the named ``lines`` (shoreline sets and open boundaries,
as they lie on the domain's boundary), kept for ``d_hold``, then growing
linearly to ``h_max`` over ``d_grade``; several gradations combine by their
minimum. Distances are true distances on the Earth.
"""

from __future__ import annotations

from dataclasses import dataclass

from coastmesh.case import schema
from coastmesh.case.schema import key
from coastmesh.case.terms.base import SizeTerm

__all__ = ["GradationConfig", "Gradations"]


@dataclass(frozen=True)
class GradationConfig:
    """One ``[[mesh_size.gradations]]`` entry."""

    lines: tuple[str, ...] = key(
        check=schema.names,
        doc="the shoreline sets and open boundaries graded from, by name",
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


class Gradations(SizeTerm):
    """The term of ``[mesh_size.gradations]``."""

    key = "gradations"
    config = GradationConfig
    many = True
    default = ()
    doc = "the paper's gradations from named lines (below)"
