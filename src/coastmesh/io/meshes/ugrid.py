"""UGRID netCDF mesh files, written with xarray and read back.

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
"""

from __future__ import annotations

import logging
import os
from typing import Any

import numpy as np
from numpy.typing import NDArray

from coastmesh.errors import FormatError, InputDataError
from coastmesh.io._atomic import atomic_write
from coastmesh.io._cf import axis_attrs, crs_from_grid_mapping, grid_mapping_attrs
from coastmesh.io._inputs import check_input, resolve_crs
from coastmesh.io.meshes._model import check_mesh, index_dtype, point_values
from coastmesh.io.meshes._reading import mesh_from_file
from coastmesh.types import Mesh
from coastmesh.types.topology import unique_edges

__all__ = ["read_ugrid", "write_ugrid"]

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
_RESERVED = frozenset(
    {TOPOLOGY, _X, _Y, _FACE_NODES, _EDGE_NODES, _CRS, "boundary_id", "region_id"}
)


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
    - ``region_id`` on the faces: each triangle's physical surface id
      (``mesh.regions``: a farm's or a turbine footprint's, else the domain's),
      with ``flag_values``/``flag_meanings`` naming them (``domain`` for the
      domain's, also given as ``domain_surface_id``);
    - ``mesh2d_crs``: the CRS (only if ``mesh.crs`` is known);
    - one node variable per ``mesh.point_data`` entry; ``depth`` in metres with
      ``positive = "down"``.

    A global mesh (:func:`~coastmesh.io.meshes.sphere.on_sphere`) is written the same
    way: nodes keep their longitude in [-180, 180), and a face that crosses the
    antimeridian lists its nodes counter-clockwise seen from outside the
    sphere, as UGRID asks of every face ("anticlockwise", viewed from above).
    Its edges are the shorter great-circle arcs between its nodes (the reading
    ugrid-conventions issue #40 settles on), which is how spherical readers such
    as UXarray rebuild it; planar readers draw it across the map.

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
    check_mesh(mesh)
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


def read_ugrid(path: str | os.PathLike[str], *, crs: Any = None) -> Mesh:
    """Read a 2D triangle mesh from a UGRID-1.0 netCDF file.

    Parameters
    ----------
    path : str or path-like
        The ``.nc`` file, with one 2D mesh topology (``cf_role =
        "mesh_topology"``, ``topology_dimension = 2``) of triangles, as
        :func:`write_ugrid` or xugrid write it.
    crs : pyproj.CRS or CRS-like, optional
        The CRS of the coordinates, if the file has no grid mapping; if it has
        one, it must agree.

    Returns
    -------
    Mesh
        Nodes and triangles in file order (``start_index`` taken off); the edges
        with ``boundary_id > 0`` as boundary edges, with those ids; names from
        the ``flag_values``/``flag_meanings`` of ``boundary_id`` (spaces were
        written as ``_``; ``boundary_<id>`` means no name); kinds from its
        ``open_boundary_ids``/``shoreline_boundary_ids``; the CRS from the grid
        mapping; every numeric variable on the nodes as point data (a ``depth``
        with ``positive = "up"`` is negated, so depths are positive down);
        ``region_id`` on the faces as ``regions`` (its ``domain_surface_id``,
        or the flag named ``domain``, as ``surface_id``, and the other flags'
        names as ``region_names``); without it, ``surface_id`` 1. A file
        without ``boundary_id`` gives the edges of one triangle (the
        boundary) id 1, with no name or kind.

    Raises
    ------
    InputDataError
        If the file is missing, has no or several 2D topologies, its faces are
        not all triangles, a variable the topology names is missing, or its grid
        mapping is not a CRS; the message names the variable.
    FormatError
        If the file is not netCDF.
    ConfigError
        If ``crs`` is not a CRS.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> m = Mesh([[0, 0], [1, 0], [1, 1], [0, 1]], [[0, 1, 2], [0, 2, 3]],
    ...          [[0, 1], [1, 2], [2, 3], [3, 0]], [2, 1, 1, 1], 1, "EPSG:32630",
    ...          {"depth": [5.0, 6.0, 7.0, 8.0]}, {2: "north sea"},
    ...          {1: "shoreline", 2: "open"})
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "square.nc"
    >>> write_ugrid(path, m)
    >>> back = read_ugrid(path)
    >>> back.boundary_edges.tolist(), back.boundary_ids.tolist()
    ([[0, 1], [0, 3], [1, 2], [2, 3]], [2, 1, 1, 1])
    >>> back.boundary_names, back.boundary_kinds, back.crs.to_epsg()
    ({2: 'north_sea'}, {2: 'open', 1: 'shoreline'}, 32630)
    """
    import xarray as xr

    name = check_input(path)
    try:
        dataset = xr.open_dataset(name, engine="netcdf4", decode_times=False)
    except (OSError, ValueError) as exc:
        raise FormatError(f"{name}: not a readable netCDF file ({exc})") from None
    with dataset:
        topology = _topology(dataset, name)
        attrs = dataset[topology].attrs
        x_name, y_name = _names(dataset, attrs, "node_coordinates", name, 2)
        points = np.column_stack(
            [np.asarray(dataset[v].values, np.float64) for v in (x_name, y_name)]
        )
        node_dim = dataset[x_name].dims[0]
        (faces,) = _names(dataset, attrs, "face_node_connectivity", name, 1)
        triangles = _connectivity(dataset[faces], 3, name)
        edges, ids, names, kinds = _boundary(dataset, attrs, triangles, name)
        stored = _grid_mapping(dataset, (x_name, topology), name)
        point_data = {}
        for key, var in dataset.data_vars.items():
            on_nodes = var.dims[:1] == (node_dim,) and key not in (x_name, y_name)
            if on_nodes and var.dtype.kind in "iuf":
                up = key == "depth" and var.attrs.get("positive") == "up"
                point_data[str(key)] = -var.values if up else var.values
        regions, surface, region_names = _regions(dataset, len(triangles), name)
    return mesh_from_file(
        name,
        points,
        triangles,
        edges,
        ids,
        surface,
        resolve_crs(stored, crs, name),
        point_data,
        names,
        kinds,
        regions,
        region_names,
    )


def _topology(dataset: Any, name: str) -> str:
    """Return the name of the file's one 2D mesh topology variable."""
    found = [
        str(key)
        for key, var in dataset.variables.items()
        if var.attrs.get("cf_role") == "mesh_topology"
        and int(var.attrs.get("topology_dimension", 0)) == 2
    ]
    if len(found) != 1:
        raise InputDataError(
            f"has {len(found)} 2D mesh topologies ({', '.join(found) or 'none'}); "
            "expected one variable with cf_role = 'mesh_topology' and "
            "topology_dimension = 2",
            path=name,
        )
    return found[0]


def _names(
    dataset: Any, attrs: dict[str, Any], key: str, name: str, count: int
) -> list[str]:
    """Return the variables an attribute of the topology names; each must exist."""
    names = str(attrs.get(key, "")).split()
    missing = [v for v in names if v not in dataset.variables]
    if len(names) != count or missing:
        raise InputDataError(
            f"the mesh topology's {key} is {attrs.get(key)!r}; expected {count} "
            "variable name(s) of the file",
            path=name,
        )
    return names


def _connectivity(var: Any, width: int, name: str) -> NDArray[np.int64]:
    """Return the 0-based node indices of a connectivity variable, ``width`` a row."""
    values = np.asarray(var.values, dtype=np.float64)
    if values.ndim != 2 or values.shape[1] != width or np.isnan(values).any():
        raise InputDataError(
            f"variable {var.name!r} has shape {values.shape} (or fill values); "
            f"expected {width} nodes per row: only triangle meshes are read",
            path=name,
        )
    return values.astype(np.int64) - int(var.attrs.get("start_index", 0))


def _boundary(
    dataset: Any, attrs: dict[str, Any], triangles: NDArray[np.int64], name: str
) -> tuple[NDArray[np.int64], NDArray[np.int64], dict[int, str], dict[int, str]]:
    """Return the boundary edges, their ids, and the names and kinds of the ids."""
    if "boundary_id" not in dataset.variables or "edge_node_connectivity" not in attrs:
        edges, count = unique_edges(triangles, int(triangles.max(initial=-1)) + 1)
        outer = edges[count == 1]
        return outer, np.ones(len(outer), np.int64), {}, {}
    (edge_var,) = _names(dataset, attrs, "edge_node_connectivity", name, 1)
    edges = _connectivity(dataset[edge_var], 2, name)
    var = dataset["boundary_id"]
    values = np.asarray(var.values).astype(np.int64)
    tagged = values > 0
    flags = np.atleast_1d(var.attrs.get("flag_values", [])).astype(np.int64)
    meanings = str(var.attrs.get("flag_meanings", "")).split()
    names = {
        int(i): text
        for i, text in zip(flags, meanings, strict=False)
        if i > 0 and text != f"boundary_{int(i)}"
    }
    kinds = {
        int(i): kind
        for kind in ("open", "shoreline")
        for i in np.atleast_1d(var.attrs.get(f"{kind}_boundary_ids", []))
    }
    return edges[tagged], values[tagged], names, kinds


def _grid_mapping(dataset: Any, holders: tuple[str, ...], name: str) -> Any:
    """Return the CRS of the grid mapping the coordinates (or topology) name."""
    for holder in holders:
        mapping = dataset[holder].attrs.get("grid_mapping")
        if mapping and mapping in dataset.variables:
            return crs_from_grid_mapping(dataset[mapping].attrs, name, mapping)
    return None


def _ugrid_dataset(mesh: Mesh, name: str) -> Any:
    """Build the UGRID xarray Dataset of a mesh."""
    import xarray as xr

    from coastmesh.version import __version__

    grid_mapping = {} if mesh.crs is None else {"grid_mapping": _CRS}
    coords = {
        var: (
            _NODE,
            mesh.points[:, k].copy(),
            {
                "long_name": f"{axis.lower()}-coordinate of mesh nodes",
                "mesh": TOPOLOGY,
                **axis_attrs(mesh.crs, axis),
                **grid_mapping,
            },
        )
        for k, (var, axis) in enumerate(((_X, "X"), (_Y, "Y")))
    }
    data_vars = _topology_vars(mesh, name, grid_mapping)
    data_vars |= _node_vars(mesh, name, set(coords), grid_mapping)
    if mesh.crs is not None:
        data_vars[_CRS] = ((), np.int32(0), grid_mapping_attrs(mesh.crs))
    return xr.Dataset(
        data_vars,
        coords=coords,
        attrs={
            "Conventions": "CF-1.8 UGRID-1.0",
            "title": "coastmesh mesh",
            "source": f"coastmesh {__version__}",
        },
    )


def _topology_vars(
    mesh: Mesh, name: str, grid_mapping: dict[str, str]
) -> dict[str, Any]:
    """Return the mesh topology, its faces and edges, and the edges' boundary ids."""
    index = index_dtype(len(mesh.points))
    edges, boundary_id = _edges(mesh, name)
    return {
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
        "region_id": (
            _FACE,
            mesh.regions.astype(np.int32),
            {
                "long_name": "physical surface id of the face (a farm's or a "
                "turbine footprint's, else the domain's)",
                "mesh": TOPOLOGY,
                "location": "face",
                **_region_flags(mesh),
                **grid_mapping,
            },
        ),
    }


def _node_vars(
    mesh: Mesh, name: str, coords: set[str], grid_mapping: dict[str, str]
) -> dict[str, Any]:
    """Return every node field of the mesh as a variable on the nodes."""
    n = len(mesh.points)
    data_vars: dict[str, Any] = {}
    for key, values in mesh.point_data.items():
        if key in _RESERVED or key in coords:
            raise FormatError(
                f"{name}: point_data[{key!r}] has the name of a mesh variable; "
                f"rename it (taken: {', '.join(sorted(_RESERVED))})"
            )
        array = point_values(key, values, n, name)
        dims = (_NODE,) if array.ndim == 1 else (_NODE, f"{key}_component")
        attrs = {"mesh": TOPOLOGY, "location": "node", **grid_mapping}
        if key == "depth":
            attrs |= {
                "long_name": "bed depth below the vertical datum",
                "units": "m",
                "positive": "down",
            }
        data_vars[key] = (dims, array, attrs)
    return data_vars


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


def _region_flags(mesh: Mesh) -> dict[str, Any]:
    """CF flag attributes naming the region ids; the domain's is ``domain``."""
    ids = mesh.region_ids
    meanings = [
        "domain"
        if i == mesh.surface_id
        else "_".join(mesh.region_names.get(i, f"region_{i}").split()) or f"region_{i}"
        for i in ids
    ]
    return {
        "flag_values": np.array(ids, dtype=np.int32),
        "flag_meanings": " ".join(meanings),
        "domain_surface_id": np.int32(mesh.surface_id),
    }


def _regions(dataset: Any, count: int, name: str) -> tuple[Any, int, dict[int, str]]:
    """Return the faces' region ids, the domain's id and the others' names.

    A file without ``region_id``: every face the domain's, id 1.
    """
    if "region_id" not in dataset.variables:
        return None, 1, {}
    var = dataset["region_id"]
    regions = np.asarray(var.values).astype(np.int64).reshape(-1)
    if regions.shape != (count,):
        raise FormatError(
            f"{name}: region_id has {regions.size} values for {count} faces"
        )
    values = np.atleast_1d(var.attrs.get("flag_values", [])).astype(int).tolist()
    meanings = str(var.attrs.get("flag_meanings", "")).split()
    named = dict(zip(values, meanings, strict=False))
    surface = int(var.attrs.get("domain_surface_id", 0)) or None
    if surface is None:
        surface = next((i for i, m in named.items() if m == "domain"), None)
    if surface is None or surface not in set(regions.tolist()):
        ids, counts = np.unique(regions, return_counts=True)
        surface = int(ids[np.argmax(counts)])
    names = {i: m for i, m in named.items() if i != surface}
    return regions, surface, names


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
