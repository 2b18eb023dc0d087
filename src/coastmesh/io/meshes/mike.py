"""DHI MIKE ``.mesh`` files (MIKE 21/3 FM): nodes with boundary codes, triangles.

The ASCII layout (as ``mikecore.MeshFile`` reads it, and as ``mikeio.Mesh`` opens
it):

.. code-block:: text

    100079 1000 NPOIN PROJECTION        item type (bathymetry), unit (metre)
    id x y z code                       NPOIN lines, ids 1..NPOIN
    NELEM 3 21                          3 nodes per element, 21 = triangles only
    id n1 n2 n3                         NELEM lines, 1-based, counter-clockwise

``code`` is 0 for an interior (water) node, 1 for a land node and 2, 3, ... for
the nodes of open boundaries (mikeio: "0=water, 1=land, 2...=open boundaries").
MIKE has no boundary edges: it derives the code of each boundary face from its two
nodes, so the node codes are chosen to give every boundary edge back its kind (see
:func:`write_mike_mesh`).
"""

from __future__ import annotations

import logging
import os
from typing import Any

import numpy as np
from numpy.typing import NDArray
from pyproj import CRS
from pyproj.exceptions import CRSError

from coastmesh.errors import ConfigError, FormatError, InputDataError
from coastmesh.io._atomic import atomic_write
from coastmesh.io._inputs import check_input, resolve_crs
from coastmesh.io.meshes._model import (
    POSITIVE,
    check_mesh,
    mesh_boundary_rings,
    node_depth,
    require_kinds,
)
from coastmesh.io.meshes._reading import counter_clockwise, mesh_from_file
from coastmesh.io.meshes._table import TextLines, put_lines, write_table
from coastmesh.io.meshes.sphere import crossing_triangles, on_sphere
from coastmesh.types import Mesh
from coastmesh.types.topology import unique_edges

__all__ = ["read_mike_mesh", "write_mike_mesh"]

logger = logging.getLogger(__name__)

BATHYMETRY_ITEM = 100079  # eumIBathymetry
METRE_UNIT = 1000  # eumUmeter
LAND_CODE = 1
GEOGRAPHIC = "LONG/LAT"  # WGS 84 longitude, latitude in degrees
LOCAL = "NON-UTM"  # local coordinates, no projection
NODES_PER_ELEMENT = 3
TRIANGLES_ONLY = 21  # element type code of a mesh of triangles
_SIGNIFICANT = 15


def write_mike_mesh(
    path: str | os.PathLike[str],
    mesh: Mesh,
    *,
    overwrite: bool = False,
    positive: str = "up",
    crs_wkt: str | None = None,
) -> dict[int, int]:
    """Write a mesh as a DHI MIKE ``.mesh`` file with boundary codes.

    Parameters
    ----------
    path : str or path-like
        The output file, such as ``domain.mesh``.
    mesh : Mesh
        The mesh; every boundary id needs a kind in ``mesh.boundary_kinds``
        (``"open"`` or ``"shoreline"``). Depth is ``mesh.point_data["depth"]``
        (metres, positive down); without it every node gets z = 0, with a
        warning.
    overwrite : bool, default False
        Whether an existing file may be replaced.
    positive : {"up", "down"}, default "up"
        Sign of the written z: ``"up"`` writes the bed elevation, ``-depth``,
        which is what MIKE's bathymetry holds (water below the datum is
        negative); ``"down"`` writes the depth as it is.
    crs_wkt : str, optional
        The projection string of the header: a WKT, or a MIKE name such as
        ``"LONG/LAT"`` or ``"UTM-32"``. By default it comes from ``mesh.crs``:
        ``"LONG/LAT"`` for geographic WGS 84 (EPSG:4326), ``"NON-UTM"`` (local
        coordinates) when the CRS is unknown, else the CRS as ESRI WKT 1 (the form
        ``mikeio.spatial.CRS.from_pyproj`` writes).

    Returns
    -------
    dict of int to int
        The node code of each open boundary id: the open ids in increasing order
        get codes 2, 3, ... Land boundaries all get code 1; interior nodes 0.

    Raises
    ------
    FormatError
        If a boundary id has no kind, the boundary edges do not form simple rings,
        the depth is not one finite number per node, the CRS has no ESRI WKT 1
        form (give ``crs_wkt``), a land boundary between two open boundaries
        is a single edge (node codes cannot mark it as land), or a lon/lat mesh
        has triangles that cross the antimeridian (a global mesh).
    ConfigError
        If ``positive`` is invalid.
    OutputExistsError
        If ``path`` exists and ``overwrite`` is false.

    Warns
    -----
    CoastmeshWarning
        If the mesh has no ``depth`` point data (zeros are written).

    Notes
    -----
    MIKE gives each boundary face (edge) a code from its two nodes, walking with
    the domain on the left: a face is land (1) if either node has code 1, and
    otherwise takes the code of its end node. This is the rule of DHI's own mesh
    checks: ``DHI/MIKECore-Examples``, ``Examples/CSharp/MeshMerger.cs``
    (``MeshValidator.ValidateFaceInfo``) and ``DHI.Mesh`` (``SMeshFace``,
    ``SetBoundaryCode``). So a node where an open boundary meets land gets the
    open code, not 1: with code 1 there, the open boundary's end edge would turn
    into land. A node between two open boundaries gets the code of the one that
    ends there (walking with the domain on the left), so each keeps all its edges.
    Nodes of land edges that do not touch an open boundary get code 1. Every
    boundary edge is checked to decode to the code it should have; a land
    boundary of a single edge between two open ones cannot, and is an error.

    A global mesh (:func:`~coastmesh.io.meshes.sphere.on_sphere`: lon/lat, with
    triangles across the antimeridian) is refused: DHI documents no way for a
    ``.mesh`` file to hold an element across the antimeridian, and MIKE's own
    mesh tools work in the lon/lat plane, where such an element spans the map.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> m = Mesh([[0, 0], [1, 0], [1, 1], [0, 1], [2, 0]],
    ...          [[0, 1, 2], [0, 2, 3], [1, 4, 2]],
    ...          [[0, 1], [1, 4], [4, 2], [2, 3], [3, 0]], [2, 2, 1, 1, 1], 1,
    ...          "EPSG:4326", point_data={"depth": [5.0, 5.0, 4.0, 4.0, 6.0]},
    ...          boundary_kinds={1: "shoreline", 2: "open"})
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "tri.mesh"
    >>> write_mike_mesh(path, m)
    {2: 2}
    >>> print(path.read_text().splitlines()[0])
    100079 1000 5 LONG/LAT
    >>> nodes = [line.split() for line in path.read_text().splitlines()[1:6]]
    >>> [(float(z), int(code)) for _, _, _, z, code in nodes]
    [(-5.0, 2), (-5.0, 2), (-4.0, 1), (-4.0, 1), (-6.0, 2)]
    """
    check_mesh(mesh)
    name = os.fspath(path)
    if on_sphere(mesh):
        count = int(crossing_triangles(mesh.points, mesh.triangles).sum())
        raise FormatError(
            f"{name}: {count} triangles cross the antimeridian (longitude span over "
            "180 degrees), which the MIKE .mesh format cannot hold; write a global "
            "mesh as fort14, gr3 or ugrid"
        )
    z = node_depth(mesh, name, positive=positive, label="z", stacklevel=3)
    projection = _projection(mesh, name, crs_wkt)
    kinds = require_kinds(mesh, name)
    open_ids = sorted(pid for pid, kind in kinds.items() if kind == "open")
    codes_of = {pid: LAND_CODE + 1 + k for k, pid in enumerate(open_ids)}
    codes = _node_codes(mesh, name, codes_of)
    n, m = len(mesh.points), len(mesh.triangles)
    with atomic_write(path, overwrite=overwrite) as tmp, open(tmp, "wb") as handle:
        put_lines(handle, f"{BATHYMETRY_ITEM} {METRE_UNIT} {n} {projection}")
        write_table(
            handle,
            [
                (np.arange(1, n + 1), None),
                (mesh.points[:, 0], _SIGNIFICANT),
                (mesh.points[:, 1], _SIGNIFICANT),
                (z, _SIGNIFICANT),
                (codes, None),
            ],
        )
        put_lines(handle, f"{m} {NODES_PER_ELEMENT} {TRIANGLES_ONLY}")
        write_table(
            handle,
            [(np.arange(1, m + 1), None)]
            + [(mesh.triangles[:, k] + 1, None) for k in range(3)],
        )
    logger.debug(
        "wrote %s: %d nodes, %d triangles, open boundary codes %s",
        name,
        n,
        m,
        codes_of,
    )
    return codes_of


def read_mike_mesh(
    path: str | os.PathLike[str], *, crs: Any = None, positive: str = "up"
) -> Mesh:
    """Read a DHI MIKE ``.mesh`` file of triangles as a Mesh.

    Parameters
    ----------
    path : str or path-like
        The ``.mesh`` file (ASCII).
    crs : pyproj.CRS or CRS-like, optional
        The CRS of the coordinates, for a header whose projection string pyproj
        does not know (a MIKE name such as ``UTM-32``) or that says ``NON-UTM``;
        if the header gives a CRS (``LONG/LAT``, a WKT), it must agree.
    positive : {"up", "down"}, default "up"
        The sign of the file's z: ``"up"`` for a bed elevation (MIKE's
        bathymetry; the depth is ``-z``), ``"down"`` for a depth.

    Returns
    -------
    Mesh
        Nodes and triangles in file order (a clockwise triangle is turned
        counter-clockwise); ``point_data["depth"]`` in metres, positive down;
        the boundary edges with the code MIKE gives each boundary face as their
        id: 1 for land (kind ``"shoreline"``), 2, 3, ... for the open boundaries
        (kind ``"open"``); no names; ``surface_id`` 1.

    Raises
    ------
    InputDataError
        If the file is missing, a line lacks a value or holds a non-number, the
        node ids are not ``1..NPOIN`` in order, an element is not a triangle, or a
        boundary face has code 0 at both ends; the message names the line.
    ConfigError
        If ``positive`` or ``crs`` is invalid.

    Notes
    -----
    MIKE stores codes on the nodes, not the edges. A boundary face (edge), with
    the domain on its left, is land if either node has code 1, and otherwise
    takes the code of its end node (or of its start node if the end node has code
    0), the rule :func:`write_mike_mesh` encodes. All land boundaries share code
    1, so land ids written apart come back as one id 1; open ids come back as
    their codes.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> m = Mesh([[0, 0], [1, 0], [1, 1], [0, 1]], [[0, 1, 2], [0, 2, 3]],
    ...          [[0, 1], [1, 2], [2, 3], [3, 0]], [5, 1, 1, 1], 1, "EPSG:4326",
    ...          point_data={"depth": [5.0, 5.0, 4.0, 4.0]},
    ...          boundary_kinds={1: "shoreline", 5: "open"})
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "square.mesh"
    >>> write_mike_mesh(path, m)
    {5: 2}
    >>> back = read_mike_mesh(path)
    >>> edges = map(tuple, back.boundary_edges.tolist())
    >>> sorted(zip(edges, back.boundary_ids.tolist()))
    [((0, 1), 2), ((1, 2), 1), ((2, 3), 1), ((3, 0), 1)]
    >>> back.boundary_kinds, back.crs.to_epsg(), back.point_data["depth"].tolist()
    ({1: 'shoreline', 2: 'open'}, 4326, [5.0, 5.0, 4.0, 4.0])
    """
    if positive not in POSITIVE:
        raise ConfigError(
            f"positive={positive!r}; expected one of {', '.join(POSITIVE)}"
        )
    lines = TextLines.read(check_input(path))
    what = "ITEM UNIT NPOIN PROJECTION"
    words = lines.next_line().split(maxsplit=3)
    try:
        count = int(words[2])
    except (IndexError, ValueError):
        raise lines.error(what, "expected 3 integers and a projection") from None
    projection = words[3].strip() if len(words) > 3 else LOCAL
    table = lines.table(count, 5, float, "ID X Y Z CODE")
    if not np.array_equal(table[:, 0], np.arange(1, count + 1)):
        raise lines.error("ID X Y Z CODE", f"node ids must run 1..{count} in order")
    elements, per_element, kind = lines.ints(3, "NELEM NPE TYPE")
    if (per_element, kind) != (NODES_PER_ELEMENT, TRIANGLES_ONLY):
        raise lines.error(
            "NELEM NPE TYPE",
            f"expected {NODES_PER_ELEMENT} nodes per element and type "
            f"{TRIANGLES_ONLY} (triangles only)",
        )
    corners = lines.table(elements, 4, int, "ID N1 N2 N3")[:, 1:] - 1
    if corners.size and (corners.min() < 0 or corners.max() >= count):
        raise lines.error("ID N1 N2 N3", f"node numbers must be in 1..{count}")
    points = table[:, 1:3]
    found = resolve_crs(_header_crs(projection), crs, lines.path)
    sphere = found is not None and bool(found.is_geographic)
    triangles = counter_clockwise(points, corners, sphere=sphere)
    edges, ids = _boundary_codes(triangles, table[:, 4].astype(np.int64), lines.path)
    z = table[:, 3]
    return mesh_from_file(
        lines.path,
        points,
        triangles,
        edges,
        ids,
        1,
        found,
        {"depth": -z if positive == "up" else z},
        {},
        {int(i): "shoreline" if i == LAND_CODE else "open" for i in np.unique(ids)},
    )


def _header_crs(projection: str) -> CRS | None:
    """Return the CRS of a header's projection; None if pyproj does not know it."""
    if projection.upper() == GEOGRAPHIC:
        return CRS.from_epsg(4326)
    if projection.upper() == LOCAL:
        return None
    try:
        return CRS.from_user_input(projection)
    except CRSError:
        logger.debug("MIKE projection %r: not a CRS pyproj knows", projection)
        return None


def _boundary_codes(
    triangles: NDArray[np.int64], codes: NDArray[np.int64], name: str
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """Return the boundary edges (domain on the left) and their face codes."""
    n = len(codes)
    edges, count = unique_edges(triangles, n)
    outer = edges[count == 1]
    half = triangles[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)  # as each triangle runs
    keys = half.min(axis=1) * n + half.max(axis=1)
    on_boundary = np.isin(keys, outer[:, 0] * n + outer[:, 1])
    directed = half[on_boundary][np.argsort(keys[on_boundary], kind="stable")]
    start, end = codes[directed[:, 0]], codes[directed[:, 1]]
    face = np.where((start == LAND_CODE) | (end == LAND_CODE), LAND_CODE, end)
    face = np.where(face == 0, start, face)
    if (face == 0).any():
        a, b = directed[np.flatnonzero(face == 0)[0]] + 1
        raise InputDataError(
            f"boundary face of nodes {a}-{b} has code 0 (water) at both ends; "
            "boundary nodes need code 1 (land) or 2, 3, ... (open)",
            path=name,
        )
    return directed, face


def _projection(mesh: Mesh, name: str, crs_wkt: str | None) -> str:
    """Return the header's projection string."""
    if crs_wkt is not None:
        if not isinstance(crs_wkt, str) or not crs_wkt.strip() or "\n" in crs_wkt:
            raise FormatError(
                f"{name}: crs_wkt={crs_wkt!r}: expected a projection string of one "
                "line, such as 'LONG/LAT' or a WKT"
            )
        return crs_wkt.strip()
    if mesh.crs is None:
        return LOCAL
    if mesh.crs.equals(CRS.from_epsg(4326), ignore_axis_order=True):
        return GEOGRAPHIC
    wkt = mesh.crs.to_wkt(version="WKT1_ESRI")
    if not wkt:
        raise FormatError(
            f"{name}: the mesh CRS {mesh.crs.name!r} has no ESRI WKT 1 form for the "
            "MIKE header; give the projection string as crs_wkt"
        )
    return wkt


def _node_codes(mesh: Mesh, name: str, codes_of: dict[int, int]) -> NDArray[np.int64]:
    """Return the MIKE code of each node (see :func:`write_mike_mesh`, Notes)."""
    rings = mesh_boundary_rings(mesh, name)
    codes = np.zeros(len(mesh.points), dtype=np.int64)
    for ring in rings:
        # edge i runs from nodes[i] to nodes[i + 1], domain on the left
        wanted = np.array([codes_of.get(int(pid), LAND_CODE) for pid in ring.ids])
        before = np.roll(wanted, 1)  # the edge ending at nodes[i]
        after = wanted  # the edge starting at nodes[i]
        codes[ring.nodes] = np.where(
            before != LAND_CODE,
            before,
            np.where(after != LAND_CODE, after, LAND_CODE),
        )
        start, end = codes[ring.nodes], codes[np.roll(ring.nodes, -1)]
        got = np.where((start == LAND_CODE) | (end == LAND_CODE), LAND_CODE, end)
        bad = np.flatnonzero(got != wanted)
        if len(bad):
            i = int(bad[0])
            a, b = int(ring.nodes[i]), int(ring.nodes[(i + 1) % len(ring.nodes)])
            raise FormatError(
                f"{name}: boundary id {int(ring.ids[i])}, edge of nodes {a}-{b}: a "
                "land boundary of one edge between two open boundaries; MIKE node "
                "codes cannot mark it as land: refine the mesh there or join the ids"
            )
    return codes
