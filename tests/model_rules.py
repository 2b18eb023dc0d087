"""The models' own rules for grid and boundary files, checked on written files.

A checker written apart from coastmesh's writers and readers: it parses each file
itself, with numpy alone, and checks what ADCIRC, SCHISM and Telemac ask of the
boundary lists, as their sources and docs state them:

ADCIRC ``fort.14`` (``adcirc/adcirc``, c622c78):

- ``A1`` external boundaries are listed before any island (internal) segment,
  and those of one ring in order around it (``docs/user_guide/
  model_configuration/boundary_conditions/flux_specified_boundaries.rst``,
  "General Notes for Normal Flow Boundary Conditions");
- ``A2`` a ring of land with no open boundary that surrounds the domain (a lake)
  is one external segment closed by repeating its first node (same page);
- ``A3`` an island is one internal segment (``IBTYPE`` 1, 11, 21) closed by
  repeating its first node (same page; ``src/mesh.F`` closes an unclosed
  internal segment itself and treats every unclosed segment's ends as ends of
  the boundary, with a dummy inner angle);
- ``A4`` an unclosed land segment starts and ends where it meets an open
  segment ("always start listing the boundary nodes where two boundaries
  connect");
- ``A5`` no node is listed twice among the open segments (``src/gwce.F`` adds
  the tide once per listing);
- ``A6`` the types are ones this checker knows: ``IBTYPEE`` 0, ``IBTYPE`` 0,
  1, 10, 11, 20, 21.

SCHISM ``hgrid.gr3`` (``schism-dev/schism``, 820ac00):

- ``S1`` an open segment does not end on its first node (``src/Hydro/
  grid_subs.F90``: "Looped open bnd");
- ``S2`` a node lies on at most two open segments ("node on more than 2 open
  bnds");
- ``S3`` every boundary node lies on a segment (else "Incomplete ball");
- ``S4`` ``docs/input-output/hgrid.md``: an island is one segment of flag 1
  whose last node is not its first, the exterior's land has flag 0, a ring with
  no other boundary is two segments linked at both ends, no open segment on an
  island (WWM).

Telemac SELAFIN + ``.cli`` (``ogoe/OpenTelemac``, BIEF ``elebd.f``,
``front2.f``; HERMES ``utils_serafin.F``):

- ``T1`` the ``.cli`` has one line per boundary node, each once, ``K`` its line
  number (``elebd.f``: ``T3(NBOR(K)) = K``);
- ``T2`` the SELAFIN ``IPOBO`` gives each boundary node its ``.cli`` line, 0 to
  the others;
- ``T3`` no liquid point between two solid points and no solid point between
  two liquid points (``front2.f`` stops on both);
- ``T4`` each contour is listed in order, the next line the next node along
  the boundary with the domain on the left, the exterior first.

All of them also check ``cover``: every boundary edge of the elements is on
exactly one segment (coastmesh's own promise: nothing left for the model to
guess) and each two consecutive nodes of a segment are a boundary edge, run
with the domain on their left.

Each break names the rule, the node (1-based, as in the file) and the segment.
"""

from __future__ import annotations

import itertools
import struct
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

ADCIRC_EXTERNAL = {0, 10, 20}
ADCIRC_INTERNAL = {1, 11, 21}


@dataclass(frozen=True)
class Break:
    """One broken rule."""

    rule: str
    node: int  # 1-based, as in the file
    segment: str
    text: str

    def __str__(self) -> str:
        return f"{self.rule} at node {self.node} ({self.segment}): {self.text}"


@dataclass
class Grid:
    """A fort.14 or hgrid.gr3 as written: 1-based node numbers throughout."""

    xy: np.ndarray
    elements: np.ndarray  # (NE, 3), 1-based
    open: list[tuple[np.ndarray, int | None, str]] = field(default_factory=list)
    land: list[tuple[np.ndarray, int, str]] = field(default_factory=list)


def parse_grid(path: str | Path) -> Grid:
    """Parse a fort.14 or hgrid.gr3 line by line, checking every count."""
    lines = Path(path).read_text().splitlines()
    at = 1
    ne, npt = (int(v) for v in lines[at].split()[:2])
    at += 1
    nodes = np.array([lines[at + k].split()[:4] for k in range(npt)], dtype=float)
    assert (nodes[:, 0] == np.arange(1, npt + 1)).all(), "nodes not numbered 1..NP"
    at += npt
    elements = np.array([lines[at + k].split()[:5] for k in range(ne)], dtype=int)
    assert (elements[:, 1] == 3).all(), "not all triangles"
    at += ne
    grid = Grid(nodes[:, 1:3], elements[:, 2:5])
    for which in ("open", "land"):
        count, total = int(lines[at].split()[0]), int(lines[at + 1].split()[0])
        at += 2
        seen = 0
        for _ in range(count):
            head = lines[at].split("=")[0].split()
            size = int(head[0])
            code = int(head[1]) if len(head) > 1 else None
            body = np.array([int(lines[at + 1 + k].split()[0]) for k in range(size)])
            assert ((body >= 1) & (body <= npt)).all(), "node number out of range"
            name = f"{which} segment {len(getattr(grid, which)) + 1}"
            getattr(grid, which).append((body, code, name))
            seen += size
            at += 1 + size
        assert seen == total, f"{which}: the total {total} is not the {seen} listed"
    assert not any(line.strip() for line in lines[at:]), "lines after the land list"
    return grid


class _Boundary:
    """The boundary of a triangulation: directed edges with the domain on the left."""

    def __init__(self, xy: np.ndarray, elements: np.ndarray) -> None:
        tri = np.asarray(elements)
        area = _areas(xy, tri)
        tri = np.where((area < 0)[:, None], tri[:, ::-1], tri)  # counter-clockwise
        count: dict[tuple[int, int], int] = {}
        directed: dict[tuple[int, int], tuple[int, int]] = {}
        for a, b, c in tri.tolist():
            for p, q in ((a, b), (b, c), (c, a)):
                key = (min(p, q), max(p, q))
                count[key] = count.get(key, 0) + 1
                directed[key] = (p, q)
        self.edges = {directed[k] for k, n in count.items() if n == 1}
        self.next = dict(self.edges)
        self.nodes = set(self.next)
        # rings, and which run counter-clockwise (outside the domain's water)
        self.ring_of: dict[int, int] = {}
        self.rings: list[list[int]] = []
        for start in sorted(self.nodes):
            if start in self.ring_of:
                continue
            ring = [start]
            while self.next[ring[-1]] != start:
                ring.append(self.next[ring[-1]])
            for p in ring:
                self.ring_of[p] = len(self.rings)
            self.rings.append(ring)
        self.external = [_ring_area(xy, ring) > 0 for ring in self.rings]

    def key(self, p: int, q: int) -> tuple[int, int]:
        return (min(p, q), max(p, q))


def _areas(xy: np.ndarray, tri: np.ndarray) -> np.ndarray:
    a, b, c = (xy[tri[:, k] - 1] for k in range(3))
    return (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (
        c[:, 0] - a[:, 0]
    )


def _ring_area(xy: np.ndarray, ring: list[int]) -> float:
    p = xy[np.array(ring) - 1]
    p = p - p.mean(axis=0)
    return 0.5 * float(
        np.dot(p[:, 0], np.roll(p[:, 1], -1)) - np.dot(np.roll(p[:, 0], -1), p[:, 1])
    )


def _cover(
    boundary: _Boundary, segments: list[tuple[list[tuple[int, int]], str]]
) -> list[Break]:
    """Each listed edge a boundary edge with the domain on its left, each once."""
    out: list[Break] = []
    seen: dict[tuple[int, int], str] = {}
    for edges, name in segments:
        for p, q in edges:
            if p == q:
                out.append(Break("cover", p, name, "a node listed twice in a row"))
                continue
            key = boundary.key(p, q)
            if (p, q) not in boundary.edges:
                text = (
                    "runs against the boundary (the domain must be on its left)"
                    if (q, p) in boundary.edges
                    else f"the edge to node {q} is not a boundary edge"
                )
                out.append(Break("cover", p, name, text))
            if key in seen:
                out.append(Break("cover", p, name, f"edge to {q} also in {seen[key]}"))
            seen[key] = name
    for p, q in sorted(boundary.edges):
        if boundary.key(p, q) not in seen:
            out.append(Break("cover", p, "no segment", f"edge to {q} is on no segment"))
    return out


def _whole_ring(boundary: _Boundary, nodes: np.ndarray) -> bool:
    """Whether ``nodes`` lists a whole boundary ring, each node once."""
    ring = boundary.ring_of.get(int(nodes[0]))
    return ring is not None and sorted(nodes.tolist()) == sorted(boundary.rings[ring])


def _pairs(nodes: np.ndarray, close: bool = False) -> list[tuple[int, int]]:
    nodes = nodes.tolist()
    pairs = list(itertools.pairwise(nodes))
    if close and nodes[0] != nodes[-1]:
        pairs.append((nodes[-1], nodes[0]))
    return pairs


def check_adcirc(path: str | Path) -> list[Break]:
    """Every ADCIRC rule (module docstring) that the fort.14 at ``path`` breaks."""
    grid = parse_grid(path)
    boundary = _Boundary(grid.xy, grid.elements)
    # A5: a ring open all round lists each node once; its last edge is implied
    out = _cover(
        boundary,
        [(_pairs(n, close=_whole_ring(boundary, n)), name) for n, _, name in grid.open]
        + [(_pairs(n), name) for n, _, name in grid.land],
    )
    listed: dict[int, str] = {}
    for nodes, code, name in grid.open:
        if code not in (0, None):
            out.append(Break("A6", int(nodes[0]), name, f"IBTYPEE {code}"))
        for p in nodes.tolist():
            if p in listed:
                out.append(Break("A5", p, name, f"also listed in {listed[p]}"))
            listed[p] = name
    open_ends = {int(n[0]) for n, _, _ in grid.open} | {
        int(n[-1]) for n, _, _ in grid.open
    }
    open_rings = {boundary.ring_of[p] for n, _, _ in grid.open for p in n.tolist()}
    internal_seen = None
    ring_order: dict[int, list[int]] = {}
    for k, (nodes, code, name) in enumerate(grid.land):
        first, last = int(nodes[0]), int(nodes[-1])
        closed = first == last
        if code not in ADCIRC_EXTERNAL | ADCIRC_INTERNAL:
            out.append(Break("A6", first, name, f"IBTYPE {code}"))
            continue
        ring = boundary.ring_of.get(first)
        if ring is None:
            continue  # reported by cover
        if code in ADCIRC_INTERNAL:
            internal_seen = name if internal_seen is None else internal_seen
            if boundary.external[ring]:
                out.append(Break("A3", first, name, f"IBTYPE {code} on the outside"))
        elif internal_seen is not None:
            out.append(Break("A1", first, name, f"external, after {internal_seen}"))
        if ring in open_rings:
            if closed:
                out.append(Break("A4", first, name, "closed on a ring with open parts"))
            for end in {first, last} - open_ends:
                out.append(Break("A4", end, name, "ends where no open segment does"))
            ring_order.setdefault(ring, []).append(k)
            continue
        # a ring of land alone: one closed segment of the whole ring
        whole = len(nodes) == len(boundary.rings[ring]) + 1
        rule = "A2" if boundary.external[ring] else "A3"
        if not (closed and whole):
            out.append(Break(rule, first, name, "not one closed segment of its ring"))
        want = ADCIRC_EXTERNAL if boundary.external[ring] else ADCIRC_INTERNAL
        if code not in want:
            out.append(Break(rule, first, name, f"IBTYPE {code} on this ring"))
    out += _ring_order(boundary, grid.land, ring_order)
    return out


def _ring_order(
    boundary: _Boundary, segments: list, ring_order: dict[int, list[int]]
) -> list[Break]:
    """A1: the segments of one ring in order around it, each ring's together."""
    out = []
    for ring, ks in ring_order.items():
        if ks != list(range(ks[0], ks[0] + len(ks))):
            name = segments[ks[0]][2]
            out.append(Break("A1", int(segments[ks[0]][0][0]), name, "ring split up"))
        position = {p: i for i, p in enumerate(boundary.rings[ring])}
        starts = [position[int(segments[k][0][0])] for k in ks]
        turn = int(np.argmin(starts))
        rotated = starts[turn:] + starts[:turn]
        if rotated != sorted(rotated):
            name = segments[ks[0]][2]
            out.append(Break("A1", int(segments[ks[0]][0][0]), name, "out of order"))
    return out


def check_schism(path: str | Path) -> list[Break]:
    """Every SCHISM rule (module docstring) that the hgrid.gr3 at ``path`` breaks."""
    grid = parse_grid(path)
    boundary = _Boundary(grid.xy, grid.elements)
    out = _cover(
        boundary,
        [(_pairs(n), name) for n, _, name in grid.open]
        + [(_pairs(n, close=code == 1), name) for n, code, name in grid.land],
    )
    on_open: dict[int, list[str]] = {}
    for nodes, _, name in grid.open:
        if nodes[0] == nodes[-1]:
            out.append(Break("S1", int(nodes[0]), name, "ends on its first node"))
        for p in set(nodes.tolist()):
            on_open.setdefault(p, []).append(name)
            if len(on_open[p]) == 3:
                out.append(Break("S2", p, name, f"on {', '.join(on_open[p])}"))
    listed = set(on_open)
    for nodes, _, _ in grid.land:
        listed |= set(nodes.tolist())
    for p in sorted(boundary.nodes - listed):
        out.append(Break("S3", p, "no segment", "boundary node on no segment"))
    open_rings = {boundary.ring_of[p] for p in on_open}
    for ring, external in enumerate(boundary.external):
        if ring in open_rings and not external:
            p = boundary.rings[ring][0]
            out.append(Break("S4", p, "island", "an open segment on an island"))
    for nodes, code, name in grid.land:
        first = int(nodes[0])
        ring = boundary.ring_of.get(first)
        if ring is None:
            continue
        if first == int(nodes[-1]):
            out.append(Break("S4", first, name, "ends on its first node"))
        if boundary.external[ring] and code != 0:
            out.append(Break("S4", first, name, f"flag {code} on the exterior"))
        if not boundary.external[ring] and ring not in open_rings:
            if code != 1 or len(nodes) != len(boundary.rings[ring]):
                out.append(
                    Break("S4", first, name, "an island not one segment of flag 1")
                )
    return out


# Telemac ------------------------------------------------------------------------

_KLOG = 2  # LIHBOR of a solid boundary (BIEF leclim.f)


def _records(data: bytes):
    """Yield the Fortran sequential records of a big-endian SELAFIN file."""
    at = 0
    while at < len(data):
        (size,) = struct.unpack(">i", data[at : at + 4])
        yield data[at + 4 : at + 4 + size]
        (end,) = struct.unpack(">i", data[at + 4 + size : at + 8 + size])
        assert end == size, "record markers differ"
        at += 8 + size


def parse_selafin(path: str | Path) -> dict:
    """Read a SELAFIN mesh's IKLE, IPOBO, X and Y (single precision)."""
    rec = list(_records(Path(path).read_bytes()))
    assert rec[0][72:80] == b"SERAFIN ", "not single-precision SERAFIN"
    nbv1 = struct.unpack(">2i", rec[1])[0]
    at = 2 + nbv1
    iparam = struct.unpack(">10i", rec[at])
    at += 1 + (1 if iparam[9] == 1 else 0)
    nelem, npoin, ndp, _ = struct.unpack(">4i", rec[at])
    ikle = np.frombuffer(rec[at + 1], dtype=">i4").reshape(nelem, ndp)
    ipobo = np.frombuffer(rec[at + 2], dtype=">i4")
    x = np.frombuffer(rec[at + 3], dtype=">f4").astype(float)
    y = np.frombuffer(rec[at + 4], dtype=">f4").astype(float)
    assert len(ipobo) == len(x) == len(y) == npoin
    return {
        "ikle": ikle.astype(int),
        "ipobo": ipobo.astype(int),
        "xy": np.column_stack([x, y]),
    }


def parse_cli(path: str | Path) -> np.ndarray:
    """The .cli as an integer table: LIHBOR LIUBOR LIVBOR ... LITBOR ... N K."""
    rows = [line.split() for line in Path(path).read_text().splitlines()]
    assert all(len(r) == 13 for r in rows), "a .cli line without 13 columns"
    table = np.array([[float(v) for v in r] for r in rows])
    return table[:, [0, 1, 2, 7, 11, 12]].astype(int)  # LIH LIU LIV LIT N K


def check_telemac(slf: str | Path, cli: str | Path) -> list[Break]:
    """Every Telemac rule (module docstring) that the .slf and .cli break."""
    mesh = parse_selafin(slf)
    table = parse_cli(cli)
    boundary = _Boundary(mesh["xy"], mesh["ikle"])
    out: list[Break] = []
    nbor, kcol = table[:, 4], table[:, 5]
    for k, (n, kk) in enumerate(zip(nbor.tolist(), kcol.tolist(), strict=True), 1):
        if kk != k:
            out.append(Break("T1", n, f"line {k}", f"K = {kk}"))
    seen: dict[int, int] = {}
    for k, n in enumerate(nbor.tolist(), 1):
        if n in seen:
            out.append(Break("T1", n, f"line {k}", f"also on line {seen[n]}"))
        seen[n] = k
    for n in sorted(boundary.nodes - set(seen)):
        out.append(Break("T1", n, "no line", "boundary node not in the .cli"))
    for n in sorted(set(seen) - boundary.nodes):
        out.append(Break("T1", n, f"line {seen[n]}", "not a boundary node"))
    want = np.zeros(len(mesh["ipobo"]), dtype=int)
    for n, k in seen.items():
        want[n - 1] = k
    for n in np.flatnonzero(mesh["ipobo"] != want)[:10]:
        out.append(
            Break("T2", int(n) + 1, "IPOBO", f"{mesh['ipobo'][n]} not {want[n]}")
        )
    if out:
        return out
    lih = table[:, 0]
    line_of = {n: k - 1 for n, k in seen.items()}
    following = {line_of[p]: line_of[boundary.next[p]] for p in boundary.nodes}
    preceding = {f: k for k, f in following.items()}
    for k in range(len(table)):
        l1, l2, l3 = lih[preceding[k]], lih[k], lih[following[k]]
        n = int(nbor[k])
        if l1 == _KLOG and l2 != _KLOG and l3 == _KLOG:
            out.append(Break("T3", n, f"line {k + 1}", "liquid between two solid"))
        if l1 != _KLOG and l2 == _KLOG and l3 != _KLOG:
            out.append(Break("T3", n, f"line {k + 1}", "solid between two liquid"))
    # T4: each contour's lines in order along it, the exterior's first
    k = 0
    while k < len(table):
        ring = boundary.ring_of[int(nbor[k])]
        size = len(boundary.rings[ring])
        if k == 0 and not boundary.external[ring]:
            out.append(Break("T4", int(nbor[0]), "line 1", "first contour an island"))
        for j in range(k, k + size):
            after = j + 1 if j + 1 < k + size else k
            if following[j] != after:
                out.append(
                    Break("T4", int(nbor[j]), f"line {j + 1}", "next line not next")
                )
                break
        k += size
    return out


def liquid_boundaries(slf: str | Path, cli: str | Path) -> int:
    """How many liquid boundaries Telemac finds (``front2.f``'s count)."""
    mesh = parse_selafin(slf)
    table = parse_cli(cli)
    boundary = _Boundary(mesh["xy"], mesh["ikle"])
    lih, liu, nbor = table[:, 0], table[:, 1], table[:, 4]
    line_of = {int(n): k for k, n in enumerate(nbor)}
    count = 0
    for ring in boundary.rings:
        ks = [line_of[p] for p in ring]
        liquid_edges = [
            lih[a] != _KLOG and lih[b] != _KLOG
            for a, b in zip(ks, ks[1:] + ks[:1], strict=True)
        ]
        if all(liquid_edges):
            count += 1
            continue
        # a liquid run starts at each edge that is liquid after a solid one, and
        # front2 also splits a run where LIHBOR or LIUBOR changes between nodes
        for i, liquid in enumerate(liquid_edges):
            if liquid and not liquid_edges[i - 1]:
                count += 1
            elif liquid and liquid_edges[i - 1]:
                a, b = ks[i], ks[(i + 1) % len(ks)]
                if lih[a] != lih[b] or liu[a] != liu[b]:
                    count += 1
    return count
