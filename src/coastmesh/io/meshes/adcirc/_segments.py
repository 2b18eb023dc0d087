"""The boundary segments of a ``fort.14`` or ``hgrid.gr3``, by each model's rules.

A mesh's boundary is a set of rings of edges, each edge with a boundary id of
kind ``"open"`` or ``"shoreline"``. The grid files list it as node strings, and
each model reads those strings by rules of its own. The rules below were read in
the models' sources and docs (``adcirc/adcirc`` at c622c78,
``schism-dev/schism`` at 820ac00); each is named here, and the test suite checks
written files against them with a checker of its own (``tests/models``).

ADCIRC (``fort.14``):

A1. All external boundaries are listed in consecutive order around the outside
    of the domain before any internal (island) segment
    (``docs/user_guide/model_configuration/boundary_conditions/
    flux_specified_boundaries.rst``, "General Notes for Normal Flow Boundary
    Conditions").
A2. An external no-flow boundary that surrounds the domain (a lake) is closed by
    repeating its first node as the last (same page).
A3. Each island is one segment of an internal type (``IBTYPE`` 1, 11 or 21),
    closed by repeating its first node (same page). An island cut into several
    unclosed external pieces makes ADCIRC list each seam node twice, each time
    with a dummy inner angle and another normal (``src/mesh.F``:
    ``NBVV(K,0) = NBVV(K,1)``, ``THETA = -9999999``), and apply the no-normal-flow
    rewrite of the momentum equations twice.
A4. An unclosed segment starts and ends where two boundaries meet (same page:
    "always start listing the boundary nodes where two boundaries connect"):
    an external land segment runs from one open boundary to the next, so the
    coast between two open boundaries is one segment whatever shoreline sets
    make it up.
A5. No node is listed twice among the open (elevation) segments: ``src/gwce.F``
    adds the forced tide once per listing (``DO I=1,NETA ... Eta2(NBDI) =
    Eta2(NBDI) + ...``), so a corner in two open segments gets it twice. Open
    boundaries that meet are one segment, and a ring that is open all round is
    listed once, not closed.

SCHISM (``hgrid.gr3``):

S1. An open segment does not end on its first node: ``src/Hydro/grid_subs.F90``
    (``aquire_hgrid``) stops on a "Looped open bnd".
S2. A node lies on at most two open segments (``grid_subs.F90``: "node on more
    than 2 open bnds"); so open boundaries that meet may share their corner.
S3. Every boundary node lies on an open or a land segment: ``grid_subs.F90``
    marks the boundary nodes from the lists (``isbnd_global``), and a boundary
    node it did not mark stops the run ("Incomplete ball").
S4. ``docs/input-output/hgrid.md``: land segments have flag 0 on the exterior and
    1 on islands, an island is one segment whose last node is not its first, and
    a ring with no other boundary on it is two segments linked at both ends;
    WWM reads the flags and allows no open boundary on an island.

So both models get each island as one segment and each stretch of coast between
two open boundaries as one segment, whatever shoreline sets make them up; only
the open boundaries differ (one segment per run in ADCIRC, one per boundary id
in SCHISM, sharing their corners). The ids of the edges along a segment are kept
in the comment after its counts (:func:`label`), which both models skip.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from coastmesh.errors import ConfigError
from coastmesh.io.meshes._model import mesh_boundary_rings
from coastmesh.io.meshes.sphere import on_sphere
from coastmesh.types import Mesh
from coastmesh.types.topology import BoundaryRing

__all__ = [
    "DEFAULT_LAND",
    "LAND_TYPES",
    "Segment",
    "grid_segments",
    "label",
    "land_codes",
    "outside_rings",
]

# fort.14 IBTYPE of (external land, island) for each choice of writer option
LAND_TYPES = {"essential": (0, 1), "natural": (20, 21)}
#: the default land types (``fort.14``): see :func:`land_codes`
DEFAULT_LAND = "essential"
_GR3_FLAGS = (0, 1)  # hgrid.md: 0 exterior land, 1 island


@dataclass(frozen=True, slots=True)
class Segment:
    """One node string of a grid file, as written.

    Attributes
    ----------
    nodes : ndarray of int
        Node indices (0-based) in the order written, the domain on the left; a
        closed segment repeats its first node at the end.
    runs : tuple of (int, int)
        ``(k, id)`` for each run of boundary ids along the segment: the edge
        from ``nodes[k]`` to ``nodes[k + 1]`` and the edges after it, up to the
        next run, have boundary id ``id``. The first run starts at 0.
    open : bool
        An open (elevation) segment, else a land segment.
    code : int or None
        The number written after the count: ``IBTYPEE`` or ``IBTYPE`` in a
        ``fort.14``, the land flag in a ``hgrid.gr3``; None for a gr3 open
        segment, whose header holds the count only.
    """

    nodes: NDArray[np.int64]
    runs: tuple[tuple[int, int], ...]
    open: bool
    code: int | None


def land_codes(land: str) -> tuple[int, int]:
    """Return the ``fort.14`` IBTYPE of external land and of islands for ``land``.

    Parameters
    ----------
    land : {"essential", "natural"}
        ADCIRC's essential no-normal-flow boundaries (``IBTYPE`` 0 and 1: the
        normal velocity set to zero at every coast node in the momentum
        equations, and no flux in the continuity equation) or natural ones (20
        and 21: no flux in the continuity equation only). Essential is the
        default: ADCIRC's docs prefer the natural types
        (``flux_specified_boundaries.rst``), but with them the smoke test on
        the Vestfjorden coast (``tests/data/coasts``: 1 to 3 m coast nodes
        beside 155 m ones) stopped at 2.9 h, and with the essential ones it
        ran the whole cycle (0.86 m/s); the demo ran with both.

    Returns
    -------
    tuple of int
        (external, island).

    Raises
    ------
    ConfigError
        If ``land`` is neither.

    Examples
    --------
    >>> land_codes("natural"), land_codes("essential")
    ((20, 21), (0, 1))
    """
    try:
        return LAND_TYPES[land]
    except (KeyError, TypeError):
        raise ConfigError(
            f"land={land!r}; expected one of {', '.join(map(repr, LAND_TYPES))}: "
            "ADCIRC's natural (IBTYPE 20/21) or essential (0/1) no-normal-flow "
            "boundaries"
        ) from None


def grid_segments(
    mesh: Mesh,
    name: str,
    kinds: dict[int, str],
    flavour: str,
    *,
    land: str = DEFAULT_LAND,
) -> tuple[list[Segment], list[Segment]]:
    """Return the open and the land segments of a grid file, in the order written.

    Parameters
    ----------
    mesh : Mesh
        The mesh; its boundary edges must form simple rings.
    name : str
        The output file, for messages.
    kinds : dict of int to str
        The kind of every boundary id (``"open"`` or ``"shoreline"``).
    flavour : {"fort14", "gr3"}
        ADCIRC's rules or SCHISM's (module docstring).
    land : {"essential", "natural"}, default "essential"
        The ``fort.14`` land types (:func:`land_codes`); not used for gr3.

    Returns
    -------
    open_segments, land_segments : list of Segment
        Rings on the outside of the domain (the exterior; in the plane, every
        ring that runs counter-clockwise) come first, in the order of
        :func:`~coastmesh.types.topology.boundary_rings`, then the other rings
        with an open part, then the islands. Along a ring with open and land
        parts, segments start where an open boundary begins and follow the
        ring with the domain on the left.

    Examples
    --------
    A square whose south side is open (id 2) and whose other sides are two
    shoreline sets (1 and 3): in ADCIRC, the coast is one segment of two runs.

    >>> m = Mesh([[0, 0], [1, 0], [1, 1], [0, 1]], [[0, 1, 2], [0, 2, 3]],
    ...          [[0, 1], [1, 2], [2, 3], [3, 0]], [2, 1, 3, 3], 1, None)
    >>> kinds = {1: "shoreline", 2: "open", 3: "shoreline"}
    >>> opened, land = grid_segments(m, "fort.14", kinds, "fort14")
    >>> [(s.nodes.tolist(), s.runs, s.code) for s in opened + land]
    [([0, 1], ((0, 2),), 0), ([1, 2, 3, 0], ((0, 1), (1, 3)), 0)]
    """
    external, island = land_codes(land) if flavour == "fort14" else _GR3_FLAGS
    rings = mesh_boundary_rings(mesh, name)
    outside = outside_rings(mesh, rings)
    groups: dict[str, list[Segment]] = {
        key: [] for key in ("open0", "open1", "land0", "land1", "islands")
    }
    open_ids = np.array([i for i, kind in kinds.items() if kind == "open"], np.int64)
    for ring, out in zip(rings, outside, strict=True):
        is_open = np.isin(ring.ids, open_ids)
        rank = "0" if out else "1"
        if not is_open.any():
            key = "land0" if out else "islands"
            code = external if out else island
            groups[key] += _whole(
                ring, flavour, opened=False, code=code, island=not out
            )
        elif is_open.all():
            groups["open" + rank] += _whole(ring, flavour, opened=True, code=None)
        else:
            opened, landed = _split(ring, is_open, flavour, external)
            groups["open" + rank] += opened
            groups["land" + rank] += landed
    return (
        groups["open0"] + groups["open1"],
        groups["land0"] + groups["land1"] + groups["islands"],
    )


def label(runs: tuple[tuple[int, int], ...], names: dict[int, str]) -> str:
    """Return the comment that names a segment's boundary ids, after its counts.

    One id: ``": id 2 north"``. Several: each run after the first gives the
    1-based position of its first node in the segment, ``": id 10 near; id 5
    @301 far"``: the edges from the 301st node on have id 5. Names keep one
    space between words; a ``;`` in a name is written as ``,``. ADCIRC and
    SCHISM read the counts list-directed and skip the rest of the line;
    :func:`~coastmesh.io.meshes.adcirc.read_fort14_mesh` reads it back.

    Examples
    --------
    >>> label(((0, 10), (300, 5)), {10: "near  coast", 5: "far"})
    ': id 10 near coast; id 5 @301 far'
    """
    parts = []
    for k, (start, pid) in enumerate(runs):
        name = " ".join(names.get(pid, "").replace(";", ",").split())
        at = f" @{start + 1}" if k else ""
        parts.append(f"id {pid}{at}" + (f" {name}" if name else ""))
    return ": " + "; ".join(parts)


def outside_rings(mesh: Mesh, rings: list[BoundaryRing]) -> list[bool]:
    """Return whether each ring bounds the domain from outside (ADCIRC's "external").

    On the sphere, the ring :func:`~coastmesh.io.meshes.sphere.sphere_boundary_rings`
    calls exterior. In the plane, every ring that runs counter-clockwise with
    the domain on its left: the exterior, and the outer ring of each other
    piece of water that does not touch it.
    """
    if on_sphere(mesh):
        return [ring.exterior for ring in rings]
    out = []
    for ring in rings:
        xy = mesh.points[ring.nodes]
        x, y = xy[:, 0] - xy[:, 0].mean(), xy[:, 1] - xy[:, 1].mean()
        area = float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))
        out.append(ring.exterior or area > 0)
    return out


def _runs(ids: NDArray[np.int64]) -> tuple[tuple[int, int], ...]:
    """``(k, id)`` at each change of id along a sequence of edge ids."""
    starts = np.flatnonzero(np.r_[True, ids[1:] != ids[:-1]])
    return tuple((int(k), int(ids[k])) for k in starts)


def _whole(
    ring: BoundaryRing,
    flavour: str,
    *,
    opened: bool,
    code: int | None,
    island: bool = False,
) -> list[Segment]:
    """Return the segments of a ring of one kind all round (A2, A3, A5; S1-S4)."""
    nodes, ids = ring.nodes, ring.ids
    if flavour == "fort14":
        if opened:  # A5: each node once, not closed
            # the edge back to the first node is not listed: start the ring where
            # that edge has the id of the edge before it, so no id is lost
            same = np.flatnonzero(ids == np.roll(ids, 1))
            shift = (int(same[0]) + 1) % len(ids) if len(same) else 0
            nodes, ids = np.roll(nodes, -shift), np.roll(ids, -shift)
            return [Segment(nodes, _runs(ids[:-1]), True, 0)]
        # A2, A3: closed by repeating the first node
        return [Segment(np.append(nodes, nodes[0]), _runs(ids), False, code)]
    if island:  # S4: one segment, last node not the first
        return [Segment(nodes.copy(), _runs(ids), False, code)]
    closed = np.append(nodes, nodes[0])
    if opened and len(_runs(ids)) > 1:  # S2: one segment per id, sharing corners
        return _open_by_id(closed, ids)
    # S1, S4: two segments linked at both ends
    half = len(nodes) // 2
    return [
        Segment(closed[: half + 1], _runs(ids[:half]), opened, code),
        Segment(closed[half:], _runs(ids[half:]), opened, code),
    ]


def _open_by_id(closed: NDArray[np.int64], ids: NDArray[np.int64]) -> list[Segment]:
    """gr3 open segments of a run of open edges: one per id (S2).

    ``closed`` holds the run's nodes (one more than ``ids``, its edges' ids).
    """
    out = []
    for a, pid in _runs(ids):
        b = a + int(np.argmax(np.r_[ids[a:] != pid, True]))
        out.append(Segment(closed[a : b + 1], ((0, pid),), True, None))
    return out


def _split(
    ring: BoundaryRing, is_open: NDArray[np.bool_], flavour: str, external: int
) -> tuple[list[Segment], list[Segment]]:
    """Return the segments of a ring of open and land parts, from an open start."""
    k = len(ring.nodes)
    first = int(np.flatnonzero(is_open & ~np.roll(is_open, 1))[0])
    nodes = np.roll(ring.nodes, -first)
    ids = np.roll(ring.ids, -first)
    kind = np.roll(is_open, -first)
    closed = np.append(nodes, nodes[0])
    cuts = np.r_[np.flatnonzero(kind[1:] != kind[:-1]) + 1, k]
    opened: list[Segment] = []
    landed: list[Segment] = []
    start = 0
    for stop in cuts:
        run_ids = ids[start:stop]
        if not kind[start]:
            landed.append(
                Segment(closed[start : stop + 1], _runs(run_ids), False, external)
            )
        elif flavour == "fort14":  # A5: open boundaries that meet are one segment
            opened.append(Segment(closed[start : stop + 1], _runs(run_ids), True, 0))
        else:  # S2: one segment per id, sharing corners
            opened += _open_by_id(closed[start : stop + 1], run_ids)
        start = stop
    return opened, landed
