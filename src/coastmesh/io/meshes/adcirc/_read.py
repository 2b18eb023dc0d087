"""Read ``fort.14`` and ``hgrid.gr3`` files (:mod:`coastmesh.io.meshes.adcirc`).

:func:`read_fort14` parses a file as it is written (counts, node lists, types);
:func:`read_fort14_mesh` builds a :class:`~coastmesh.types.Mesh` from it, with
the boundary ids, names and kinds, the depth and, for files coastmesh wrote, the
CRS.
"""

from __future__ import annotations

import os
import re
import warnings
from typing import Any

import numpy as np
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.errors import ConfigError, InputDataError, RepairedBoundaryWarning
from coastmesh.io._inputs import check_input, resolve_crs
from coastmesh.io.meshes._model import POSITIVE
from coastmesh.io.meshes._reading import counter_clockwise, mesh_from_file
from coastmesh.io.meshes._table import TextLines
from coastmesh.io.meshes.adcirc._regions import with_region_file
from coastmesh.types import Mesh
from coastmesh.types.topology import unique_edges

__all__ = ["read_fort14", "read_fort14_mesh", "read_gr3_mesh"]

# the comment coastmesh writes after a segment's counts: "...: id 2 north sea", or
# for a segment of several ids, "...: id 10 near; id 5 @301 far" (the edges from
# its 301st node on have id 5; coastmesh.io.meshes.adcirc._segments.label)
_ID_COMMENT = re.compile(r":\s*(id\s+\d+\b.*)$")
_ID_RUN = re.compile(r"^id\s+(\d+)(?:\s+@(\d+))?\b\s*(.*)$")
_TITLE_CRS = re.compile(r"^coastmesh EPSG:(\d+)$")
_BARRIER_PAIRS = (4, 5)  # IBTYPE 4, 24, 5, 25: node pairs across a barrier


def read_fort14(path: str | os.PathLike[str]) -> dict[str, Any]:
    r"""Read an ADCIRC ``fort.14`` or SCHISM ``hgrid.gr3`` file as it is written.

    A line-by-line parse of the published layout: counts are taken from the file
    and returned next to the lists they count, so callers can check them.

    Parameters
    ----------
    path : str or path-like
        The file. Text after the values a line must hold is ignored (comments).

    Returns
    -------
    dict
        ``title`` (str); ``ne``, ``np`` (ints, as declared); ``node_ids`` (NP,)
        int; ``xy`` (NP, 2) float; ``depth`` (NP,) float, as written (``DP``);
        ``element_ids`` (NE,) int; ``nhy`` (NE,) int; ``elements`` (NE, 3) int,
        the node numbers as written (1-based); ``nope``, ``neta`` (ints, as
        declared); ``open_boundaries``: a list of dicts with ``nodes`` (1-based
        int array), ``ibtypee`` (int, or None when the header has no type, as
        in SCHISM files) and ``comment`` (the text after the counts, without a
        leading ``=``); ``nbou``, ``nvel`` (ints, as declared);
        ``land_boundaries``: a list of dicts with ``nodes``, ``ibtype`` and
        ``comment``; ``trailing_lines``: the number of non-blank lines after the
        last land segment. For barrier types (``IBTYPE`` 3, 4, 5, ...) only the
        first number of each node line is kept.

    Raises
    ------
    InputDataError
        If the file is missing or ends early, a line lacks a value it must hold,
        a value is not a number, ``NHY`` is not 3, or a node number is outside
        ``1..NP``; the message names the line.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "fort.14"
    >>> _ = path.write_text("tri\n1 3\n1 0 0 5\n2 1 0 5\n3 0 1 5\n1 3 1 2 3\n"
    ...                     "0\n0\n0\n0\n")
    >>> grid = read_fort14(path)
    >>> grid["ne"], grid["np"], grid["elements"].tolist()
    (1, 3, [[1, 2, 3]])
    """
    lines = TextLines.read(check_input(path))
    out: dict[str, Any] = {"title": lines.next_line().strip()}
    out["ne"], out["np"] = lines.ints(2, "NE NP")
    node_table = lines.table(out["np"], 4, float, "JN X Y DP")
    out["node_ids"] = node_table[:, 0].astype(np.int64)
    out["xy"] = node_table[:, 1:3]
    out["depth"] = node_table[:, 3]
    element_table = lines.table(out["ne"], 5, int, "JE NHY NM1 NM2 NM3")
    out["element_ids"] = element_table[:, 0]
    out["nhy"] = element_table[:, 1]
    out["elements"] = element_table[:, 2:5]
    if len(out["nhy"]) and (out["nhy"] != 3).any():
        bad = int(np.flatnonzero(out["nhy"] != 3)[0])
        raise InputDataError(
            f"element {out['element_ids'][bad]} has NHY = {out['nhy'][bad]}; "
            "only triangles (NHY = 3) are read",
            path=lines.path,
        )
    out["nope"], out["neta"], out["open_boundaries"] = _segment_list(
        lines, out["np"], ("NOPE", "NETA", "NVDLL IBTYPEE", "NBDV"), "ibtypee"
    )
    out["nbou"], out["nvel"], out["land_boundaries"] = _segment_list(
        lines, out["np"], ("NBOU", "NVEL", "NVELL IBTYPE", "NBVV"), "ibtype"
    )
    out["trailing_lines"] = lines.remaining()
    table = out["elements"]
    if table.size and (table.min() < 1 or table.max() > out["np"]):
        raise InputDataError(
            f"elements have node numbers in [{table.min()}, {table.max()}], "
            f"expected 1..NP = 1..{out['np']}",
            path=lines.path,
        )
    return out


def read_fort14_mesh(
    path: str | os.PathLike[str], *, crs: Any = None, positive: str = "down"
) -> Mesh:
    r"""Read an ADCIRC ``fort.14`` or SCHISM ``hgrid.gr3`` file as a Mesh.

    Parameters
    ----------
    path : str or path-like
        The file (``fort.14``, ``hgrid.gr3``, ``hgrid.ll``, ...).
    crs : pyproj.CRS or CRS-like, optional
        The CRS of the coordinates, for files that do not declare one. Files
        coastmesh wrote declare it in their title (``coastmesh EPSG:32630``);
        ``crs`` must then agree with it.
    positive : {"down", "up"}, default "down"
        The sign of the file's depth (``DP``): ADCIRC's and SCHISM's depths are
        positive down; ``"up"`` reads elevations (the depth is their negative).

    Returns
    -------
    Mesh
        Nodes and triangles in file order (a clockwise triangle is turned
        counter-clockwise; in a geographic CRS, a triangle that crosses the
        antimeridian is turned by how it runs on the sphere);
        ``point_data["depth"]`` in metres, positive down; boundary edges from
        the node lists, with ids, names and kinds (see Notes); ``surface_id`` 1
        and no regions, unless a ``fort.13`` beside the file holds region ids.

    Raises
    ------
    InputDataError
        As :func:`read_fort14`; also if the node numbers are not ``1..NP`` in
        order, a land segment is an internal barrier (``IBTYPE`` 4, 24, 5, 25:
        node pairs), one boundary id is on both an open and a land segment, two
        consecutive nodes of a segment are not a boundary edge of the elements,
        or an edge is listed twice;
        or the ``fort.13`` beside it holds ``coastmesh_region_id`` but does not
        fit the grid (NumOfNodes, non-integer ids).
    ConfigError
        If ``positive`` or ``crs`` is invalid.

    Notes
    -----
    Each segment's node list gives one boundary edge per two consecutive nodes;
    a segment whose last node is joined to its first by a boundary edge that no
    segment lists (a SCHISM island, an ADCIRC ring open all round) also gets
    that edge. Segments of the open list (``NOPE``) are ``"open"``, all segments
    of the land list (``NBOU``) are ``"shoreline"``, whatever their ``IBTYPE``.
    Any other boundary edge of the elements that no segment lists is read as
    land with a new id named ``unlisted``, with a
    :class:`~coastmesh.errors.RepairedBoundaryWarning`.

    Boundary ids and names come from the comment coastmesh writes after each
    segment's counts (``4 0 = Number of nodes for open boundary 1: id 2 north``:
    id 2, name ``north``; for a segment of several ids, ``: id 10 near; id 5
    @301 far``, id 5 from its 301st node on). When a segment has no such comment
    (files written by other tools), the segments are numbered in file order
    instead: the open segments 1 to ``NOPE``, then the land segments ``NOPE +
    1`` on, with no names.

    Region ids come from the nodal attributes file beside the grid, its stem
    with the ending ``.13`` (``fort.14`` -> ``fort.13``), if it holds the
    attribute ``coastmesh_region_id`` (:func:`~coastmesh.io.meshes.adcirc.write_fort14`
    writes it; a ``fort.13`` of other attributes only is ignored). Its default
    value is the ``surface_id``; each triangle takes the outermost id among its
    nodes (:func:`~coastmesh.io.meshes.adcirc.regions_from_nodes`, in the
    order the ``AGRID`` line lists). That gives back the region of every
    triangle with a node no region nested in its own took: all of them, unless
    a triangle's three nodes all lie on the outlines of smaller regions (a sea
    triangle in a notch of a farm, a strip of one triangle between two farms).
    The names of the regions are not kept.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from coastmesh.io.meshes.adcirc import write_gr3
    >>> m = Mesh([[0, 0], [1, 0], [1, 1], [0, 1]], [[0, 1, 2], [0, 2, 3]],
    ...          [[0, 1], [1, 2], [2, 3], [3, 0]], [2, 1, 1, 1], 1, "EPSG:32630",
    ...          point_data={"depth": [5.0, 5.0, 4.0, 4.0]},
    ...          boundary_names={2: "sea"},
    ...          boundary_kinds={1: "shoreline", 2: "open"})
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "hgrid.gr3"
    >>> write_gr3(path, m)
    >>> back = read_fort14_mesh(path)
    >>> back.boundary_edges.tolist(), back.boundary_ids.tolist()
    ([[0, 1], [1, 2], [2, 3], [3, 0]], [2, 1, 1, 1])
    >>> back.boundary_names, back.boundary_kinds, back.crs.to_epsg()
    ({2: 'sea'}, {2: 'open', 1: 'shoreline'}, 32630)
    >>> back.point_data["depth"].tolist()
    [5.0, 5.0, 4.0, 4.0]
    """
    mesh = _read_grid(path, crs=crs, positive=positive)
    return with_region_file(mesh, path, "fort14")


def read_gr3_mesh(
    path: str | os.PathLike[str], *, crs: Any = None, positive: str = "down"
) -> Mesh:
    r"""Read a SCHISM ``hgrid.gr3`` (or ``fort.14``) file, and its region ids.

    Parameters
    ----------
    path : str or path-like
        The file (``hgrid.gr3``, ``hgrid.ll``, ...).
    crs : pyproj.CRS or CRS-like, optional
        As for :func:`read_fort14_mesh`.
    positive : {"down", "up"}, default "down"
        As for :func:`read_fort14_mesh`.

    Returns
    -------
    Mesh
        As :func:`read_fort14_mesh` reads the grid. If a ``<stem>.regions.prop``
        lies beside it (``hgrid.regions.prop``, which
        :func:`~coastmesh.io.meshes.adcirc.write_gr3` writes for a mesh with regions),
        each triangle gets its region id from it, exactly, and ``surface_id`` is
        the id of the most triangles (the file does not say which is the sea's).

    Raises
    ------
    InputDataError
        As :func:`read_fort14_mesh`; also if the ``.regions.prop`` does not have
        one line per element, numbered 1..NE in order, or an id is not an
        integer >= 1.
    ConfigError
        If ``positive`` or ``crs`` is invalid.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from coastmesh.io.meshes.adcirc import write_gr3
    >>> m = Mesh([[0, 0], [1, 0], [1, 1], [0, 1], [2, 0]],
    ...          [[0, 1, 2], [0, 2, 3], [1, 4, 2]],
    ...          [[0, 1], [1, 4], [4, 2], [2, 3], [3, 0]], [1] * 5, 1, None,
    ...          boundary_kinds={1: "shoreline"}, regions=[1, 20, 1],
    ...          point_data={"depth": [5.0, 5.0, 4.0, 4.0, 3.0]})
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "hgrid.gr3"
    >>> write_gr3(path, m)
    >>> print((path.parent / "hgrid.regions.prop").read_text(), end="")
    1  1
    2 20
    3  1
    >>> back = read_gr3_mesh(path)
    >>> back.regions.tolist(), back.surface_id
    ([1, 20, 1], 1)
    """
    mesh = _read_grid(path, crs=crs, positive=positive)
    return with_region_file(mesh, path, "gr3")


def _read_grid(path: str | os.PathLike[str], *, crs: Any, positive: str) -> Mesh:
    """Read the Mesh of a fort.14 or gr3 file alone (:func:`read_fort14_mesh`)."""
    if positive not in POSITIVE:
        raise ConfigError(
            f"positive={positive!r}; expected one of {', '.join(POSITIVE)}"
        )
    grid = read_fort14(path)
    name = os.fspath(path)
    count = grid["np"]
    jn = grid["node_ids"]
    if not np.array_equal(jn, np.arange(1, count + 1)):
        first = int(np.flatnonzero(jn != np.arange(1, count + 1))[0])
        raise InputDataError(
            f"node line {first + 1} has node number JN = {jn[first]}; a Mesh is read "
            "from files whose nodes are numbered 1..NP in order",
            path=name,
        )
    for k, land in enumerate(grid["land_boundaries"], start=1):
        if land["ibtype"] % 10 in _BARRIER_PAIRS:
            raise InputDataError(
                f"land segment {k} has IBTYPE {land['ibtype']}, an internal barrier "
                "(node pairs), which a Mesh cannot hold",
                path=name,
            )
    segments = [
        (b["nodes"] - 1, "open", None, b["comment"]) for b in grid["open_boundaries"]
    ] + [
        (b["nodes"] - 1, "shoreline", b["ibtype"], b["comment"])
        for b in grid["land_boundaries"]
    ]
    runs, names, kinds = _segment_ids(segments, name)
    edges, edge_ids = _boundary(segments, runs, grid["elements"] - 1, name)
    if len(edge_ids) and edge_ids.max() > max(kinds, default=0):
        fresh = int(edge_ids.max())  # the land the lists left out (_boundary)
        names[fresh], kinds[fresh] = "unlisted", "shoreline"
    match = _TITLE_CRS.match(grid["title"])
    stored = CRS.from_epsg(int(match.group(1))) if match else None
    found = resolve_crs(stored, crs, name)
    sphere = found is not None and bool(found.is_geographic)
    return mesh_from_file(
        name,
        grid["xy"],
        counter_clockwise(grid["xy"], grid["elements"] - 1, sphere=sphere),
        edges,
        edge_ids,
        1,
        found,
        {"depth": grid["depth"] if positive == "down" else -grid["depth"]},
        names,
        kinds,
    )


def _segment_list(
    lines: TextLines, count_of_nodes: int, what: tuple[str, str, str, str], key: str
) -> tuple[int, int, list[dict[str, Any]]]:
    """Read a segment list: its two counts, then each segment's header and nodes."""
    count_what, total_what, header_what, node_what = what
    (count,) = lines.ints(1, count_what)
    (total,) = lines.ints(1, total_what)
    segments = []
    for _ in range(count):
        size, rest = lines.count_and_rest(header_what)
        words = rest.split(maxsplit=1)
        try:
            kind, comment = int(words[0]), "".join(words[1:])
        except (IndexError, ValueError):
            kind, comment = None, rest
        if kind is None and key == "ibtype":
            raise lines.error(header_what, "expected two integers")
        nodes = lines.table(size, 1, int, node_what)[:, 0].astype(np.int64)
        if nodes.size and (nodes.min() < 1 or nodes.max() > count_of_nodes):
            raise lines.error(
                node_what, f"node numbers must be in 1..NP = 1..{count_of_nodes}"
            )
        segment = {"nodes": nodes, key: kind, "comment": comment.strip(" =\t")}
        segments.append(segment)
    return count, total, segments


def _segment_ids(
    segments: list[tuple[Any, str, int | None, str]], name: str
) -> tuple[list[list[tuple[int, int]]], dict[int, str], dict[int, str]]:
    """Return the id runs of each segment, and the names and kinds of the ids.

    A run ``(k, id)`` gives id ``id`` to the segment's edges from its node ``k``
    (0-based) on. Without coastmesh's comments on every segment, each segment
    is one run, numbered in file order (the open segments first).
    """
    found = [_ID_COMMENT.search(comment) for *_, comment in segments]
    if not all(found):
        return (
            [[(0, pid)] for pid in range(1, len(segments) + 1)],
            {},
            {pid: s[1] for pid, s in enumerate(segments, start=1)},
        )
    runs: list[list[tuple[int, int]]] = []
    names: dict[int, str] = {}
    kinds: dict[int, str] = {}
    for k, (m, (_, kind, _, _)) in enumerate(zip(found, segments, strict=True)):
        segment_runs = []
        for part in m.group(1).split(";") if m else ():
            run = _ID_RUN.match(part.strip())
            if run is None:
                raise InputDataError(
                    f"segment {k + 1} ({kind}): the id comment part {part.strip()!r} "
                    "is not 'id N', 'id N @K' or either with a name",
                    path=name,
                )
            pid = int(run.group(1))
            start = int(run.group(2)) - 1 if run.group(2) else 0
            if kinds.setdefault(pid, kind) != kind:
                raise InputDataError(
                    f"boundary id {pid} is on both an open and a land segment "
                    f"(segment comments such as ': id {pid}'); ids must keep one kind",
                    path=name,
                )
            if run.group(3).strip():
                names.setdefault(pid, run.group(3).strip())
            segment_runs.append((start, pid))
        runs.append(segment_runs)
    return runs, names, kinds


def _boundary(
    segments: list[tuple[Any, str, int | None, str]],
    runs: list[list[tuple[int, int]]],
    triangles: NDArray[np.int64],
    name: str,
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """Return the boundary edges and their ids, from the segments' node lists.

    Each two consecutive nodes of a segment are an edge, with the id of its run.
    A boundary edge of the triangles that no segment lists is given the id of
    the segment whose two ends it joins (a SCHISM island, an ADCIRC ring open
    all round), else a new land id, with a :class:`RepairedBoundaryWarning`:
    ADCIRC puts no flux through such an edge, and SCHISM stops on it.

    Raises
    ------
    InputDataError
        If two consecutive nodes of a segment are not a boundary edge of the
        triangles, or one edge is listed twice.
    """
    n = max(
        [int(triangles.max()) + 1 if triangles.size else 0]
        + [int(nodes.max()) + 1 for nodes, *_ in segments if len(nodes)]
    )
    table = _segment_edges(segments, runs)
    keys = np.minimum(table[:, 0], table[:, 1]) * n + np.maximum(
        table[:, 0], table[:, 1]
    )
    order = np.argsort(keys, kind="stable")
    twice = np.flatnonzero(keys[order][1:] == keys[order][:-1])
    if len(twice):
        first, second = table[order[twice[0]]], table[order[twice[0] + 1]]
        raise InputDataError(
            f"the edge between nodes {first[0] + 1} and {first[1] + 1} is listed "
            f"twice: in {_which(segments, first[3])} and in "
            f"{_which(segments, second[3])}; "
            "each boundary edge belongs to one segment",
            path=name,
        )
    edges_all, count = unique_edges(triangles, n)
    boundary = edges_all[count == 1]
    boundary_keys = boundary[:, 0] * n + boundary[:, 1]
    off = np.flatnonzero(~np.isin(keys, boundary_keys))
    if len(off):
        a, b, _, k = table[off[0]]
        raise InputDataError(
            f"{_which(segments, k)} lists nodes {a + 1} and {b + 1} one after the "
            "other, but they are not joined by a boundary edge of the mesh (an edge "
            "of one element); a segment follows the boundary",
            path=name,
        )
    missing = boundary[~np.isin(boundary_keys, keys)]
    # a segment's last node back to its first: the edge that closes it
    ends: dict[int, tuple[int, int, int]] = {}
    for (nodes, *_), segment_runs in zip(segments, runs, strict=True):
        if len(nodes) > 2 and nodes[0] != nodes[-1]:
            a, b = int(nodes[0]), int(nodes[-1])
            ends.setdefault(min(a, b) * n + max(a, b), (b, a, segment_runs[-1][1]))
    fresh = int(table[:, 2].max(initial=0)) + 1
    extra, unlisted = [], []
    for a, b in missing.tolist():
        found = ends.get(a * n + b)
        if found is None:
            unlisted.append((a, b))
            found = (a, b, fresh)
        extra.append(found)
    if unlisted:
        a, b = unlisted[0]
        warnings.warn(
            f"{name}: {len(unlisted)} boundary edge(s) of the mesh are in no segment "
            f"(the first between nodes {a + 1} and {b + 1}); they are read as land, "
            f"boundary id {fresh} 'unlisted' (ADCIRC lets no water through an edge "
            "no segment lists; SCHISM stops on one)",
            RepairedBoundaryWarning,
            stacklevel=4,
        )
    more = np.array(extra, dtype=np.int64).reshape(-1, 3)
    return (
        np.concatenate([table[:, :2], more[:, :2]]),
        np.concatenate([table[:, 2], more[:, 2]]),
    )


def _segment_edges(
    segments: list[tuple[Any, str, int | None, str]],
    runs: list[list[tuple[int, int]]],
) -> NDArray[np.int64]:
    """Return the segments' edges, one row each: node, node, id, segment.

    Each two consecutive nodes of a segment are an edge, with the id of the run
    it lies in; a node repeated in place makes no edge.
    """
    parts = []
    for k, ((nodes, *_), segment_runs) in enumerate(zip(segments, runs, strict=True)):
        starts = np.array([start for start, _ in segment_runs], dtype=np.int64)
        run_of = np.searchsorted(starts, np.arange(len(nodes) - 1), side="right") - 1
        pids = np.array([pid for _, pid in segment_runs], dtype=np.int64)
        parts.append(
            np.column_stack(
                [
                    nodes[:-1],
                    nodes[1:],
                    pids[np.maximum(run_of, 0)],
                    np.full(len(nodes) - 1, k),
                ]
            ).reshape(-1, 4)
        )
    table = np.concatenate(parts) if parts else np.empty((0, 4), np.int64)
    return table[table[:, 0] != table[:, 1]]


def _which(segments: list[tuple[Any, str, int | None, str]], k: int) -> str:
    """Name segment ``k`` of the lists: its place in its list and its kind."""
    kind = segments[k][1]
    before = sum(1 for s in segments[:k] if s[1] == kind)
    return f"{'open' if kind == 'open' else 'land'} segment {before + 1}"
