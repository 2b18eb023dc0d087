"""VTK unstructured grid (``.vtu``) mesh files, for ParaView, through meshio.

meshio's VTU reader and writer are called directly (``meshio.read`` and
``meshio.write`` print). A file holds the points (z = 0), a block of triangles
and a block of boundary lines, with cell data ``physical`` and ``boundary_id``
and every node value as point data. VTU has no place for the CRS, nor for the
names and kinds of the boundary ids.
"""

from __future__ import annotations

import logging
import os
from typing import Any

import numpy as np

from coastmesh.io._atomic import atomic_write
from coastmesh.io._inputs import check_input, resolve_crs
from coastmesh.io.meshes._meshio import (
    flat_points,
    read_with_meshio,
    split_cells,
    surface_of,
)
from coastmesh.io.meshes._model import check_mesh, index_dtype, point_values
from coastmesh.io.meshes._reading import mesh_from_file
from coastmesh.types import Mesh

__all__ = ["read_vtu", "write_vtu"]

logger = logging.getLogger(__name__)


def write_vtu(
    path: str | os.PathLike[str], mesh: Mesh, *, overwrite: bool = False
) -> None:
    """Write a mesh as a VTK unstructured grid (``.vtu``) through meshio.

    Parameters
    ----------
    path : str or path-like
        The ``.vtu`` file.
    mesh : Mesh
        The mesh; it is not changed.
    overwrite : bool, default False
        Whether an existing file may be replaced.

    Raises
    ------
    FormatError
        If a ``point_data`` entry is not numbers of shape (N,) or (N, k).
    OutputExistsError
        If ``path`` exists and ``overwrite`` is false.

    Notes
    -----
    Points get z = 0. Two cell blocks: the triangles, then the boundary edges as
    lines (left out if there are none). Cell data ``physical`` is each
    triangle's region id (``mesh.regions``: ``mesh.surface_id`` but in farms
    and turbine footprints) and the boundary id on the lines;
    ``boundary_id`` is 0 on the triangles and the boundary id on the lines. Every
    ``mesh.point_data`` entry is point data (``depth`` positive down, as stored).
    The file is binary, zlib-compressed.

    A global lon/lat mesh is written as it is: ParaView draws the triangles that
    cross the antimeridian across the whole plane (read back, they are the
    same triangles).

    Examples
    --------
    >>> import tempfile, pathlib, meshio.vtu
    >>> m = Mesh([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]], [[0, 1], [1, 2], [2, 0]],
    ...          [1, 1, 2], 7, None, {"depth": [1.0, 2.0, 3.0]})
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "tri.vtu"
    >>> write_vtu(path, m)
    >>> back = meshio.vtu.read(path)
    >>> [c.type for c in back.cells], back.cell_data["physical"][1].tolist()
    (['triangle', 'line'], [1, 1, 2])
    """
    import meshio
    import meshio.vtu

    check_mesh(mesh)
    name = os.fspath(path)
    n = len(mesh.points)
    point_data = {
        key: point_values(key, values, n, name)
        for key, values in mesh.point_data.items()
    }
    m = len(mesh.triangles)
    cells = [("triangle", mesh.triangles.astype(index_dtype(n)))]
    physical = [mesh.regions.astype(np.int32)]
    boundary = [np.zeros(m, dtype=np.int32)]
    if len(mesh.boundary_edges):
        cells.append(("line", mesh.boundary_edges.astype(index_dtype(n))))
        physical.append(mesh.boundary_ids.astype(np.int32))
        boundary.append(mesh.boundary_ids.astype(np.int32))
    points = np.zeros((n, 3), dtype=np.float64)
    points[:, :2] = mesh.points
    out = meshio.Mesh(
        points,
        cells,
        point_data=point_data,
        cell_data={"physical": physical, "boundary_id": boundary},
    )
    with atomic_write(path, overwrite=overwrite) as tmp:
        meshio.vtu.write(tmp, out, binary=True, compression="zlib")
    logger.debug(
        "wrote %s: VTU, %d nodes, %d triangles, %d boundary edges",
        name,
        n,
        m,
        len(mesh.boundary_edges),
    )


def read_vtu(path: str | os.PathLike[str], *, crs: Any = None) -> Mesh:
    """Read a 2D triangle mesh with boundary lines from a ``.vtu`` file.

    Parameters
    ----------
    path : str or path-like
        The ``.vtu`` file, as :func:`write_vtu` writes it (or any VTU of
        triangles and lines in a plane z = 0).
    crs : pyproj.CRS or CRS-like, optional
        The CRS of the coordinates, which VTU does not store.

    Returns
    -------
    Mesh
        Points and triangles in file order; the line cells as boundary edges,
        with their ``boundary_id`` (else ``physical``, else 1) cell data as ids;
        each triangle's ``physical`` cell data (else 1) as ``regions``, the id
        of the most triangles as ``surface_id``; every
        numeric point data array as point data (``depth`` as stored: metres,
        positive down). No names or kinds.

    Raises
    ------
    InputDataError
        If ``path`` does not exist.
    FormatError
        If meshio cannot read it, a node has z != 0, there are no triangles, or
        the triangles carry several ``physical`` ids.
    ConfigError
        If ``crs`` is not a CRS.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> m = Mesh([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]], [[0, 1], [1, 2], [2, 0]],
    ...          [1, 1, 2], 7, None, {"depth": [1.0, 2.0, 3.0]})
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "tri.vtu"
    >>> write_vtu(path, m)
    >>> back = read_vtu(path, crs="EPSG:32630")
    >>> back.boundary_ids.tolist(), back.surface_id, back.crs.to_epsg()
    ([1, 1, 2], 7, 32630)
    """
    import meshio.vtu

    name = check_input(path)
    data = read_with_meshio(meshio.vtu.read, name, "VTU")
    triangles, edges, ids, regions = split_cells(
        data, name, lambda k: _cell_values(data, k)
    )
    return mesh_from_file(
        name,
        flat_points(data, name),
        triangles,
        edges,
        ids,
        surface_of(regions),
        resolve_crs(None, crs, name),
        {
            key: values
            for key, values in data.point_data.items()
            if np.asarray(values).dtype.kind in "iuf"
        },
        regions=regions,
    )


def _cell_values(data: Any, block: int) -> tuple[Any, Any]:
    """Return the physical and boundary ids of a block's cells; 1 if not stored."""
    size = len(data.cells[block].data)
    found = [
        np.asarray(data.cell_data[key][block], dtype=np.int64).reshape(-1)
        if key in data.cell_data
        else None
        for key in ("physical", "boundary_id")
    ]
    physical = found[0] if found[0] is not None else np.ones(size, np.int64)
    return physical, found[1] if found[1] is not None else physical
