"""Telemac geometry: a SELAFIN (Serafin) mesh file and its ``.cli`` boundary file.

The layout follows Telemac's own reader and writer, HERMES ``utils_serafin.F``
(``OPEN_MESH_SRF``, ``SET_MESH_SRF``, ``GET_BND_VALUE_SRF``; read in the copy of
the Telemac sources in ``tomsail/telemac-conda``), checked against the readers of
python-serafin (``serafin/serafin.py``, ``SerafinHeader.from_file``) and
xarray-selafin (``xarray_selafin/xarray_backend.py``):

- every record is a Fortran sequential record: a big-endian int32 byte count, the
  data, the same count again;
- title (72 characters) + format ``"SERAFIN "`` (single precision), 80 bytes;
- NBV1, NBV2 (linear and quadratic variable counts): ``1 0``;
- one 32-byte record per variable: 16 characters of name, 16 of unit;
- IPARAM, 10 integers: ``IPARAM(1) = 1`` as Telemac writes it, ``IPARAM(3:4)``
  the coordinate offset (0 here), ``IPARAM(7)`` the number of planes (0 in 2D),
  ``IPARAM(8:9)`` NPTFR/NPTIR (0 for a serial file: Telemac then counts the
  non-zero IPOBO entries and the ``.cli`` lines), ``IPARAM(10) = 0``: no date
  record follows;
- NELEM, NPOIN, NDP = 3, 1;
- IKLE, element after element (``IKLES((IELEM-1)*NDP+I)`` in ``SET_MESH_SRF``),
  node numbers from 1;
- IPOBO, one integer per node: 0 inside, k for the k-th line of the ``.cli``;
- X, then Y, float32;
- one time step: the time (float32 0.0), then one record per variable.

The ``.cli`` file has one line per boundary node and 13 columns, ``LIHBOR LIUBOR
LIVBOR HBOR UBOR VBOR AUBOR LITBOR TBOR ATBOR BTBOR N K``, read with list-directed
``READ(NCLI,*)`` (``GET_BND_VALUE_SRF``); Telemac takes the number of boundary
nodes from the number of lines (``OPEN_BND_SRF``), so the file has no header and
no blank line.
"""

from __future__ import annotations

import logging
import os
import struct
import warnings
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from coastmesh.errors import CoastmeshWarning, FormatError
from coastmesh.io._atomic import AtomicOutputs, check_output
from coastmesh.io.meshes._model import (
    check_mesh,
    mesh_boundary_rings,
    node_depth,
    require_kinds,
)
from coastmesh.io.meshes.sphere import crossing_triangles, misdrawn_triangles, on_sphere
from coastmesh.types import Mesh
from coastmesh.types.topology import BoundaryRing

__all__ = ["write_selafin"]

logger = logging.getLogger(__name__)

# Telemac boundary codes (BIEF leclim.f): 0 KADH wall without slip, 1 KINC
# incident wave, 2 KLOG solid wall, 4 KSORT free, 5 KENT prescribed, 6 KENTU
# prescribed velocity
_CODES = frozenset({0, 1, 2, 4, 5, 6})
_LAND = 2  # KLOG: solid boundary, on LIHBOR, LIUBOR, LIVBOR and LITBOR
_OPEN_TRACER = 4  # KSORT: free tracer on open boundaries
_INT32_MAX = 2**31 - 1
_CHUNK = 1 << 20  # triangles per block in the single-precision check
_BOTTOM = b"BOTTOM          M               "


def write_selafin(
    path: str | os.PathLike[str],
    mesh: Mesh,
    *,
    overwrite: bool = False,
    positive: str = "up",
    cli: bool = True,
    open_codes: str | Sequence[int] = "5 4 4",
    title: str | None = None,
) -> None:
    """Write a mesh as a Telemac SELAFIN geometry file and its ``.cli`` file.

    Parameters
    ----------
    path : str or path-like
        The ``.slf`` file. The boundary conditions file goes next to it, with the
        same stem and the suffix ``.cli``.
    mesh : Mesh
        The mesh; it is not changed. Node depth, if any, is
        ``mesh.point_data["depth"]``, in metres, positive down.
    overwrite : bool, default False
        Whether existing files may be replaced.
    positive : {"up", "down"}, default "up"
        The sign of the ``BOTTOM`` variable. Telemac's ``BOTTOM`` is the bed
        elevation (positive up), so "up" writes ``-depth``; "down" writes the depth
        itself.
    cli : bool, default True
        Also write the ``.cli`` boundary conditions file; it needs a kind (open or
        shoreline) for every boundary id in ``mesh.boundary_kinds``.
    open_codes : str or sequence of 3 int, default "5 4 4"
        ``LIHBOR LIUBOR LIVBOR`` of open boundary nodes: by default prescribed
        elevation, free velocity. Shoreline nodes get ``2 2 2`` (solid wall).
    title : str, optional
        The file title, ASCII, at most 72 characters. By default it names the
        mesh CRS, and says when the coordinates are geographic.

    Raises
    ------
    FormatError
        If ``positive``, ``open_codes`` or ``title`` is invalid; the depth is not
        one finite value per node; the mesh is too large for 32-bit records; the
        boundary edges do not form simple rings; a boundary id has no kind (with
        ``cli``); or a shoreline run between two open boundaries has fewer than 3
        edges (Telemac would make it open, or stop).
    OutputExistsError
        If the ``.slf`` or (with ``cli``) the ``.cli`` file exists and
        ``overwrite`` is false; then nothing is written.

    Warns
    -----
    CoastmeshWarning
        If the mesh has no depth (``BOTTOM`` is then 0 everywhere), a triangle
        has no area left once the coordinates are rounded to single precision,
        or triangles cross the antimeridian (a global mesh; see Notes).

    Notes
    -----
    Coordinates are written as they are, in the mesh CRS, in single precision.
    Most Telemac runs need metres (a projected CRS); for longitude/latitude in
    degrees the steering file must say ``SPHERICAL COORDINATES = YES`` and
    ``GEOGRAPHIC SYSTEM = 1`` (WGS84 longitude/latitude in real degrees).
    Single precision keeps about 7 digits: 0.5 m at a UTM northing of 6500 km.

    A global mesh (:func:`~coastmesh.io.meshes.sphere.on_sphere`) is written as the
    ADCIRC and SCHISM writers write it: longitudes in [-180, 180), every
    triangle counter-clockwise on the sphere, the ``.cli`` rings ordered on the
    sphere. Telemac releases turn longitude, latitude into Mercator metres when
    they read the mesh (``read_mesh_coord.f``), where a triangle across the
    antimeridian spans the map; support for global meshes is planned (Telemac
    issue 985), hence the warning.

    The ``.cli`` lists the boundary nodes ring by ring, as
    :func:`~coastmesh.types.topology.boundary_rings` orders them: the exterior
    counter-clockwise, then the islands clockwise. ``N`` is the node number (from
    1), ``K`` the line number. ``LITBOR`` is 2 on land and 4 on open boundaries;
    the prescribed values are 0. A node where an open and a shoreline boundary
    meet takes the open codes: Telemac (BIEF ``front2.f``) counts a segment
    between a liquid and a solid node as solid, and one between two liquid nodes
    as liquid, so the tagged edges keep their kind. Telemac numbers the liquid
    boundaries itself, in order along each contour from its south-westernmost
    node; adjacent open boundaries with the same codes form one liquid boundary.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> m = Mesh([[0, 0], [1, 0], [1, 1], [0, 1]], [[0, 1, 2], [0, 2, 3]],
    ...          [[0, 1], [1, 2], [2, 3], [3, 0]], [2, 1, 1, 1], 1, "EPSG:32630",
    ...          {"depth": [5.0, 6.0, 7.0, 8.0]},
    ...          boundary_kinds={1: "shoreline", 2: "open"})
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> write_selafin(folder / "square.slf", m)
    >>> sorted(p.name for p in folder.iterdir())
    ['square.cli', 'square.slf']
    >>> print((folder / "square.cli").read_text().splitlines()[0])
    5 4 4 0.000 0.000 0.000 0.000 4 0.000 0.000 0.000 1 1
    """
    check_mesh(mesh)
    name = os.fspath(path)
    slf_path = Path(path)
    cli_path = slf_path.with_suffix(".cli")
    if positive not in ("up", "down"):
        raise FormatError(
            f"{name}: positive is {positive!r}; expected 'up' (BOTTOM is the bed "
            "elevation, -depth) or 'down' (BOTTOM is the depth)"
        )
    codes = _open_codes(open_codes, name)
    header_title = _title(mesh, title, name)
    _check_size(mesh, name)
    if cli and slf_path.suffix.lower() == ".cli":
        raise FormatError(
            f"{name}: the geometry file cannot end in .cli, which is the name of its "
            "boundary conditions file; use .slf"
        )
    check_output(slf_path, overwrite=overwrite)
    if cli:
        check_output(cli_path, overwrite=overwrite)
    rings = mesh_boundary_rings(mesh, name)
    order = (
        np.concatenate([ring.nodes for ring in rings])
        if rings
        else np.empty(0, dtype=np.int64)
    )
    table = _cli_table(mesh, rings, codes, name) if cli else None
    bottom = node_depth(mesh, name, positive=positive, label="BOTTOM", stacklevel=3)
    x = mesh.points[:, 0].astype(np.float32)
    y = mesh.points[:, 1].astype(np.float32)
    _check_single_precision(mesh, x, y, name)
    _warn_crossing(mesh, name)
    ipobo = np.zeros(len(mesh.points), dtype=">i4")
    ipobo[order] = np.arange(1, len(order) + 1)
    with AtomicOutputs(overwrite=overwrite) as outputs:
        staged_slf = outputs.stage(slf_path)
        staged_cli = outputs.stage(cli_path) if table is not None else None
        _write_slf(staged_slf, header_title, mesh.triangles, ipobo, x, y, bottom)
        if staged_cli is not None and table is not None:
            _write_cli(staged_cli, table, order)
    logger.debug(
        "wrote %s%s: %d nodes, %d triangles, %d boundary nodes",
        name,
        f" and {cli_path}" if cli else "",
        len(mesh.points),
        len(mesh.triangles),
        len(order),
    )


def _open_codes(open_codes: str | Sequence[int], name: str) -> tuple[int, int, int]:
    """Parse ``open_codes`` into (LIHBOR, LIUBOR, LIVBOR)."""
    parts = open_codes.split() if isinstance(open_codes, str) else list(open_codes)
    try:
        codes = tuple(int(p) for p in parts)
    except (TypeError, ValueError):
        codes = ()
    if len(codes) != 3 or not set(codes) <= _CODES:
        raise FormatError(
            f"{name}: open_codes is {open_codes!r}; expected three Telemac codes "
            f"LIHBOR LIUBOR LIVBOR from {sorted(_CODES)}, such as '5 4 4' "
            "(prescribed elevation, free velocity)"
        )
    if codes[0] == _LAND:
        raise FormatError(
            f"{name}: open_codes is {open_codes!r}; LIHBOR = 2 marks a solid wall, "
            "so the open boundaries would be land; use 4 (free) or 5 (prescribed)"
        )
    return codes[0], codes[1], codes[2]


def _title(mesh: Mesh, title: str | None, name: str) -> bytes:
    """Return the 80-byte title record: 72 characters, then ``SERAFIN``."""
    if title is None:
        if mesh.crs is None:
            text = "coastmesh mesh, CRS unknown"
        else:
            epsg = mesh.crs.to_epsg()
            crs = f"EPSG:{epsg}" if epsg is not None else mesh.crs.name
            suffix = ", geographic lon/lat degrees" if mesh.crs.is_geographic else ""
            text = f"coastmesh mesh, {crs}"[: 72 - len(suffix)] + suffix
        text = text.encode("ascii", "replace").decode("ascii")
    else:
        if not isinstance(title, str) or not title.isascii() or len(title) > 72:
            shown = len(title) if isinstance(title, str) else type(title).__name__
            raise FormatError(
                f"{name}: title {title!r} ({shown}) must be ASCII text of at most 72 "
                "characters (the SELAFIN title record)"
            )
        text = title
    return text.ljust(72).encode("ascii") + b"SERAFIN "


def _check_size(mesh: Mesh, name: str) -> None:
    """Refuse meshes whose records overflow the 32-bit Fortran record markers."""
    largest = max(12 * len(mesh.triangles), 4 * len(mesh.points))
    if largest > _INT32_MAX:
        raise FormatError(
            f"{name}: {len(mesh.points)} nodes and {len(mesh.triangles)} triangles "
            f"need a {largest}-byte record; SELAFIN record markers are 32-bit "
            f"(at most {_INT32_MAX} bytes)"
        )


def _cli_table(
    mesh: Mesh, rings: list[BoundaryRing], codes: tuple[int, int, int], name: str
) -> NDArray[np.int64]:
    """Return LIHBOR, LIUBOR, LIVBOR, LITBOR of each boundary node, (nptfr, 4)."""
    require_kinds(mesh, name, hint=", or write with cli=False (no .cli file)")
    if not rings:
        return np.empty((0, 4), dtype=np.int64)
    edge_ids = np.concatenate([ring.ids for ring in rings])
    open_ids = np.array(
        [pid for pid, kind in mesh.boundary_kinds.items() if kind == "open"],
        dtype=np.int64,
    )
    open_edge = np.isin(edge_ids, open_ids)  # the edge from node i to the next
    prev, nxt = _ring_neighbours([len(ring.nodes) for ring in rings])
    liquid = open_edge | open_edge[prev]  # a junction node takes the open codes
    _check_land_runs(mesh, rings, open_edge, liquid, prev, nxt, edge_ids, name)
    table = np.empty((len(edge_ids), 4), dtype=np.int64)
    for column, code in enumerate(codes):
        table[:, column] = np.where(liquid, code, _LAND)
    table[:, 3] = np.where(liquid, _OPEN_TRACER, _LAND)
    return table


def _ring_neighbours(
    lengths: list[int],
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """Previous and next position, within its ring, of each concatenated node."""
    sizes = np.asarray(lengths, dtype=np.int64)
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    start = np.repeat(starts, sizes)
    size = np.repeat(sizes, sizes)
    local = np.arange(int(sizes.sum())) - start
    return start + (local - 1) % size, start + (local + 1) % size


def _check_land_runs(
    mesh: Mesh,
    rings: list[BoundaryRing],
    open_edge: NDArray[np.bool_],
    liquid: NDArray[np.bool_],
    prev: NDArray[np.int64],
    nxt: NDArray[np.int64],
    edge_ids: NDArray[np.int64],
    name: str,
) -> None:
    """Refuse shoreline runs Telemac would turn liquid or stop on (BIEF front2.f)."""
    # a land edge between two liquid nodes counts as liquid; a solid node between
    # two liquid nodes stops FRONT2 ("SOLID POINT BETWEEN TWO LIQUID POINTS")
    lost = ~open_edge & liquid & liquid[nxt]
    stuck = ~liquid & liquid[prev] & liquid[nxt]
    bad = np.flatnonzero(lost | stuck)
    if len(bad) == 0:
        return
    nodes = np.concatenate([ring.nodes for ring in rings])
    first = int(bad[0])
    pid = int(edge_ids[first])  # a shoreline edge in both cases
    label = mesh.boundary_names.get(pid)
    shown = f"{pid} ({label!r})" if label else str(pid)
    raise FormatError(
        f"{name}: shoreline boundary {shown} has a run of fewer than 3 edges between "
        f"two open boundaries, at mesh node {int(nodes[first])} "
        f"({len(bad)} such place(s)); Telemac would make it open or stop "
        "(BIEF front2.f). Refine the mesh there or tag the run as open"
    )


def _warn_crossing(mesh: Mesh, name: str) -> None:
    """Warn that Telemac releases cannot run triangles across the antimeridian."""
    if not on_sphere(mesh):
        return
    count = int(crossing_triangles(mesh.points, mesh.triangles).sum())
    warnings.warn(
        f"{name}: {count} triangles cross the antimeridian; they are written as "
        "ADCIRC and SCHISM take them (longitude in [-180, 180), counter-clockwise "
        "on the sphere), but Telemac releases project longitude, latitude to "
        "Mercator (read_mesh_coord.f), where these triangles span the map: only a "
        "Telemac with global-mesh support can run this mesh",
        CoastmeshWarning,
        stacklevel=3,
    )


def _check_single_precision(
    mesh: Mesh, x: NDArray[np.float32], y: NDArray[np.float32], name: str
) -> None:
    """Warn if rounding to float32 leaves triangles with no or negative area.

    In a mesh on the sphere, the triangles across the antimeridian or at a pole
    are left out: the lon/lat plane does not draw them as they are.
    """
    tri = mesh.triangles
    if on_sphere(mesh):
        tri = tri[~misdrawn_triangles(mesh.points, tri)]
    bad = 0
    first = -1
    for start in range(0, len(tri), _CHUNK):
        block = tri[start : start + _CHUNK]
        x0, x1, x2 = (x[block[:, k]].astype(np.float64) for k in range(3))
        y0, y1, y2 = (y[block[:, k]].astype(np.float64) for k in range(3))
        cross = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)
        flat = np.flatnonzero(cross <= 0)
        if len(flat) and first < 0:
            first = start + int(flat[0])
        bad += len(flat)
    if bad:
        warnings.warn(
            f"{name}: {bad} triangles (the first is {first}) have zero or negative "
            "area once the coordinates are rounded to single precision; subtract an "
            "offset from the coordinates or use a projected CRS with smaller values",
            CoastmeshWarning,
            stacklevel=3,
        )


def _record(out, data: bytes | NDArray) -> None:
    """Write one Fortran sequential record: byte count, data, byte count."""
    size = len(data) if isinstance(data, bytes) else data.nbytes
    marker = struct.pack(">i", size)
    out.write(marker)
    out.write(data if isinstance(data, bytes) else np.ascontiguousarray(data).data)
    out.write(marker)


def _write_slf(
    path: Path,
    title: bytes,
    triangles: NDArray[np.int64],
    ipobo: NDArray[np.int32],
    x: NDArray[np.float32],
    y: NDArray[np.float32],
    bottom: NDArray[np.float64],
) -> None:
    ikle = np.empty(triangles.shape, dtype=">i4")
    np.add(triangles, 1, out=ikle, casting="unsafe")  # node numbers from 1
    iparam = np.zeros(10, dtype=">i4")
    iparam[0] = 1
    sizes = np.array([len(triangles), len(x), 3, 1], dtype=">i4")
    with open(path, "wb") as out:
        _record(out, title)
        _record(out, np.array([1, 0], dtype=">i4"))
        _record(out, _BOTTOM)
        _record(out, iparam)
        _record(out, sizes)
        _record(out, ikle)
        _record(out, ipobo)
        _record(out, x.astype(">f4"))
        _record(out, y.astype(">f4"))
        _record(out, np.array([0.0], dtype=">f4"))
        _record(out, bottom.astype(">f4"))


def _write_cli(path: Path, table: NDArray[np.int64], order: NDArray[np.int64]) -> None:
    # newline="\n": LECLIM reports Windows line ends as a reading error
    lines = [
        f"{h} {u} {v} 0.000 0.000 0.000 0.000 {t} 0.000 0.000 0.000 {n} {k}\n"
        for k, (h, u, v, t, n) in enumerate(
            zip(*table.T.tolist(), (order + 1).tolist(), strict=True), start=1
        )
    ]
    with open(path, "w", encoding="ascii", newline="\n") as out:
        out.writelines(lines)
