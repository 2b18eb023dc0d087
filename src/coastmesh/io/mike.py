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

import numpy as np
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.errors import FormatError
from coastmesh.io._atomic import atomic_write
from coastmesh.io.adcirc import node_depth, require_kinds, write_table
from coastmesh.meshing.topology import boundary_rings
from coastmesh.types import Mesh

__all__ = ["write_mike_mesh"]

logger = logging.getLogger(__name__)

BATHYMETRY_ITEM = 100079  # eumIBathymetry
METRE_UNIT = 1000  # eumUmeter
LAND_CODE = 1
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
        form (give ``crs_wkt``), or a land boundary between two open boundaries
        is a single edge (node codes cannot mark it as land).
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
    if not isinstance(mesh, Mesh):
        raise TypeError(f"mesh is a {type(mesh).__name__}, expected a Mesh")
    name = os.fspath(path)
    z = node_depth(mesh, name, positive=positive, stacklevel=3)
    projection = _projection(mesh, name, crs_wkt)
    kinds = require_kinds(mesh, name)
    open_ids = sorted(pid for pid, kind in kinds.items() if kind == "open")
    codes_of = {pid: LAND_CODE + 1 + k for k, pid in enumerate(open_ids)}
    codes = _node_codes(mesh, name, codes_of)
    n, m = len(mesh.points), len(mesh.triangles)
    with atomic_write(path, overwrite=overwrite) as tmp, open(tmp, "wb") as handle:
        handle.write(f"{BATHYMETRY_ITEM} {METRE_UNIT} {n} {projection}\n".encode())
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
        handle.write(f"{m} 3 21\n".encode())
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
        return "NON-UTM"
    if mesh.crs.equals(CRS.from_epsg(4326), ignore_axis_order=True):
        return "LONG/LAT"
    wkt = mesh.crs.to_wkt(version="WKT1_ESRI")
    if not wkt:
        raise FormatError(
            f"{name}: the mesh CRS {mesh.crs.name!r} has no ESRI WKT 1 form for the "
            "MIKE header; give the projection string as crs_wkt"
        )
    return wkt


def _node_codes(mesh: Mesh, name: str, codes_of: dict[int, int]) -> NDArray[np.int64]:
    """Return the MIKE code of each node (see :func:`write_mike_mesh`, Notes)."""
    try:
        rings = boundary_rings(mesh)
    except FormatError as exc:
        raise FormatError(f"{name}: {exc}") from exc
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
