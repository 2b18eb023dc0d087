"""The patch put into the existing mesh: numbers, coordinates, depths.

Every kept node and element keeps its number, its coordinates (the input's
own floats, never reprojected) and its depth; the boundary lists are the
input's. The patch's nodes on the hole's rings are the kept nodes there (found
by their coordinates in the meshing CRS, which the mesher kept bit for bit);
its other nodes take the numbers of the nodes cut out, in order, then follow
the last; its elements likewise take the numbers of the elements cut out.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.case.config import CaseConfig
from coastmesh.case.patch.cut import Hole
from coastmesh.errors import MeshingError
from coastmesh.geometry.earth import reproject_points
from coastmesh.types import Mesh, MeshLine

__all__ = ["merge"]


def merge(
    mesh: Mesh,
    points: NDArray[np.float64],
    hole: Hole,
    new: Mesh,
    crs: CRS,
    config: CaseConfig,
    name: str,
    *,
    clockwise: bool = False,
) -> tuple[Mesh, NDArray[np.int64], NDArray[np.int64]]:
    """Return the patched mesh, its patch's element numbers, the nodes' new numbers.

    The third array gives each input node's number in the patched mesh (for a
    node cut out, the number its slot ends up with). The kept nodes keep their
    numbers unless the patch has fewer nodes than it cut out: then the gaps
    are closed, and the nodes after them move down.
    """
    number, fresh = _node_numbers(points, hole, new, name)
    n_old = len(mesh.points)
    slots = hole.inner_nodes
    count = len(fresh)
    # the nodes cut out give their numbers first; then the patch's others follow
    given = np.concatenate(
        [slots[:count], n_old + np.arange(max(count - len(slots), 0))]
    )
    number[fresh] = given
    keep = np.ones(n_old + max(count - len(slots), 0), dtype=bool)
    keep[slots[count:]] = False  # fewer new nodes than cut out: close the gaps
    shift = np.cumsum(~keep) if (~keep).any() else None
    xy = np.empty((len(keep), 2))
    xy[:n_old] = mesh.points
    assert mesh.crs is not None
    xy[given] = reproject_points(new.points[fresh], crs, mesh.crs)
    depth = _depths(mesh, points, hole, new, fresh, crs, config)
    point_data = _point_data(mesh, new, fresh, given, len(keep), depth)
    triangles, regions, new_elements = _elements(mesh, hole, new, number, clockwise)

    def renumber(a: NDArray[np.int64]) -> NDArray[np.int64]:
        return a if shift is None else a - shift[a]

    merged = Mesh(
        xy[keep],
        renumber(triangles),
        renumber(mesh.boundary_edges),
        mesh.boundary_ids,
        mesh.surface_id,
        mesh.crs,
        point_data={k: v[keep] for k, v in point_data.items()},
        boundary_names=dict(mesh.boundary_names),
        boundary_kinds=dict(mesh.boundary_kinds),
        regions=regions,
        region_names={**mesh.region_names, **new.region_names},
        lines=(*mesh.lines, *_lines(new, crs, mesh.crs)),
    )
    return merged, new_elements, renumber(np.arange(n_old))


def _node_numbers(
    points: NDArray[np.float64], hole: Hole, new: Mesh, name: str
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """Return the patch's nodes numbered as the mesh's on the rings, and the rest."""
    ring_nodes = np.unique(np.concatenate(hole.rings))
    at = {tuple(points[k]): int(k) for k in ring_nodes}
    number = np.full(len(new.points), -1, dtype=np.int64)
    for i, p in enumerate(map(tuple, new.points)):
        number[i] = at.get(p, -1)
    found = np.unique(number[number >= 0])
    if len(found) != len(ring_nodes) or (number >= 0).sum() != len(found):
        missing = np.setdiff1d(ring_nodes, found)
        raise MeshingError(
            f"{name}: the patch's mesh does not keep the seam's nodes as they are "
            f"({len(missing)} of {len(ring_nodes)} missing, the first node "
            f"{int(missing[0]) + 1 if len(missing) else '?'}); nothing was written"
        )
    return number, np.flatnonzero(number < 0)


def _elements(
    mesh: Mesh,
    hole: Hole,
    new: Mesh,
    number: NDArray[np.int64],
    clockwise: bool,
) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.int64]]:
    """Return the elements: the kept ones where they were, the patch's in the gaps.

    ``clockwise``: the input's elements turn clockwise; the patch's then do too.
    """
    tris = number[new.triangles]
    if clockwise:
        tris = tris[:, [0, 2, 1]]
    slots = np.flatnonzero(hole.removed)
    m_old = len(mesh.triangles)
    count = len(tris)
    at = np.concatenate([slots[:count], m_old + np.arange(max(count - len(slots), 0))])
    triangles = np.empty((m_old + max(count - len(slots), 0), 3), dtype=np.int64)
    triangles[:m_old] = mesh.triangles
    triangles[at] = tris
    regions = np.empty(len(triangles), dtype=np.int64)
    regions[:m_old] = mesh.regions
    new_regions = np.where(new.regions == new.surface_id, mesh.surface_id, new.regions)
    regions[at] = new_regions
    keep = np.ones(len(triangles), dtype=bool)
    keep[slots[count:]] = False  # fewer new elements than cut out: close the gaps
    final = np.cumsum(keep) - 1
    return triangles[keep], regions[keep], np.sort(final[at])


def _depths(
    mesh: Mesh,
    points: NDArray[np.float64],
    hole: Hole,
    new: Mesh,
    fresh: NDArray[np.int64],
    crs: CRS,
    config: CaseConfig,
) -> NDArray[np.float64] | None:
    """Return the new nodes' depths: the case's bathymetry, else the mesh's own."""
    if "depth" not in mesh.point_data:
        return None
    if config.bathymetry is not None:
        from coastmesh.case.pipeline.depth import node_depths, read_sources

        rasters = read_sources(config.bathymetry.stack, new.points, crs)
        with_depth, _ = node_depths(config.bathymetry, new, rasters, lambda *_: None)
        return np.asarray(with_depth.point_data["depth"], dtype=np.float64)[fresh]
    return _interpolated(mesh, points, hole, new.points[fresh])


def _interpolated(
    mesh: Mesh, points: NDArray[np.float64], hole: Hole, at: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Return the mesh's depths, linear on the elements cut out, at points."""
    import matplotlib.tri as mtri

    depth = np.asarray(mesh.point_data["depth"], dtype=np.float64)
    tris = mesh.triangles[hole.removed]
    used, local = np.unique(tris, return_inverse=True)
    x, y = points[used].T
    tri = mtri.Triangulation(x, y, local.reshape(-1, 3))
    found = mtri.LinearTriInterpolator(tri, depth[used])(*at.T)
    values = np.ma.filled(found, np.nan)
    lost = np.isnan(values)
    if lost.any():  # on the hole's edge, by rounding: the nearest old node's
        from scipy.spatial import cKDTree

        _, k = cKDTree(points[used]).query(at[lost])
        values[lost] = depth[used][k]
    return values


def _point_data(
    mesh: Mesh,
    new: Mesh,
    fresh: NDArray[np.int64],
    given: NDArray[np.int64],
    n: int,
    depth: NDArray[np.float64] | None,
) -> dict[str, NDArray[np.generic]]:
    """Return the input's node values, the new nodes given theirs (NaN if none)."""
    out: dict[str, NDArray[np.generic]] = {}
    for key, given_values in mesh.point_data.items():
        values = np.asarray(given_values)
        if values.ndim != 1 or not np.issubdtype(values.dtype, np.number):
            continue
        full = np.full(n, np.nan if values.dtype.kind == "f" else 0, dtype=values.dtype)
        full[: len(values)] = values
        if key == "depth" and depth is not None:
            full[given] = depth
        elif key in new.point_data:
            full[given] = np.asarray(new.point_data[key])[fresh]
        out[key] = full
    return out


def _lines(new: Mesh, crs: CRS, target: CRS) -> tuple[MeshLine, ...]:
    """Return the patch's lines (cables), in the input's CRS."""
    return tuple(
        MeshLine(line.id, line.name, reproject_points(line.xy, crs, target))
        for line in new.lines
    )
