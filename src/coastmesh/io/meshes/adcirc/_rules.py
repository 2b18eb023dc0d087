"""Which of its model's rules a ``fort.14`` or ``hgrid.gr3`` breaks, as written.

The rules are those :mod:`coastmesh.io.meshes.adcirc._segments` names and the writers
follow (A1 to A5 for ADCIRC, S1 to S4 for SCHISM). A file from another tool may
break them; :func:`rule_breaks` lists how, so that ``coastmesh convert`` can say
what writing the mesh anew repaired. Each break names the rule, the node (as
numbered in the file) and the segment.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from coastmesh.io.meshes._model import mesh_boundary_rings
from coastmesh.io.meshes.adcirc._segments import outside_rings
from coastmesh.types import Mesh

__all__ = ["RuleBreak", "rule_breaks"]

_INTERNAL = {1, 11, 21}


@dataclass(frozen=True, slots=True)
class RuleBreak:
    """One rule of a model that a grid file breaks.

    Attributes
    ----------
    rule : str
        ``"A1"`` to ``"A5"`` (ADCIRC), ``"S1"`` to ``"S4"`` (SCHISM).
    node : int
        The node, numbered as in the file (from 1).
    segment : str
        Which segment, such as ``"open segment 2"``.
    text : str
        What is wrong.
    """

    rule: str
    node: int
    segment: str
    text: str

    def __str__(self) -> str:
        return f"{self.rule} at node {self.node} ({self.segment}): {self.text}"


def rule_breaks(grid: dict[str, Any], mesh: Mesh, model: str) -> list[RuleBreak]:
    """List the rules of ``model`` that a grid file's boundary lists break.

    Parameters
    ----------
    grid : dict
        The file as :func:`~coastmesh.io.meshes.adcirc.read_fort14` parses it.
    mesh : Mesh
        The same file as a Mesh (:func:`~coastmesh.io.meshes.adcirc.read_fort14_mesh`),
        for its boundary rings.
    model : {"adcirc", "schism"}
        Whose rules.

    Returns
    -------
    list of RuleBreak
        Empty when the lists follow the rules.

    Examples
    --------
    A corner listed in two open segments, as coastmesh wrote them before:

    >>> m = Mesh([[0, 0], [1, 0], [1, 1], [0, 1]], [[0, 1, 2], [0, 2, 3]],
    ...          [[0, 1], [1, 2], [2, 3], [3, 0]], [2, 3, 1, 1], 1, None,
    ...          boundary_kinds={1: "shoreline", 2: "open", 3: "open"})
    >>> grid = {"open_boundaries": [{"nodes": np.array([1, 2])},
    ...                             {"nodes": np.array([2, 3])}],
    ...         "land_boundaries": [{"nodes": np.array([3, 4, 1]), "ibtype": 0}]}
    >>> (corner,) = rule_breaks(grid, m, "adcirc")
    >>> corner.rule, corner.node, corner.segment
    ('A5', 2, 'open segment 2')
    >>> corner.text
    'also listed in open segment 1; ADCIRC forces the tide there once per listing'
    >>> rule_breaks(grid, m, "schism")  # SCHISM lets two open segments share it
    []
    """
    rings = mesh_boundary_rings(mesh, "the grid")
    ring_of = np.full(len(mesh.points), -1)
    for k, ring in enumerate(rings):
        ring_of[ring.nodes] = k
    outside = outside_rings(mesh, rings)
    opened = [
        (np.asarray(b["nodes"]), f"open segment {k}")
        for k, b in enumerate(grid["open_boundaries"], 1)
    ]
    land = [
        (np.asarray(b["nodes"]), int(b["ibtype"]), f"land segment {k}")
        for k, b in enumerate(grid["land_boundaries"], 1)
    ]
    open_rings = {int(ring_of[n - 1]) for nodes, _ in opened for n in nodes}
    out: list[RuleBreak] = []
    if model == "adcirc":
        out += _adcirc_open(opened)
        out += _adcirc_land(land, opened, ring_of, rings, outside, open_rings)
    else:
        out += _schism_open(opened)
        out += _schism_land(land, opened, ring_of, rings, outside, open_rings)
    return out


def _adcirc_open(opened: list[tuple[np.ndarray, str]]) -> list[RuleBreak]:
    """A5: no node twice among the open segments."""
    out: list[RuleBreak] = []
    seen: dict[int, str] = {}
    for nodes, name in opened:
        for n in nodes.tolist():
            if n in seen:
                out.append(
                    RuleBreak(
                        "A5",
                        n,
                        name,
                        f"also listed in {seen[n]}; "
                        "ADCIRC forces the tide there once per listing",
                    )
                )
            seen.setdefault(n, name)
    return out


def _adcirc_land(land, opened, ring_of, rings, outside, open_rings) -> list[RuleBreak]:
    """A1 to A4 on the land segments."""
    out = []
    ends = {int(n[0]) for n, _ in opened} | {int(n[-1]) for n, _ in opened}
    internal_seen = None
    for nodes, code, name in land:
        first, last = int(nodes[0]), int(nodes[-1])
        ring = int(ring_of[first - 1])
        if code in _INTERNAL:
            internal_seen = internal_seen or name
        elif internal_seen is not None:
            out.append(
                RuleBreak(
                    "A1",
                    first,
                    name,
                    f"an external segment after {internal_seen}, an island",
                )
            )
        if ring < 0:
            continue
        if ring in open_rings:
            for end in sorted({first, last} - ends):
                out.append(
                    RuleBreak(
                        "A4",
                        end,
                        name,
                        "ends where no open boundary "
                        "does (a seam between two land segments)",
                    )
                )
            continue
        rule = "A2" if outside[ring] else "A3"
        whole = first == last and len(nodes) == len(rings[ring].nodes) + 1
        if not whole:
            out.append(
                RuleBreak(
                    rule,
                    first,
                    name,
                    "part of a ring of land, which "
                    "must be one segment closed by its first node",
                )
            )
        elif (code in _INTERNAL) == outside[ring]:
            out.append(
                RuleBreak(
                    rule,
                    first,
                    name,
                    f"IBTYPE {code} on "
                    f"{'the outside' if outside[ring] else 'an island'}",
                )
            )
    return out


def _schism_open(opened: list[tuple[np.ndarray, str]]) -> list[RuleBreak]:
    """S1 and S2 on the open segments."""
    out: list[RuleBreak] = []
    count: dict[int, int] = {}
    for nodes, name in opened:
        if len(nodes) > 1 and nodes[0] == nodes[-1]:
            out.append(
                RuleBreak(
                    "S1",
                    int(nodes[0]),
                    name,
                    "ends on its first node (SCHISM: 'Looped open bnd')",
                )
            )
        for n in set(nodes.tolist()):
            count[n] = count.get(n, 0) + 1
            if count[n] == 3:
                out.append(RuleBreak("S2", n, name, "on three open segments"))
    return out


def _schism_land(land, opened, ring_of, rings, outside, open_rings) -> list[RuleBreak]:
    """S3 and S4: every boundary node listed; islands one segment of flag 1."""
    out = []
    listed = {n for nodes, _ in opened for n in nodes.tolist()}
    listed |= {n for nodes, _, _ in land for n in nodes.tolist()}
    for ring in rings:
        for n in ring.nodes.tolist():
            if n + 1 not in listed:
                out.append(
                    RuleBreak(
                        "S3",
                        n + 1,
                        "no segment",
                        "a boundary node on no segment (SCHISM: 'Incomplete ball')",
                    )
                )
                break
    for nodes, code, name in land:
        ring = int(ring_of[int(nodes[0]) - 1])
        if ring < 0 or ring in open_rings or outside[ring]:
            continue
        if code != 1 or len(nodes) != len(rings[ring].nodes) or nodes[0] == nodes[-1]:
            out.append(
                RuleBreak(
                    "S4",
                    int(nodes[0]),
                    name,
                    "part of an island, which is one segment of flag 1, not closed",
                )
            )
    return out
