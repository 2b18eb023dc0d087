"""A mesh as a GeoPackage, for a look in a GIS, and read back.

Three layers, in the mesh CRS:

==============  ==================  =================================================
layer           geometry            fields
==============  ==================  =================================================
``nodes``       Point               ``id`` (row in ``mesh.points``), one float field
                                    per 1-D numeric ``point_data`` entry (``depth``)
``triangles``   Polygon (closed)    ``id`` (row in ``mesh.triangles``)
``boundaries``  2-point LineString  ``physical_id``, ``name``, ``kind``: one feature
                                    per boundary edge, in order
==============  ==================  =================================================

The layers are written into one staged file (:func:`coastmesh.io.vectors.domain_gpkg.
write_layers`); reading matches the corners of triangles and boundary lines to the
nodes by their exact coordinates, which the GeoPackage stores as float64.

A global mesh (:func:`coastmesh.io.meshes.sphere.on_sphere`) has MultiPolygon triangles
and MultiLineString boundary edges instead, those that cross the antimeridian cut
in two as RFC 7946 (section 3.1.9) asks (:mod:`coastmesh.io.meshes._dateline`).
"""

from __future__ import annotations

import logging
import os
from collections.abc import Mapping
from typing import Any

import numpy as np
import shapely
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.errors import InputDataError
from coastmesh.io._inputs import check_input, resolve_crs
from coastmesh.io.meshes._dateline import (
    cut_edges,
    cut_triangles,
    edge_nodes,
    triangle_nodes,
)
from coastmesh.io.meshes._model import check_mesh
from coastmesh.io.meshes._reading import mesh_from_file
from coastmesh.io.meshes.sphere import on_sphere
from coastmesh.types import Features, Mesh

__all__ = ["MESH_LAYERS", "read_mesh_gpkg", "write_mesh_gpkg"]

logger = logging.getLogger(__name__)

MESH_LAYERS = ("nodes", "triangles", "boundaries")


def write_mesh_gpkg(
    path: str | os.PathLike[str],
    mesh: Mesh,
    *,
    overwrite: bool = False,
    metadata: Mapping[str, str] | None = None,
) -> None:
    """Write a mesh as a GeoPackage of nodes, triangles and boundary edges.

    Parameters
    ----------
    path : str or path-like
        The ``.gpkg`` file.
    mesh : Mesh
        The mesh; it is not changed. Point data that is not one number per node
        is left out.
    overwrite : bool, default False
        Whether an existing file may be replaced.
    metadata : mapping of str to str, optional
        Key/value notes stored as GeoPackage dataset metadata.

    Raises
    ------
    FormatError
        If GDAL cannot write a layer.
    OutputExistsError
        If ``path`` exists and ``overwrite`` is false.

    Notes
    -----
    A global mesh (:func:`~coastmesh.io.meshes.sphere.on_sphere`: lon/lat, with
    triangles across the antimeridian) keeps its nodes in [-180, 180); each
    triangle is a MultiPolygon and each boundary edge a MultiLineString, one
    part, or two for those that cross the antimeridian, cut at longitude 180
    (RFC 7946, section 3.1.9, as GDAL's ``-wrapdateline`` does). A triangle
    around a pole is the cap between its edges and the pole. The cut points
    are not nodes; :func:`read_mesh_gpkg` rebuilds each triangle from the
    corners that are. Each triangle has its ``region`` (``mesh.regions``: a
    farm's or a turbine footprint's id, else the domain's) and ``region_name``
    (``domain`` for the domain's).

    Examples
    --------
    >>> import tempfile, pathlib, pyogrio
    >>> m = Mesh([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]], [[0, 1], [1, 2], [2, 0]],
    ...          [1, 1, 2], 1, "EPSG:32630", {"depth": [1.0, 2.0, 3.0]})
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "tri.gpkg"
    >>> write_mesh_gpkg(path, m)
    >>> pyogrio.list_layers(path)[:, 0].tolist()
    ['nodes', 'triangles', 'boundaries']
    """
    from coastmesh.io.vectors.domain_gpkg import write_layers

    check_mesh(mesh)
    write_layers(path, _mesh_layers(mesh), overwrite=overwrite, metadata=metadata)


def read_mesh_gpkg(path: str | os.PathLike[str], *, crs: Any = None) -> Mesh:
    """Read a mesh from a GeoPackage written by :func:`write_mesh_gpkg`.

    Parameters
    ----------
    path : str or path-like
        The ``.gpkg`` file, with layers ``nodes``, ``triangles`` and
        ``boundaries``.
    crs : pyproj.CRS or CRS-like, optional
        The CRS of the coordinates, if the layers declare none; if they do, it
        must agree.

    Returns
    -------
    Mesh
        Nodes, triangles and boundary edges in the order of their ``id`` fields
        (boundary edges in feature order, as drawn); boundary ids, names and
        kinds from ``physical_id``, ``name`` and ``kind``; every numeric field of
        ``nodes`` but ``id`` as point data (``depth`` in metres, positive down);
        the CRS of the ``triangles`` layer; the triangles' ``region`` field as
        ``regions`` (the one named ``domain`` in ``region_name`` as
        ``surface_id``, the others' names as ``region_names``; without the
        field, ``surface_id`` 1).
        Triangles and edges cut at the antimeridian (multi-part features) are
        rebuilt from the corners that are nodes (longitude 180 is the node at
        -180, latitude +-90 the node at that pole), each triangle turned to
        run counter-clockwise on the sphere.

    Raises
    ------
    InputDataError
        If the file or a layer is missing, two nodes share coordinates, a triangle
        or boundary corner is not a node, or a field is missing.
    FormatError
        If GDAL cannot read the file.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> m = Mesh([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]], [[0, 1], [1, 2], [2, 0]],
    ...          [1, 1, 2], 1, "EPSG:32630", {"depth": [1.0, 2.0, 3.0]},
    ...          {2: "sea"}, {1: "shoreline", 2: "open"})
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "tri.gpkg"
    >>> write_mesh_gpkg(path, m)
    >>> back = read_mesh_gpkg(path)
    >>> back.triangles.tolist(), back.boundary_ids.tolist(), back.boundary_names
    ([[0, 1, 2]], [1, 1, 2], {2: 'sea'})
    >>> back.point_data["depth"].tolist(), back.crs.to_epsg()
    ([1.0, 2.0, 3.0], 32630)
    """
    from coastmesh.io.vectors.vector import pick_layer

    name = check_input(path)
    for layer in MESH_LAYERS:
        pick_layer(name, layer)
    meta, points, node_fields = _read_layer(name, "nodes")
    nodes = _by_id(shapely.get_coordinates(points), node_fields, name, "nodes")
    point_data = {
        key: _by_id(values, node_fields, name, "nodes").astype(np.float64)
        for key, values in node_fields.items()
        if key != "id" and values.dtype.kind in "iuf"
    }
    meta, polygons, fields = _read_layer(name, "triangles")
    stored = CRS.from_user_input(meta["crs"]) if meta.get("crs") else None
    if _plain(polygons, shapely.Polygon):
        corners = _corners(polygons, 4, name, "triangles")[:, :3]
        found = _node_index(nodes, corners, name, "triangles")
    else:
        _node_index(nodes, np.empty((0, 1, 2)), name, "triangles")  # distinct nodes
        geographic = resolve_crs(stored, crs, name)
        sphere = geographic is not None and bool(geographic.is_geographic)
        found = triangle_nodes(nodes, polygons, name, "triangles", sphere=sphere)
    triangles = _by_id(found, fields, name)
    regions, surface, region_names = None, 1, {}
    if "region" in fields:
        regions = _by_id(fields["region"].astype(np.int64), fields, name)
        labels = fields.get("region_name", np.full(len(regions), None, dtype=object))
        labels = _by_id(np.asarray(labels, dtype=object), fields, name)
        named = {int(i): str(v) for i, v in zip(regions, labels, strict=True) if v}
        domain = next((i for i, v in named.items() if v == "domain"), None)
        if domain is None:
            ids, counts = np.unique(regions, return_counts=True)
            domain = int(ids[np.argmax(counts)])
        surface = domain
        region_names = {i: v for i, v in named.items() if i != surface}
    _, lines, fields = _read_layer(name, "boundaries")
    if _plain(lines, shapely.LineString):
        corners = _corners(lines, 2, name, "boundaries")
        ends = _node_index(nodes, corners, name, "boundaries")
    else:
        ends = edge_nodes(nodes, lines, name, "boundaries")
    if "physical_id" not in fields:
        raise InputDataError("no field 'physical_id'", path=name, layer="boundaries")
    ids = fields["physical_id"].astype(np.int64)
    named_ids: dict[str, dict[int, str]] = {}
    for key in ("name", "kind"):
        found = fields.get(key, np.full(len(ids), None, dtype=object))
        named_ids[key] = {int(i): str(v) for i, v in zip(ids, found, strict=True) if v}
    return mesh_from_file(
        name,
        nodes,
        triangles,
        ends,
        ids,
        surface,
        resolve_crs(stored, crs, name),
        point_data,
        named_ids["name"],
        named_ids["kind"],
        regions,
        region_names,
    )


def _mesh_layers(mesh: Mesh) -> dict[str, Features]:
    """Build the GeoPackage layers of a mesh: nodes, triangles, boundary edges."""
    triangles = mesh.triangles
    edges = mesh.boundary_edges
    if on_sphere(mesh):
        polygons = cut_triangles(mesh.points, triangles)
        lines = cut_edges(mesh.points, edges)
    else:
        corners = mesh.points[triangles]  # (M, 3, 2)
        polygons = (
            shapely.polygons(np.concatenate([corners, corners[:, :1]], axis=1))
            if len(triangles)
            else np.empty(0, dtype=object)
        )
        lines = (
            shapely.linestrings(mesh.points[edges])
            if len(edges)
            else np.empty(0, dtype=object)
        )
    labels = {
        key: np.array([table.get(int(i), "") for i in mesh.boundary_ids], dtype=object)
        for key, table in (("name", mesh.boundary_names), ("kind", mesh.boundary_kinds))
    }
    node_fields: dict[str, Any] = {"id": np.arange(len(mesh.points), dtype=np.int64)}
    for key, raw in mesh.point_data.items():
        values = np.asarray(raw)
        if values.ndim == 1 and np.issubdtype(values.dtype, np.number):
            node_fields[key] = values.astype(np.float64)
    return {
        "nodes": _layer(mesh, "nodes", shapely.points(mesh.points), node_fields),
        "triangles": _layer(
            mesh,
            "triangles",
            polygons,
            {
                "id": np.arange(len(triangles)),
                "region": mesh.regions,
                "region_name": np.array(
                    [_region_name(mesh, int(i)) for i in mesh.regions], dtype=object
                ),
            },
        ),
        "boundaries": _layer(
            mesh, "boundaries", lines, {"physical_id": mesh.boundary_ids, **labels}
        ),
    }


def _region_name(mesh: Mesh, pid: int) -> str:
    """``domain`` for the domain's surface id, else the region's name (or "")."""
    return "domain" if pid == mesh.surface_id else mesh.region_names.get(pid, "")


def _layer(mesh: Mesh, name: str, geometry: Any, fields: dict[str, Any]) -> Features:
    fids = np.arange(len(geometry), dtype=np.int64)
    return Features(geometry, mesh.crs, fields, fids, "<memory>", name)


def _read_layer(
    path: str, layer: str
) -> tuple[dict[str, Any], NDArray[np.object_], dict[str, NDArray[Any]]]:
    """(meta, geometries, fields by name) of one layer."""
    import pyogrio.raw

    with np.errstate(invalid="ignore"):
        meta, _, wkb, columns = pyogrio.raw.read(path, layer=layer)
    geometry = shapely.from_wkb(wkb) if wkb is not None else np.empty(0, dtype=object)
    return meta, geometry, dict(zip(meta["fields"], columns, strict=True))


def _by_id(
    values: NDArray[Any],
    fields: dict[str, NDArray[Any]],
    path: str,
    layer: str = "triangles",
) -> NDArray[Any]:
    """Put the rows of ``values`` in the order of the layer's ``id`` field."""
    if "id" not in fields:
        raise InputDataError("no field 'id'", path=path, layer=layer)
    ids = fields["id"].astype(np.int64)
    order = np.argsort(ids, kind="stable")
    if not np.array_equal(ids[order], np.arange(len(ids))):
        raise InputDataError(
            f"the ids are not 0..{len(ids) - 1}, each once", path=path, layer=layer
        )
    return values[order]


def _plain(geometry: NDArray[np.object_], kind: type) -> bool:
    """Whether every feature is a single ``kind`` (not cut at the antimeridian)."""
    return bool((shapely.get_type_id(geometry) == shapely.get_type_id(kind())).all())


def _corners(
    geometry: NDArray[np.object_], count: int, path: str, layer: str
) -> NDArray[np.float64]:
    """Return the (K, count, 2) vertices of K closed polygons or K lines."""
    if len(geometry) == 0:
        return np.empty((0, count, 2))
    parts = shapely.get_exterior_ring(geometry) if count == 4 else geometry
    sizes = shapely.get_num_coordinates(parts)
    if (sizes != count).any():
        k = int(np.flatnonzero(sizes != count)[0])
        raise InputDataError(
            f"has {sizes[k]} vertices, expected {count}",
            path=path,
            layer=layer,
            feature=k,
        )
    return shapely.get_coordinates(parts).reshape(len(geometry), count, 2)


def _node_index(
    nodes: NDArray[np.float64], corners: NDArray[np.float64], path: str, layer: str
) -> NDArray[np.int64]:
    """Return the node at the exact coordinates of each corner."""
    keys = nodes[:, 0] + 1j * nodes[:, 1]  # sorts by x, then y
    order = np.argsort(keys)
    ordered = keys[order]
    if len(ordered) > 1 and (ordered[1:] == ordered[:-1]).any():
        raise InputDataError(
            "two nodes have the same coordinates", path=path, layer="nodes"
        )
    wanted = (corners[..., 0] + 1j * corners[..., 1]).ravel()
    where = np.minimum(np.searchsorted(ordered, wanted), max(len(ordered) - 1, 0))
    found = ordered[where] == wanted if len(ordered) else np.zeros(len(wanted), bool)
    if not found.all():
        k = int(np.flatnonzero(~found)[0])
        raise InputDataError(
            f"vertex {wanted[k].real!r}, {wanted[k].imag!r} is not a node",
            path=path,
            layer=layer,
            feature=k // corners.shape[1],
        )
    return order[where].reshape(corners.shape[:-1])
