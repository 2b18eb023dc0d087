"""Read a Telemac SELAFIN geometry file and its ``.cli`` boundary file as a Mesh.

:mod:`coastmesh.io.meshes.telemac` gives both layouts, as Telemac's HERMES
``utils_serafin.F`` reads and writes them, and writes them. The reader takes what
other tools write too: either byte order (the first record marker, 80, says
which), single or double precision (``SERAFIN`` / ``SERAFIND``: the size of the X
record says which), a date record (``IPARAM(10) = 1``), a coordinate offset
(``IPARAM(3:4)``), any number of variables and time steps (the bed is read at the
first), and ``.cli`` lines with text after their 13 values.

The boundary edges, their ids and kinds come from the ``.cli`` by Telemac's own
rules (BIEF ``front2.f``), in :mod:`coastmesh.io.meshes._telemac_cli`.
"""

from __future__ import annotations

import logging
import os
import re
import struct
import warnings
from pathlib import Path
from typing import IO, Any, NamedTuple

import numpy as np
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.errors import CoastmeshWarning, ConfigError, FormatError
from coastmesh.io._inputs import check_input, resolve_crs
from coastmesh.io.meshes._model import POSITIVE
from coastmesh.io.meshes._reading import counter_clockwise, mesh_from_file
from coastmesh.io.meshes._telemac_cli import LAND_ID, cli_boundary, outline
from coastmesh.types import Mesh

__all__ = ["read_selafin_mesh"]

logger = logging.getLogger(__name__)

_TITLE_BYTES = 80
_BED = ("BOTTOM", "FOND")  # the bed elevation, in English and in French files
# the title write_selafin gives a mesh with an EPSG code (telemac._title)
_TITLE_CRS = re.compile(r"^coastmesh mesh, EPSG:(\d+)(, geographic lon/lat degrees)?$")


class _Geometry(NamedTuple):
    """What a SELAFIN file holds of a mesh."""

    title: str
    points: NDArray[np.float64]
    triangles: NDArray[np.int64]  # 0-based, as stored
    bottom: NDArray[np.float64] | None
    missing: str  # why bottom is None


def read_selafin_mesh(
    path: str | os.PathLike[str], *, crs: Any = None, positive: str = "up"
) -> Mesh:
    """Read a Telemac SELAFIN geometry file, and the ``.cli`` beside it, as a Mesh.

    Parameters
    ----------
    path : str or path-like
        The SELAFIN file (``.slf``). Its boundary conditions file is the same path
        with the suffix ``.cli``.
    crs : pyproj.CRS or CRS-like, optional
        The CRS of the coordinates: SELAFIN stores none. A file written by
        :func:`~coastmesh.io.meshes.telemac.write_selafin` names its EPSG code in the
        title (``coastmesh mesh, EPSG:32630``); ``crs`` must then agree.
    positive : {"up", "down"}, default "up"
        The sign of the file's ``BOTTOM``: Telemac's is the bed elevation
        (``"up"``: the depth is ``-BOTTOM``); ``"down"`` reads a file written with
        ``write_selafin(..., positive="down")``.

    Returns
    -------
    Mesh
        Nodes (X, Y plus the offset ``IPARAM(3:4)``, in float64) and triangles
        (``IKLE``) in file order, a clockwise triangle turned counter-clockwise;
        ``point_data["depth"]`` in metres, positive down, from ``BOTTOM`` (or
        ``FOND``) at the first time step; the boundary edges from the ``.cli``,
        ring by ring in its order, each with the domain on its left; ids and
        kinds by Telemac's rules (see Notes); no names; ``surface_id`` 1.

    Raises
    ------
    FormatError
        If the file is not a SELAFIN file (first marker not 80), a record is
        truncated or has the wrong size or markers, ``NDP`` is not 3 (only 2D
        triangle meshes are read), an ``IKLE`` node is outside ``1..NPOIN``, the
        bed is not finite, or the ``.cli`` has a line of fewer than 13 values, a
        value that is not a number, a node ``N`` outside ``1..NPOIN``, not on the
        boundary or listed twice, lines that do not follow the boundary rings
        node after node, or boundary nodes left out; the message names the file
        (and the ``.cli`` line).
    InputDataError
        If the file is missing, or what it holds is not a valid mesh.
    ConfigError
        If ``positive`` or ``crs`` is invalid.

    Warns
    -----
    CoastmeshWarning
        If there is no ``.cli`` beside the file (the boundary edges then come
        from the triangles, all land), or no bed variable or time step (no
        depth).

    Notes
    -----
    Telemac marks boundaries on the nodes, not the segments (BIEF ``front2.f``):
    a node is solid where ``LIHBOR = 2`` and liquid otherwise (4 free, 5
    prescribed elevation, 1 incident wave), and a segment is liquid only if both
    its nodes are. :func:`~coastmesh.io.meshes.telemac.write_selafin` gives every
    node of an open edge the open codes, so each edge gets its kind back.

    The ``.cli`` holds no boundary ids (``write_selafin`` writes none), so they
    are made: every solid segment gets id 1 (``"shoreline"``), and liquid
    boundary ``k``, numbered as Telemac numbers them, gets id ``k + 1``
    (``"open"``): id 2 is the first liquid boundary of the steering file's lists
    (``PRESCRIBED ELEVATIONS = ...``). Telemac numbers the contours from the
    south-westernmost boundary node, then from that of the contours left, each
    along the boundary from that node; it starts a new liquid boundary after a
    solid run, and where the codes ``LIHBOR, LIUBOR`` change between two liquid
    nodes (the segment between them stays with the boundary it leaves). So open
    boundaries written apart but meeting come back as one id, as Telemac takes
    them, and land ids written apart come back as id 1.

    Lines of the ``.cli`` follow each other along a ring while their nodes are
    joined by a boundary edge of the mesh; where they are not, the ring closes
    (its last node must be joined to its first) and the next line starts another.
    A ring listed with the domain on its right is turned round. ``N`` is read,
    ``K`` and the prescribed values are not.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from coastmesh.io.meshes.telemac import write_selafin
    >>> m = Mesh([[0, 0], [1, 0], [1, 1], [0, 1], [2, 0], [2, 1]],
    ...          [[0, 1, 2], [0, 2, 3], [1, 4, 5], [1, 5, 2]],
    ...          [[0, 1], [1, 4], [4, 5], [5, 2], [2, 3], [3, 0]],
    ...          [7, 7, 1, 1, 1, 1], 1, "EPSG:32630",
    ...          {"depth": [5.0, 6.0, 7.0, 8.0, 9.0, 9.5]},
    ...          boundary_kinds={1: "shoreline", 7: "open"})
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "strip.slf"
    >>> write_selafin(path, m)
    >>> back = read_selafin_mesh(path)
    >>> back.boundary_edges.tolist()
    [[0, 1], [1, 4], [4, 5], [5, 2], [2, 3], [3, 0]]
    >>> back.boundary_ids.tolist(), back.boundary_kinds
    ([2, 2, 1, 1, 1, 1], {1: 'shoreline', 2: 'open'})
    >>> back.point_data["depth"].tolist(), back.crs.to_epsg()
    ([5.0, 6.0, 7.0, 8.0, 9.0, 9.5], 32630)
    """
    if positive not in POSITIVE:
        raise ConfigError(
            f"positive={positive!r}; expected one of {', '.join(POSITIVE)}"
        )
    name = check_input(path)
    geometry = _read_geometry(name)
    match = _TITLE_CRS.match(geometry.title)
    stored = CRS.from_epsg(int(match.group(1))) if match else None
    found = resolve_crs(stored, crs, name)
    points = geometry.points
    sphere = found is not None and bool(found.is_geographic)
    triangles = counter_clockwise(points, geometry.triangles, sphere=sphere)
    cli = Path(name).with_suffix(".cli")
    if cli.exists():
        edges, ids = cli_boundary(cli, name, points, triangles)
    else:
        warnings.warn(
            f"{name}: no boundary conditions file {cli.name} beside it; the boundary "
            "edges are those of one triangle, all land (boundary id 1)",
            CoastmeshWarning,
            stacklevel=2,
        )
        edges = outline(triangles, len(points))
        ids = np.full(len(edges), LAND_ID, dtype=np.int64)
    point_data: dict[str, NDArray[np.float64]] = {}
    if geometry.bottom is None:
        warnings.warn(
            f"{name}: {geometry.missing}; the mesh has no depth",
            CoastmeshWarning,
            stacklevel=2,
        )
    else:
        bottom = geometry.bottom
        point_data["depth"] = -bottom if positive == "up" else bottom
    kinds = {
        int(pid): "shoreline" if pid == LAND_ID else "open" for pid in np.unique(ids)
    }
    logger.debug(
        "read %s: %d nodes, %d triangles, %d boundary edges, %d open ids",
        name,
        len(points),
        len(triangles),
        len(edges),
        sum(kind == "open" for kind in kinds.values()),
    )
    return mesh_from_file(
        name, points, triangles, edges, ids, 1, found, point_data, {}, kinds
    )


class _Records:
    """The Fortran sequential records of a file, one after another.

    Each record is a byte count, the data, the same count again, in the byte
    order of the first marker (the 80 of the title record).
    """

    def __init__(self, stream: IO[bytes], name: str) -> None:
        self.stream = stream
        self.name = name
        head = stream.read(4)
        if len(head) == 4 and struct.unpack(">i", head)[0] == _TITLE_BYTES:
            self.endian = ">"
        elif len(head) == 4 and struct.unpack("<i", head)[0] == _TITLE_BYTES:
            self.endian = "<"
        else:
            raise FormatError(
                f"{name}: not a SELAFIN file: it starts with {head.hex() or 'nothing'}"
                f", not the marker of the {_TITLE_BYTES}-byte title record"
            )
        stream.seek(0)

    def read(self, what: str, size: int | None = None, expected: str = "") -> bytes:
        """Return the next record's data; ``size`` is the byte count it must hold."""
        start = self.stream.tell()
        head = self.stream.read(4)
        if len(head) < 4:
            raise FormatError(
                f"{self.name}: the file ends at byte {start}, before the {what} "
                "record: it is truncated"
            )
        (count,) = struct.unpack(self.endian + "i", head)
        if count < 0 or (size is not None and count != size):
            raise FormatError(
                f"{self.name}: the {what} record (byte {start}) holds {count} bytes, "
                f"expected {size}{expected}"
            )
        body = self.stream.read(count)
        tail = self.stream.read(4)
        if len(body) < count or len(tail) < 4:
            raise FormatError(
                f"{self.name}: the file ends inside the {what} record, which starts "
                f"at byte {start} and holds {count} bytes: it is truncated"
            )
        if struct.unpack(self.endian + "i", tail)[0] != count:
            raise FormatError(
                f"{self.name}: the {what} record (byte {start}) ends with the marker "
                f"{struct.unpack(self.endian + 'i', tail)[0]}, not its byte count "
                f"{count}"
            )
        return body

    def ints(self, what: str, count: int) -> list[int]:
        """Return the next record as ``count`` int32 values."""
        body = self.read(what, 4 * count, f" ({count} integers)")
        return [int(v) for v in np.frombuffer(body, self.endian + "i4")]

    def at_end(self) -> bool:
        """Whether no byte is left."""
        here = self.stream.tell()
        more = self.stream.read(1)
        self.stream.seek(here)
        return not more


def _read_geometry(name: str) -> _Geometry:
    """Read the header, the mesh and the bed at the first time step."""
    with open(name, "rb") as stream:
        records = _Records(stream, name)
        title = records.read("title", _TITLE_BYTES)[:72].decode("latin-1").rstrip()
        nbv1, nbv2 = records.ints("NBV1 NBV2", 2)
        if nbv1 < 0 or nbv2 < 0:
            raise FormatError(f"{name}: NBV1, NBV2 = {nbv1}, {nbv2}: expected >= 0")
        names = [
            records.read(f"name and unit of variable {k + 1}", 32)[:16]
            .decode("latin-1")
            .strip()
            .upper()
            for k in range(nbv1 + nbv2)
        ]
        iparam = records.ints("IPARAM", 10)
        if iparam[9] == 1:
            records.read("date", 24, " (6 integers, as IPARAM(10) = 1 says)")
        nelem, npoin, ndp, _ = records.ints("NELEM NPOIN NDP 1", 4)
        if ndp != 3:
            planes = f", {iparam[6]} planes: a 3D file" if iparam[6] > 1 else ""
            raise FormatError(
                f"{name}: NDP = {ndp} nodes per element{planes}; only 2D meshes of "
                "triangles (NDP = 3) are read"
            )
        if nelem < 0 or npoin < 1:
            raise FormatError(
                f"{name}: NELEM = {nelem}, NPOIN = {npoin}: expected NELEM >= 0 and "
                "NPOIN >= 1"
            )
        ikle = records.read("IKLE", 12 * nelem, f" (4 x NDP x NELEM = 12 x {nelem})")
        triangles = np.frombuffer(ikle, records.endian + "i4").reshape(nelem, 3)
        bad = np.flatnonzero((triangles < 1).any(axis=1) | (triangles > npoin).any(1))
        if len(bad):
            raise FormatError(
                f"{name}: element {bad[0] + 1} has nodes {triangles[bad[0]].tolist()}; "
                f"IKLE node numbers run 1..NPOIN = 1..{npoin}"
            )
        records.read("IPOBO", 4 * npoin, f" (4 x NPOIN = 4 x {npoin})")
        x, dtype = _coordinates(records, "X", npoin)
        y, _ = _coordinates(records, "Y", npoin, dtype)
        points = np.column_stack([x + iparam[2], y + iparam[3]])
        bottom, missing = _bottom(records, names, npoin, dtype)
    return _Geometry(title, points, triangles.astype(np.int64) - 1, bottom, missing)


def _coordinates(
    records: _Records, what: str, npoin: int, dtype: np.dtype[Any] | None = None
) -> tuple[NDArray[np.float64], np.dtype[Any]]:
    """Read X or Y; the record's size gives the precision (float32 or float64)."""
    body = records.read(what, None if dtype is None else npoin * dtype.itemsize)
    if dtype is None:
        if len(body) not in (4 * npoin, 8 * npoin):
            raise FormatError(
                f"{records.name}: the {what} record holds {len(body)} bytes; expected "
                f"4 or 8 x NPOIN = {4 * npoin} or {8 * npoin} (single or double "
                "precision)"
            )
        dtype = np.dtype(f"{records.endian}f{len(body) // npoin}")
    return np.frombuffer(body, dtype).astype(np.float64), dtype


def _bottom(
    records: _Records, names: list[str], npoin: int, dtype: np.dtype[Any]
) -> tuple[NDArray[np.float64] | None, str]:
    """Read the bed variable at the first time step, or say why there is none."""
    found = [k for k, name in enumerate(names) if name in _BED]
    if not found:
        return None, f"no variable {' or '.join(_BED)} among {names}"
    if records.at_end():
        return None, f"no time step, so no value of {names[found[0]]}"
    records.read("time of the first step", dtype.itemsize)
    size = npoin * dtype.itemsize
    for k in range(found[0]):
        records.read(f"variable {names[k]!r} at the first time step", size)
    body = records.read(f"variable {names[found[0]]!r} at the first time step", size)
    bottom = np.frombuffer(body, dtype).astype(np.float64)
    bad = np.flatnonzero(~np.isfinite(bottom))
    if len(bad):
        raise FormatError(
            f"{records.name}: {names[found[0]]} is {bottom[bad[0]]} at node "
            f"{bad[0] + 1} ({len(bad)} nodes); a bed elevation must be finite"
        )
    return bottom, ""
