"""ADCIRC ``fort.14`` and SCHISM ``hgrid.gr3`` grid files, with boundary segments.

Both files hold a title line, ``NE NP``, the nodes ``JN X Y DP``, the elements
``JE 3 NM1 NM2 NM3`` (1-based), then the open (elevation) boundary segments and the
land (normal flow) boundary segments as node lists. The layout follows the ADCIRC
manual (``adcirc/adcirc``: ``docs/technical_reference/input_files/fort14.rst`` and
``parameter_definitions/index.rst``) and the SCHISM manual (``schism-dev/schism``:
``docs/input-output/hgrid.md``, "same as fort.14 of ADCIRC").

The two differ only in how boundary segments are listed:

=========================  ================================  ==========================
                           ``fort.14`` (ADCIRC)              ``hgrid.gr3`` (SCHISM)
=========================  ================================  ==========================
open segment header        ``NVDLL IBTYPEE`` (``IBTYPEE=0``)  ``NVDLL`` only
island (closed land ring)  ``IBTYPE 1``, first node repeated  ``1``, first node not
                           at the end                        repeated
whole ring of one id       first node repeated at the end    two segments that share
(no other boundary on it)  (a lake, ``IBTYPE 0``)            their end nodes
=========================  ================================  ==========================

Sources: ADCIRC "General Notes for Normal Flow Boundary Conditions" (islands and
external boundaries that surround the domain "should be closed by repeating the
first node as the last node"); SCHISM ``hgrid.md`` (the last island node "is
different from the first node"; "if you have no open boundary, you can create two
land boundary segments that are linked to each other", and likewise for open).

The text tables are formatted with numpy in blocks (no Python loop per node), so
meshes of millions of triangles write in seconds.
"""

from __future__ import annotations

import logging
import os
import warnings
from collections.abc import Iterator, Sequence
from typing import IO, Any

import numpy as np
from numpy.typing import NDArray

from coastmesh.errors import CoastmeshWarning, ConfigError, FormatError, InputDataError
from coastmesh.io._atomic import atomic_write
from coastmesh.meshing.topology import BoundaryString, boundary_strings
from coastmesh.types import Mesh

__all__ = ["read_fort14", "write_fort14", "write_gr3"]

logger = logging.getLogger(__name__)

POSITIVE = ("down", "up")
_SIGNIFICANT = 15  # significant digits written for floats (float64 holds ~15.9)
_CHUNK = 1 << 19  # rows formatted per block: bounds the memory of the text
_POW10 = 10 ** np.arange(19, dtype=np.int64)
# "0000" ... "9999" as uint32 words: four ASCII digits per table lookup
_QUADS = np.frombuffer("".join(f"{i:04d}" for i in range(10000)).encode(), np.uint32)


def write_fort14(
    path: str | os.PathLike[str],
    mesh: Mesh,
    *,
    overwrite: bool = False,
    positive: str = "down",
    title: str | None = None,
) -> None:
    """Write a mesh as an ADCIRC ``fort.14`` grid with its boundary segments.

    Parameters
    ----------
    path : str or path-like
        The output file, such as ``fort.14``.
    mesh : Mesh
        The mesh; every boundary id needs a kind in ``mesh.boundary_kinds``
        (``"open"`` or ``"shoreline"``). Depth is ``mesh.point_data["depth"]``
        (metres, positive down); without it every node gets depth 0, with a
        warning. Coordinates are written as they are (longitude, latitude in
        degrees for a geographic CRS, which ADCIRC runs with ``ICS=2``).
    overwrite : bool, default False
        Whether an existing file may be replaced.
    positive : {"down", "up"}, default "down"
        Sign of the written ``DP``: ``"down"`` writes the depth as it is (ADCIRC's
        ``DP`` is positive below the geoid), ``"up"`` writes its negative.
    title : str, optional
        The first line (``AGRID``); one line. By default ``coastmesh`` and the
        EPSG code of ``mesh.crs``.

    Raises
    ------
    FormatError
        If a boundary id has no kind, the boundary edges do not form simple rings,
        or the depth has the wrong shape or non-finite values.
    ConfigError
        If ``positive`` or ``title`` is invalid.
    OutputExistsError
        If ``path`` exists and ``overwrite`` is false.

    Warns
    -----
    CoastmeshWarning
        If the mesh has no ``depth`` point data (zeros are written).

    Notes
    -----
    Open boundaries (kind ``"open"``) are elevation-specified segments,
    ``IBTYPEE = 0``, one per run of edges with one id, in order along the
    boundary. Land boundaries (kind ``"shoreline"``) are ``IBTYPE = 0``
    (mainland) segments, except an island ring whose edges all have one land id,
    which is one ``IBTYPE = 1`` segment closed by repeating its first node. An
    island ring with several ids, or with open parts, is written as separate,
    non-closed ``IBTYPE = 0`` segments. Exterior segments come first, each
    starting where two boundaries meet; nodes run with the domain on the left
    (land on the right), counter-clockwise around the exterior and clockwise
    around islands, as the ADCIRC manual asks (``NBVV``). A header comment after
    each segment's counts names its boundary id and name.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> m = Mesh([[0, 0], [1, 0], [1, 1], [0, 1]], [[0, 1, 2], [0, 2, 3]],
    ...          [[0, 1], [1, 2], [2, 3], [3, 0]], [2, 1, 1, 1], 1, None,
    ...          point_data={"depth": [5.0, 5.0, 4.0, 4.0]},
    ...          boundary_kinds={1: "shoreline", 2: "open"})
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "fort.14"
    >>> write_fort14(path, m)
    >>> grid = read_fort14(path)
    >>> grid["elements"].tolist(), grid["depth"].tolist()
    ([[1, 2, 3], [1, 3, 4]], [5.0, 5.0, 4.0, 4.0])
    >>> [(b["nodes"].tolist(), b["ibtypee"]) for b in grid["open_boundaries"]]
    [([1, 2], 0)]
    >>> [(b["nodes"].tolist(), b["ibtype"]) for b in grid["land_boundaries"]]
    [([2, 3, 4, 1], 0)]
    """
    _write_grid(
        path, mesh, "fort14", overwrite=overwrite, positive=positive, title=title
    )


def write_gr3(
    path: str | os.PathLike[str],
    mesh: Mesh,
    *,
    overwrite: bool = False,
    positive: str = "down",
    title: str | None = None,
) -> None:
    """Write a mesh as a SCHISM ``hgrid.gr3`` with its boundary segments.

    Parameters
    ----------
    path : str or path-like
        The output file, such as ``hgrid.gr3`` (or ``hgrid.ll`` in degrees).
    mesh : Mesh
        The mesh; as for :func:`write_fort14`.
    overwrite : bool, default False
        Whether an existing file may be replaced.
    positive : {"down", "up"}, default "down"
        Sign of the written depth: SCHISM's depth is positive down.
    title : str, optional
        The first line, one line; SCHISM ignores it.

    Raises
    ------
    FormatError
        As :func:`write_fort14`.
    ConfigError
        If ``positive`` or ``title`` is invalid.
    OutputExistsError
        If ``path`` exists and ``overwrite`` is false.

    Warns
    -----
    CoastmeshWarning
        If the mesh has no ``depth`` point data (zeros are written).

    Notes
    -----
    As :func:`write_fort14`, with SCHISM's conventions (``hgrid.md``): an open
    segment header holds the node count only; land segments have flag ``0``
    (land) or ``1`` (island); an island lists its nodes without repeating the
    first one; a whole ring of one id with no other boundary on it (no open
    boundary at all, or a fully open ring) is split into two segments that share
    their end nodes. Counts carry SCHISM's comments (``= Number of open
    boundaries``, ...), which SCHISM and ADCIRC both skip.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> m = Mesh([[0, 0], [1, 0], [1, 1], [0, 1]], [[0, 1, 2], [0, 2, 3]],
    ...          [[0, 1], [1, 2], [2, 3], [3, 0]], [1, 1, 1, 1], 1, None,
    ...          point_data={"depth": [5.0, 5.0, 4.0, 4.0]},
    ...          boundary_kinds={1: "shoreline"})
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "hgrid.gr3"
    >>> write_gr3(path, m)
    >>> land = read_fort14(path)["land_boundaries"]
    >>> [(b["nodes"].tolist(), b["ibtype"]) for b in land]
    [([1, 2, 3], 0), ([3, 4, 1], 0)]
    """
    _write_grid(path, mesh, "gr3", overwrite=overwrite, positive=positive, title=title)


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
        int array) and ``ibtypee`` (int, or None when the header has no type, as
        in SCHISM files); ``nbou``, ``nvel`` (ints, as declared);
        ``land_boundaries``: a list of dicts with ``nodes`` and ``ibtype``;
        ``trailing_lines``: the number of non-blank lines after the last land
        segment. For barrier types (``IBTYPE`` 3, 4, 5, ...) only the first
        number of each node line is kept.

    Raises
    ------
    InputDataError
        If the file ends early, a line lacks a value it must hold, a value is not
        a number, ``NHY`` is not 3, or a node number is outside ``1..NP``; the
        message names the line.

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
    with open(path, encoding="utf-8", errors="replace") as handle:
        lines = _Lines(path, handle.read().splitlines())
    out: dict[str, Any] = {"title": lines.next_line().strip()}
    out["ne"], out["np"] = lines.ints(2, "NE NP")
    nodes = [lines.fields(4, "JN X Y DP") for _ in range(out["np"])]
    node_table = lines.numbers(nodes, float, "JN X Y DP")
    out["node_ids"] = node_table[:, 0].astype(np.int64)
    out["xy"] = node_table[:, 1:3]
    out["depth"] = node_table[:, 3]
    what = "JE NHY NM1 NM2 NM3"
    element_table = lines.numbers(
        [lines.fields(5, what) for _ in range(out["ne"])], int, what
    )
    out["element_ids"] = element_table[:, 0]
    out["nhy"] = element_table[:, 1]
    out["elements"] = element_table[:, 2:5]
    if len(out["nhy"]) and (out["nhy"] != 3).any():
        bad = int(np.flatnonzero(out["nhy"] != 3)[0])
        raise InputDataError(
            f"element {out['element_ids'][bad]} has NHY = {out['nhy'][bad]}; "
            "only triangles (NHY = 3) are read",
            path=os.fspath(path),
        )
    (out["nope"],) = lines.ints(1, "NOPE")
    (out["neta"],) = lines.ints(1, "NETA")
    out["open_boundaries"] = []
    for _ in range(out["nope"]):
        count, kind = lines.count_and_type("NVDLL IBTYPEE")
        out["open_boundaries"].append(
            {"nodes": lines.node_list(count, out["np"], "NBDV"), "ibtypee": kind}
        )
    (out["nbou"],) = lines.ints(1, "NBOU")
    (out["nvel"],) = lines.ints(1, "NVEL")
    out["land_boundaries"] = []
    for _ in range(out["nbou"]):
        count, kind = lines.count_and_type("NVELL IBTYPE")
        if kind is None:
            raise lines.error("NVELL IBTYPE", "expected two integers")
        out["land_boundaries"].append(
            {"nodes": lines.node_list(count, out["np"], "NBVV"), "ibtype": kind}
        )
    out["trailing_lines"] = lines.remaining()
    table = out["elements"]
    if table.size and (table.min() < 1 or table.max() > out["np"]):
        raise InputDataError(
            f"elements have node numbers in [{table.min()}, {table.max()}], "
            f"expected 1..NP = 1..{out['np']}",
            path=os.fspath(path),
        )
    return out


def _write_grid(
    path: str | os.PathLike[str],
    mesh: Mesh,
    flavour: str,
    *,
    overwrite: bool,
    positive: str,
    title: str | None,
) -> None:
    """Check everything, then write a fort.14 (``flavour="fort14"``) or gr3."""
    if not isinstance(mesh, Mesh):
        raise TypeError(f"mesh is a {type(mesh).__name__}, expected a Mesh")
    name = os.fspath(path)
    depth = node_depth(mesh, name, positive=positive, stacklevel=4)
    line = _title(mesh, title)
    kinds = require_kinds(mesh, name)
    open_segments, land_segments = _segments(mesh, name, kinds, flavour)
    n, m = len(mesh.points), len(mesh.triangles)
    with atomic_write(path, overwrite=overwrite) as tmp, open(tmp, "wb") as handle:
        _put(handle, line, f"{m} {n}")
        write_table(
            handle,
            [
                (np.arange(1, n + 1), None),
                (mesh.points[:, 0], _SIGNIFICANT),
                (mesh.points[:, 1], _SIGNIFICANT),
                (depth, _SIGNIFICANT),
            ],
        )
        write_table(
            handle,
            [(np.arange(1, m + 1), None), (np.full(m, 3), None)]
            + [(mesh.triangles[:, k] + 1, None) for k in range(3)],
        )
        _put(
            handle,
            f"{len(open_segments)} = Number of open boundaries",
            f"{sum(len(s[0]) for s in open_segments)} = Total number of open "
            "boundary nodes",
        )
        # IBTYPEE = 0: elevation specified; SCHISM's header holds the count only
        ibtypee = " 0" if flavour == "fort14" else ""
        for k, (nodes, label) in enumerate(open_segments, start=1):
            count = f"{len(nodes)}{ibtypee}"
            _put(handle, f"{count} = Number of nodes for open boundary {k}{label}")
            write_table(handle, [(nodes + 1, None)])
        _put(
            handle,
            f"{len(land_segments)} = Number of land boundaries",
            f"{sum(len(s[0]) for s in land_segments)} = Total number of land "
            "boundary nodes",
        )
        for k, (nodes, ibtype, label) in enumerate(land_segments, start=1):
            count = f"{len(nodes)} {ibtype}"
            _put(handle, f"{count} = Number of nodes for land boundary {k}{label}")
            write_table(handle, [(nodes + 1, None)])
    logger.debug(
        "wrote %s (%s): %d nodes, %d triangles, %d open and %d land segments",
        name,
        flavour,
        n,
        m,
        len(open_segments),
        len(land_segments),
    )


def node_depth(
    mesh: Mesh, name: str, *, positive: str, stacklevel: int = 2
) -> NDArray[np.float64]:
    """Return the depth to write at each node, with the sign ``positive`` asks.

    Parameters
    ----------
    mesh : Mesh
        Its ``point_data["depth"]`` (metres, positive down), if any.
    name : str
        The output file, for messages.
    positive : {"down", "up"}
        ``"down"`` returns the depth, ``"up"`` its negative (elevation).
    stacklevel : int, default 2
        Passed to :func:`warnings.warn`.

    Returns
    -------
    ndarray of shape (N,)
        float64; zeros (with a warning) if the mesh has no depth.

    Raises
    ------
    ConfigError
        If ``positive`` is not ``"down"`` or ``"up"``.
    FormatError
        If the depth is not one finite number per node.
    """
    if positive not in POSITIVE:
        raise ConfigError(
            f"{name}: positive={positive!r}; expected one of {', '.join(POSITIVE)}"
        )
    n = len(mesh.points)
    if "depth" not in mesh.point_data:
        warnings.warn(
            f"{name}: the mesh has no point_data['depth']; writing depth 0 at all "
            f"{n} nodes",
            CoastmeshWarning,
            stacklevel=stacklevel,
        )
        return np.zeros(n)
    depth = np.asarray(mesh.point_data["depth"])
    if depth.shape != (n,) or not np.issubdtype(depth.dtype, np.number):
        raise FormatError(
            f"{name}: point_data['depth'] has shape {depth.shape} and dtype "
            f"{depth.dtype}; expected ({n},) numbers, one per node"
        )
    depth = depth.astype(np.float64)
    bad = ~np.isfinite(depth)
    if bad.any():
        raise FormatError(
            f"{name}: point_data['depth'] is not finite at {int(bad.sum())} nodes "
            f"(first: node {int(np.flatnonzero(bad)[0])}); fill the depth first"
        )
    return depth if positive == "down" else -depth


def require_kinds(mesh: Mesh, name: str) -> dict[int, str]:
    """Return the kind of every boundary id of ``mesh``; raise if one has none.

    Parameters
    ----------
    mesh : Mesh
        The mesh.
    name : str
        The output file, for messages.

    Returns
    -------
    dict of int to str
        ``"open"`` or ``"shoreline"`` for each id in ``mesh.boundary_ids``.

    Raises
    ------
    FormatError
        If an id has no kind; the message names the ids and their names.
    """
    ids = sorted({int(i) for i in np.unique(mesh.boundary_ids)})
    missing = [i for i in ids if i not in mesh.boundary_kinds]
    if missing:
        named = ", ".join(
            f"{i} ({mesh.boundary_names[i]!r})" if i in mesh.boundary_names else str(i)
            for i in missing
        )
        raise FormatError(
            f"{name}: boundary id(s) {named} have no kind; this format separates open "
            "from land boundaries, so give every id a kind, such as "
            f"boundary_kinds={{{missing[0]}: 'open'}} (or 'shoreline')"
        )
    return {i: mesh.boundary_kinds[i] for i in ids}


def mesh_boundary_strings(mesh: Mesh, name: str) -> list[BoundaryString]:
    """Return the mesh's boundary node strings; errors name the output file.

    Parameters
    ----------
    mesh : Mesh
        The mesh.
    name : str
        The output file, for messages.

    Returns
    -------
    list of BoundaryString

    Raises
    ------
    FormatError
        If the boundary edges do not form simple rings.
    """
    try:
        return boundary_strings(mesh)
    except FormatError as exc:
        raise FormatError(f"{name}: {exc}") from exc


def _segments(
    mesh: Mesh, name: str, kinds: dict[int, str], flavour: str
) -> tuple[
    list[tuple[NDArray[np.int64], str]],
    list[tuple[NDArray[np.int64], int, str]],
]:
    """Open segments (nodes, label) and land segments (nodes, IBTYPE, label)."""
    opened: list[tuple[NDArray[np.int64], str]] = []
    land: list[tuple[NDArray[np.int64], int, str]] = []
    for string in mesh_boundary_strings(mesh, name):
        label = _label(mesh, string.physical_id)
        is_open = kinds[string.physical_id] == "open"
        island = string.closed and not string.exterior and not is_open
        for nodes in _pieces(string, flavour, island=island):
            if is_open:
                opened.append((nodes, label))
            else:
                land.append((nodes, 1 if island else 0, label))
    return opened, land


def _pieces(
    string: BoundaryString, flavour: str, *, island: bool
) -> Iterator[NDArray[np.int64]]:
    """Yield the node lists (0-based) that a boundary string is written as."""
    nodes = string.nodes
    if not string.closed:
        yield nodes
    elif flavour == "fort14":
        # ADCIRC: islands and boundaries surrounding the domain are closed by
        # repeating the first node as the last node
        yield np.append(nodes, nodes[0])
    elif island:
        # SCHISM hgrid.md: the last island node differs from the first
        yield nodes
    else:
        # SCHISM hgrid.md: a ring with no other boundary is two linked segments
        half = len(nodes) // 2
        yield nodes[: half + 1]
        yield np.append(nodes[half:], nodes[0])


def _label(mesh: Mesh, pid: int) -> str:
    name = mesh.boundary_names.get(pid)
    return f": id {pid}" + (f" {' '.join(name.split())}" if name else "")


def _title(mesh: Mesh, title: str | None) -> str:
    if title is None:
        epsg = mesh.crs.to_epsg() if mesh.crs is not None else None
        return "coastmesh" + (f" EPSG:{epsg}" if epsg else "")
    if not isinstance(title, str) or "\n" in title or "\r" in title:
        raise ConfigError(f"title={title!r}: expected a string of one line")
    return title


def _put(handle: IO[bytes], *lines: str) -> None:
    handle.write("".join(f"{line}\n" for line in lines).encode("utf-8"))


def write_table(
    handle: IO[bytes], columns: Sequence[tuple[NDArray[Any], int | None]]
) -> None:
    """Write rows of numbers, right-aligned in columns, one row per line.

    Parameters
    ----------
    handle : binary file
        Open for writing.
    columns : sequence of (array of shape (R,), int or None)
        The values of each column and how to write them: ``None`` for integers,
        else the number of significant digits of floats, written in fixed point
        with the same decimals down the column (so that its largest value keeps
        that many digits).

    Raises
    ------
    ValueError
        If the columns differ in length or a float is not finite or >= 1e18.

    Notes
    -----
    Each block of rows becomes one ``uint8`` array of characters: digits come
    four at a time from a lookup table, so there is no Python loop per row.

    Examples
    --------
    >>> import io
    >>> out = io.BytesIO()
    >>> write_table(out, [(np.array([1, 20]), None), (np.array([-1.5, 2.25]), 4)])
    >>> print(out.getvalue().decode(), end="")
     1 -1.500
    20  2.250
    """
    specs = [_column(np.asarray(values), digits) for values, digits in columns]
    rows = {len(spec[0]) for spec in specs}
    if len(rows) != 1:
        raise ValueError(f"columns have different lengths: {sorted(rows)}")
    (n,) = rows
    for start in range(0, n, _CHUNK):
        stop = min(start + _CHUNK, n)
        parts = []
        for k, spec in enumerate(specs):
            if k:
                parts.append(np.full((stop - start, 1), ord(" "), np.uint8))
            parts.append(_render(spec, start, stop))
        parts.append(np.full((stop - start, 1), ord("\n"), np.uint8))
        handle.write(np.hstack(parts).tobytes())


def _column(
    values: NDArray[Any], digits: int | None
) -> tuple[NDArray[Any], int | None, int]:
    """(values, decimals or None for integers, width of the integer part)."""
    if values.ndim != 1:
        raise ValueError(f"a column has shape {values.shape}, expected (R,)")
    if digits is None:
        values = values.astype(np.int64)
        top = int(np.abs(values).max(initial=0))
        return values, None, _ndigits(top) + int((values < 0).any())
    values = values.astype(np.float64)
    if not np.isfinite(values).all():
        raise ValueError("a column has non-finite values")
    top = float(np.abs(values).max(initial=0.0))
    if top >= 1e18:
        raise ValueError(f"a column has |values| up to {top:g}; expected < 1e18")
    decimals = max(0, digits - _ndigits(int(top)))
    unit = 10.0**-decimals
    widest = int(np.rint(top / unit)) // 10**decimals
    negative = bool((values <= -0.5 * unit).any())
    return values, decimals, _ndigits(widest) + int(negative)


def _render(
    spec: tuple[NDArray[Any], int | None, int], start: int, stop: int
) -> NDArray[np.uint8]:
    values, decimals, width = spec
    chunk = values[start:stop]
    if decimals is None:
        return _signed(np.abs(chunk), chunk < 0, width)
    scaled = np.rint(np.abs(chunk) * 10.0**decimals).astype(np.int64)
    whole, fraction = np.divmod(scaled, np.int64(10) ** decimals)
    head = _signed(whole, (chunk < 0) & (scaled != 0), width)
    if decimals == 0:
        return head
    dot = np.full((len(chunk), 1), ord("."), np.uint8)
    return np.hstack([head, dot, _digits(fraction, decimals)])


def _signed(
    magnitude: NDArray[np.int64], negative: NDArray[np.bool_], width: int
) -> NDArray[np.uint8]:
    """Right-aligned decimal text of ``magnitude``, a minus sign where negative."""
    text = _digits(magnitude, width)
    lead = width - np.maximum(np.searchsorted(_POW10, magnitude, side="right"), 1)
    blank = np.arange(width)[None, :] < lead[:, None]
    text[blank] = ord(" ")
    rows = np.flatnonzero(negative)
    text[rows, lead[rows] - 1] = ord("-")
    return text


def _digits(values: NDArray[np.int64], width: int) -> NDArray[np.uint8]:
    """Zero-padded decimal digits of non-negative ``values``, shape (R, width)."""
    words = -(-width // 4)
    out = np.empty((len(values), words), np.uint32)
    rest = values
    for k in range(words - 1, -1, -1):
        rest, quad = np.divmod(rest, 10000)
        out[:, k] = _QUADS[quad]
    return np.ascontiguousarray(out.view(np.uint8)[:, 4 * words - width :])


def _ndigits(value: int) -> int:
    return max(len(str(abs(int(value)))), 1)


class _Lines:
    """The lines of a text file, read in order, with errors naming the line."""

    def __init__(self, path: str | os.PathLike[str], lines: list[str]) -> None:
        self.path = os.fspath(path)
        self.lines = lines
        self.at = 0

    def error(self, what: str, problem: str) -> InputDataError:
        text = self.lines[self.at - 1] if 0 < self.at <= len(self.lines) else ""
        return InputDataError(
            f"line {self.at} ({what}): {problem}; found {text.strip()[:60]!r}",
            path=self.path,
        )

    def next_line(self) -> str:
        if self.at >= len(self.lines):
            self.at += 1
            raise InputDataError(
                f"the file ends at line {len(self.lines)}; more lines expected",
                path=self.path,
            )
        self.at += 1
        return self.lines[self.at - 1]

    def fields(self, k: int, what: str) -> list[str]:
        found = self.next_line().split()
        if len(found) < k:
            raise self.error(what, f"expected {k} values")
        return found[:k]

    def ints(self, k: int, what: str) -> list[int]:
        fields = self.fields(k, what)
        try:
            return [int(f) for f in fields]
        except ValueError:
            raise self.error(what, f"expected {k} integers") from None

    def numbers(self, rows: list[list[str]], kind: type, what: str) -> NDArray[Any]:
        try:
            return np.array(rows, dtype=kind).reshape(len(rows), len(what.split()))
        except ValueError:
            first = self.at - len(rows)
            for offset, row in enumerate(rows):
                try:
                    [kind(f) for f in row]
                except ValueError:
                    self.at = first + offset + 1
                    raise self.error(what, "a value is not a number") from None
            raise

    def count_and_type(self, what: str) -> tuple[int, int | None]:
        found = self.next_line().split()
        try:
            count = int(found[0])
        except (IndexError, ValueError):
            raise self.error(what, "expected an integer count") from None
        try:
            return count, int(found[1])
        except (IndexError, ValueError):
            return count, None

    def node_list(self, count: int, np_: int, what: str) -> NDArray[np.int64]:
        nodes = np.array([self.ints(1, what)[0] for _ in range(count)], np.int64)
        if nodes.size and (nodes.min() < 1 or nodes.max() > np_):
            raise self.error(what, f"node numbers must be in 1..NP = 1..{np_}")
        return nodes

    def remaining(self) -> int:
        return sum(1 for line in self.lines[self.at :] if line.strip())
