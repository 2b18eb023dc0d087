"""UGRID netCDF and VTK unstructured grid (VTU) mesh files.

UGRID-1.0 (https://ugrid-conventions.github.io/ugrid-conventions/) on CF: one
2D mesh topology variable ``mesh2d``, written with xarray. Its edges
(``edge_node_connectivity``) are *all* the edges of the triangles, as UGRID
defines them and as xugrid checks (``xugrid/ugrid/connectivity.py``,
``edge_connectivity``: a partial edge list raises "Invalid
edge_node_connectivity"); the boundary edges are those with ``boundary_id > 0``.
The CRS is a CF grid mapping variable (:meth:`pyproj.CRS.to_cf`, with
``crs_wkt``) named ``mesh2d_crs`` and referenced by every variable on the mesh,
coordinates included, as xugrid writes it (``UgridBase.write_grid_mapping``:
QGIS-MDAL reads the grid mapping from the coordinates).

VTU files are written with meshio's VTU writer, called directly because
``meshio.write`` prints.
"""

from __future__ import annotations

import logging
import os
from typing import Any

import numpy as np
from numpy.typing import NDArray

from coastmesh.errors import FormatError
from coastmesh.io._atomic import atomic_write
from coastmesh.meshing.topology import unique_edges
from coastmesh.types import Mesh

__all__ = ["write_ugrid", "write_vtu"]

logger = logging.getLogger(__name__)

TOPOLOGY = "mesh2d"
_NODE = f"{TOPOLOGY}_nNodes"
_EDGE = f"{TOPOLOGY}_nEdges"
_FACE = f"{TOPOLOGY}_nFaces"
_MAX_FACE_NODES = f"{TOPOLOGY}_nMax_face_nodes"
_TWO = "Two"
_X = f"{TOPOLOGY}_node_x"
_Y = f"{TOPOLOGY}_node_y"
_FACE_NODES = f"{TOPOLOGY}_face_nodes"
_EDGE_NODES = f"{TOPOLOGY}_edge_nodes"
_CRS = f"{TOPOLOGY}_crs"
_RESERVED = frozenset({TOPOLOGY, _X, _Y, _FACE_NODES, _EDGE_NODES, _CRS, "boundary_id"})


def write_ugrid(
    path: str | os.PathLike[str], mesh: Mesh, *, overwrite: bool = False
) -> None:
    """Write a mesh as a UGRID-1.0 netCDF file.

    Parameters
    ----------
    path : str or path-like
        The ``.nc`` file (netCDF-4).
    mesh : Mesh
        The mesh; it is not changed.
    overwrite : bool, default False
        Whether an existing file may be replaced.

    Raises
    ------
    FormatError
        If a boundary edge is not an edge of a triangle, a boundary id is not
        > 0, or a ``point_data`` entry is not numbers of shape (N,) or (N, k), or
        its name is taken by the mesh variables.
    OutputExistsError
        If ``path`` exists and ``overwrite`` is false.

    Notes
    -----
    Variables, with dimensions ``mesh2d_nNodes``, ``mesh2d_nEdges``,
    ``mesh2d_nFaces``:

    - ``mesh2d``: the topology (``cf_role = "mesh_topology"``,
      ``topology_dimension = 2``);
    - ``mesh2d_node_x``, ``mesh2d_node_y``: ``mesh.points``, with standard names
      ``longitude``/``latitude`` for a geographic CRS and
      ``projection_x_coordinate``/``projection_y_coordinate`` otherwise (none if
      the CRS is unknown);
    - ``mesh2d_face_nodes`` (faces, 3): ``mesh.triangles``, counter-clockwise;
      ``mesh2d_edge_nodes`` (edges, 2): every edge, lower node first, sorted;
      both with ``start_index = 0``;
    - ``boundary_id`` on the edges: the boundary id of boundary edges, 0 for
      interior edges; ``flag_values``/``flag_meanings`` name them, and
      ``open_boundary_ids``/``shoreline_boundary_ids`` list the kinds;
    - ``mesh2d_crs``: the CRS (only if ``mesh.crs`` is known);
    - one node variable per ``mesh.point_data`` entry; ``depth`` in metres with
      ``positive = "down"``.

    Examples
    --------
    >>> import tempfile, pathlib, xarray as xr
    >>> m = Mesh([[0, 0], [1, 0], [1, 1], [0, 1]], [[0, 1, 2], [0, 2, 3]],
    ...          [[0, 1], [1, 2], [2, 3], [3, 0]], [2, 1, 1, 1], 1, "EPSG:32630",
    ...          {"depth": [5.0, 6.0, 7.0, 8.0]})
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "square.nc"
    >>> write_ugrid(path, m)
    >>> with xr.open_dataset(path) as ds:
    ...     ds["boundary_id"].values.tolist(), ds["depth"].attrs["positive"]
    ([2, 0, 1, 1, 1], 'down')
    """
    name = os.fspath(path)
    dataset = _ugrid_dataset(mesh, name)
    encoding = {
        var: {"_FillValue": None}
        for var in dataset.variables
        if var in _RESERVED or dataset[var].dtype.kind != "f"
    }
    with atomic_write(path, overwrite=overwrite) as tmp:
        dataset.to_netcdf(tmp, engine="netcdf4", format="NETCDF4", encoding=encoding)
    logger.debug(
        "wrote %s: UGRID, %d nodes, %d triangles, %d edges",
        name,
        dataset.sizes[_NODE],
        dataset.sizes[_FACE],
        dataset.sizes[_EDGE],
    )


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
    lines (left out if there are none). Cell data ``physical`` is
    ``mesh.surface_id`` on the triangles and the boundary id on the lines;
    ``boundary_id`` is 0 on the triangles and the boundary id on the lines. Every
    ``mesh.point_data`` entry is point data (``depth`` positive down, as stored).
    The file is binary, zlib-compressed; VTU has no place for the CRS.

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

    name = os.fspath(path)
    n = len(mesh.points)
    point_data = {
        key: _point_values(key, values, n, name)
        for key, values in mesh.point_data.items()
    }
    m = len(mesh.triangles)
    cells = [("triangle", mesh.triangles.astype(_index_dtype(n)))]
    physical = [np.full(m, mesh.surface_id, dtype=np.int32)]
    boundary = [np.zeros(m, dtype=np.int32)]
    if len(mesh.boundary_edges):
        cells.append(("line", mesh.boundary_edges.astype(_index_dtype(n))))
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


def _ugrid_dataset(mesh: Mesh, name: str) -> Any:
    """Build the UGRID xarray Dataset of a mesh."""
    import xarray as xr

    from coastmesh import __version__

    n = len(mesh.points)
    index = _index_dtype(n)
    edges, boundary_id = _edges(mesh, name)
    grid_mapping = {} if mesh.crs is None else {"grid_mapping": _CRS}
    x_attrs, y_attrs = _coordinate_attrs(mesh)
    coords = {
        _X: (_NODE, mesh.points[:, 0].copy(), {**x_attrs, **grid_mapping}),
        _Y: (_NODE, mesh.points[:, 1].copy(), {**y_attrs, **grid_mapping}),
    }
    data_vars: dict[str, Any] = {
        TOPOLOGY: (
            (),
            np.int32(0),
            {
                "cf_role": "mesh_topology",
                "long_name": "Topology data of 2D mesh",
                "topology_dimension": np.int32(2),
                "node_coordinates": f"{_X} {_Y}",
                "face_node_connectivity": _FACE_NODES,
                "edge_node_connectivity": _EDGE_NODES,
                "node_dimension": _NODE,
                "edge_dimension": _EDGE,
                "face_dimension": _FACE,
            },
        ),
        _FACE_NODES: (
            (_FACE, _MAX_FACE_NODES),
            mesh.triangles.astype(index),
            {
                "cf_role": "face_node_connectivity",
                "long_name": "Vertex nodes of mesh faces (counterclockwise)",
                "start_index": np.int32(0),
                **grid_mapping,
            },
        ),
        _EDGE_NODES: (
            (_EDGE, _TWO),
            edges.astype(index),
            {
                "cf_role": "edge_node_connectivity",
                "long_name": "Start and end nodes of mesh edges",
                "start_index": np.int32(0),
                **grid_mapping,
            },
        ),
        "boundary_id": (
            _EDGE,
            boundary_id,
            {
                "long_name": "boundary id of the edge, 0 for interior edges",
                "mesh": TOPOLOGY,
                "location": "edge",
                **_boundary_flags(mesh),
                **grid_mapping,
            },
        ),
    }
    for key, values in mesh.point_data.items():
        if key in _RESERVED or key in coords:
            raise FormatError(
                f"{name}: point_data[{key!r}] has the name of a mesh variable; "
                f"rename it (taken: {', '.join(sorted(_RESERVED))})"
            )
        array = _point_values(key, values, n, name)
        dims = (_NODE,) if array.ndim == 1 else (_NODE, f"{key}_component")
        attrs = {"mesh": TOPOLOGY, "location": "node", **grid_mapping}
        if key == "depth":
            attrs |= {
                "long_name": "bed depth below the vertical datum",
                "units": "m",
                "positive": "down",
            }
        data_vars[key] = (dims, array, attrs)
    if mesh.crs is not None:
        data_vars[_CRS] = ((), np.int32(0), _crs_attrs(mesh.crs))
    return xr.Dataset(
        data_vars,
        coords=coords,
        attrs={
            "Conventions": "CF-1.8 UGRID-1.0",
            "title": "coastmesh mesh",
            "source": f"coastmesh {__version__}",
        },
    )


def _edges(mesh: Mesh, name: str) -> tuple[NDArray[np.int64], NDArray[np.int32]]:
    """Every edge of the triangles (sorted, lower node first) and its boundary id."""
    n = max(len(mesh.points), 1)
    edges, _ = unique_edges(mesh.triangles, n)
    keys = edges[:, 0] * n + edges[:, 1]  # increasing, as unique_edges sorts them
    boundary_id = np.zeros(len(keys), dtype=np.int32)
    tagged = mesh.boundary_edges
    if len(tagged):
        wanted = tagged.min(axis=1) * n + tagged.max(axis=1)
        where = np.searchsorted(keys, wanted)
        found = where < len(keys)
        found[found] = keys[where[found]] == wanted[found]
        if not found.all():
            row = int(np.flatnonzero(~found)[0])
            raise FormatError(
                f"{name}: boundary edge {row} (nodes {tagged[row].tolist()}) is not "
                "an edge of any triangle"
            )
        if (mesh.boundary_ids <= 0).any():
            bad = int(mesh.boundary_ids[mesh.boundary_ids <= 0][0])
            raise FormatError(
                f"{name}: boundary id {bad} is not > 0; UGRID boundary_id uses 0 "
                "for interior edges"
            )
        boundary_id[where] = mesh.boundary_ids
    return edges, boundary_id


def _boundary_flags(mesh: Mesh) -> dict[str, Any]:
    """CF flag attributes naming the boundary ids, and their kinds."""
    ids = np.unique(mesh.boundary_ids).astype(np.int32)
    meanings = ["interior"] + [
        "_".join(mesh.boundary_names.get(int(i), f"boundary_{int(i)}").split())
        or f"boundary_{int(i)}"
        for i in ids
    ]
    attrs: dict[str, Any] = {
        "flag_values": np.concatenate([[0], ids]).astype(np.int32),
        "flag_meanings": " ".join(meanings),
    }
    for kind in ("open", "shoreline"):
        attrs[f"{kind}_boundary_ids"] = np.array(
            [i for i in ids if mesh.boundary_kinds.get(int(i)) == kind],
            dtype=np.int32,
        )
    return attrs


def _coordinate_attrs(mesh: Mesh) -> tuple[dict[str, str], dict[str, str]]:
    """CF attributes of the node x and y coordinates."""
    x = {"long_name": "x-coordinate of mesh nodes", "mesh": TOPOLOGY}
    y = {"long_name": "y-coordinate of mesh nodes", "mesh": TOPOLOGY}
    crs = mesh.crs
    if crs is None:
        return x, y
    if crs.is_geographic:
        x |= {"standard_name": "longitude", "units": "degrees_east"}
        y |= {"standard_name": "latitude", "units": "degrees_north"}
        return x, y
    unit = crs.axis_info[0].unit_name if crs.axis_info else ""
    units = "m" if unit in ("metre", "meter") else unit
    x |= {"standard_name": "projection_x_coordinate"}
    y |= {"standard_name": "projection_y_coordinate"}
    if units:
        x["units"] = units
        y["units"] = units
    return x, y


def _crs_attrs(crs: Any) -> dict[str, Any]:
    """CF grid mapping attributes of a CRS, with the WKT for GDAL too."""
    attrs = dict(crs.to_cf())
    attrs["spatial_ref"] = attrs["crs_wkt"]
    epsg = crs.to_epsg()
    if epsg is not None:
        attrs["epsg"] = np.int32(epsg)
    return attrs


def _point_values(key: str, values: Any, n: int, name: str) -> NDArray:
    """Check one ``point_data`` entry: numbers of shape (N,) or (N, k)."""
    array = np.asarray(values)
    if array.dtype.kind == "b":
        array = array.astype(np.uint8)
    if array.dtype.kind not in "iuf" or array.ndim not in (1, 2) or len(array) != n:
        raise FormatError(
            f"{name}: point_data[{key!r}] has shape {array.shape} and dtype "
            f"{array.dtype}; expected numbers of shape ({n},) or ({n}, k)"
        )
    return array


def _index_dtype(n: int) -> type[np.integer]:
    """int32 node indices while they fit, int64 beyond."""
    return np.int32 if n <= np.iinfo(np.int32).max else np.int64
