"""Meshes and size grids: triangles with tagged boundary edges, sizes on a grid.

Frozen dataclasses, validated when built; constructors never read files.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray
from pyproj import CRS

from coastmesh.types._checks import check_positive_int
from coastmesh.types.domain import SEGMENT_KINDS

__all__ = ["Mesh", "MeshLine", "SizeGrid"]


@dataclass(frozen=True, slots=True)
class SizeGrid:
    """A target edge length on a regular grid of cell centres.

    Parameters
    ----------
    x : array_like of shape (nx,)
        Strictly ascending cell-centre x coordinates, in the meshing CRS; nx >= 2.
    y : array_like of shape (ny,)
        Strictly ascending cell-centre y coordinates, in the meshing CRS; ny >= 2.
    values : array_like of shape (ny, nx)
        Target edge lengths in metres, finite and > 0.
    scale : array_like of shape (ny, nx), optional
        The meshing CRS's scale factor at the nodes, where known (a size grid
        measures it once: :attr:`coastmesh.sizing.grid.Grid.scale`); the mesher
        works it out otherwise (:func:`coastmesh.geometry.projection.to_map_units`).
    patches : sequence of SizeGrid, optional
        Finer grids over a few places (a tidal site: sizes of metres in a
        field of hundreds). Each spans whole cells of the grid it lies in
        (this one, or a coarser patch: patches nest, finer inside coarser,
        and do not otherwise overlap) and has no patches of its own. Inside a
        patch the finest patch's values are the size
        (:func:`coastmesh.geometry.projection.sample_size`, and the view Gmsh
        gets: the cells a finer patch covers are replaced by its cells).

    Raises
    ------
    ValueError
        If a shape, order or value is wrong; the message names the field.

    Examples
    --------
    >>> g = SizeGrid([0.0, 10.0], [0.0, 10.0], [[1.0, 2.0], [1.0, 2.0]])
    >>> g.values.shape
    (2, 2)
    """

    x: NDArray[np.float64]
    y: NDArray[np.float64]
    values: NDArray[np.float64]
    scale: NDArray[np.float64] | None = None
    patches: tuple[SizeGrid, ...] = ()

    def __post_init__(self) -> None:
        _check_patches(self)
        axes = {}
        for name in ("x", "y"):
            axis = np.array(getattr(self, name), dtype=np.float64)
            if axis.ndim != 1 or axis.size < 2:
                raise ValueError(
                    f"{name} has shape {axis.shape}, expected ({name[0]}n,) with "
                    "at least 2 values"
                )
            if not np.isfinite(axis).all() or not (np.diff(axis) > 0).all():
                raise ValueError(f"{name} must be finite and strictly ascending")
            axes[name] = axis
        values = np.array(self.values, dtype=np.float64)
        expected = (axes["y"].size, axes["x"].size)
        if values.shape != expected:
            raise ValueError(
                f"values has shape {values.shape}, expected (ny, nx) = {expected}"
            )
        if not np.isfinite(values).all() or not (values > 0).all():
            raise ValueError("values must be finite and > 0 (metres)")
        arrays = [*axes.items(), ("values", values)]
        if self.scale is not None:
            scale = np.array(self.scale, dtype=np.float64)
            if scale.shape != expected:
                raise ValueError(
                    f"scale has shape {scale.shape}, expected (ny, nx) = {expected}"
                )
            arrays.append(("scale", scale))
        for name, array in arrays:
            array.flags.writeable = False
            object.__setattr__(self, name, array)

    @classmethod
    def from_dataarray(cls, field: Any) -> SizeGrid:
        """Build from a size field DataArray with dims ``("y", "x")``.

        Parameters
        ----------
        field : xarray.DataArray
            Such as :func:`coastmesh.sizing.size_field` returns (metres).

        Returns
        -------
        SizeGrid
        """
        if tuple(field.dims) != ("y", "x"):
            raise ValueError(f"field has dims {tuple(field.dims)}, expected ('y', 'x')")
        return cls(field["x"].values, field["y"].values, field.values)


class MeshLine(NamedTuple):
    """A line inside the mesh (``[[lines]]``): its id, name and nodes in order.

    ``xy`` (k, 2) are the coordinates of its nodes, exactly as the mesh's
    points hold them (in the mesh's CRS): consecutive nodes are joined by a
    mesh edge. Kept as coordinates, not indices, so that a mesh whose nodes are
    renumbered (a channel peeled, a node collapsed) keeps its lines: their
    nodes are held by every stage.
    """

    id: int
    name: str
    xy: NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class Mesh:
    """A 2D triangle mesh with tagged boundary edges.

    Parameters
    ----------
    points : array_like of shape (N, 2)
        Node coordinates in ``crs``; stored as float64.
    triangles : array_like of shape (M, 3)
        Node indices of each triangle, counter-clockwise; stored as int64.
    boundary_edges : array_like of shape (E, 2)
        Node indices of each boundary edge; stored as int64.
    boundary_ids : array_like of shape (E,)
        Physical id of each boundary edge; stored as int64.
    surface_id : int
        Physical id of the triangles.
    crs : pyproj.CRS or None
        CRS of ``points``; None if unknown (a mesh read from a file).
    point_data : mapping of str to array_like of shape (N,), optional
        Values at the nodes, by name.
    boundary_names : mapping of int to str, optional
        Names of the boundary ids (e.g. ``{2: "north", 10: "full"}``).
    boundary_kinds : mapping of int to str, optional
        ``"open"`` (sea) or ``"shoreline"`` (land) for each boundary id; model
        formats that separate open from land boundaries need it.
    regions : array_like of shape (M,), optional
        The physical surface id of each triangle: ``surface_id`` for the sea,
        a farm's or a turbine footprint's id inside them. Default
        ``surface_id`` everywhere.
    region_names : mapping of int to str, optional
        Names of the region ids other than ``surface_id`` (e.g. ``{20: "meygen"}``).
    lines : sequence of MeshLine, optional
        Lines inside the mesh whose edges are mesh edges, each with an id of
        its own (:meth:`line_edges` gives them as node indices).

    Raises
    ------
    ValueError
        If a shape or index is wrong; the message names the field and sizes.

    Examples
    --------
    >>> m = Mesh(
    ...     [[0, 0], [1, 0], [0, 1]], [[0, 1, 2]], [[0, 1], [1, 2], [2, 0]],
    ...     [1, 1, 2], 1, None,
    ... )
    >>> len(m.points), len(m.triangles)
    (3, 1)
    """

    points: NDArray[np.float64]
    triangles: NDArray[np.int64]
    boundary_edges: NDArray[np.int64]
    boundary_ids: NDArray[np.int64]
    surface_id: int
    crs: CRS | None
    point_data: dict[str, NDArray] = field(default_factory=dict)
    boundary_names: dict[int, str] = field(default_factory=dict)
    boundary_kinds: dict[int, str] = field(default_factory=dict)
    # None gives surface_id everywhere: __post_init__ always stores an array
    regions: NDArray[np.int64] = None  # type: ignore[assignment]
    region_names: dict[int, str] = field(default_factory=dict)
    lines: tuple[MeshLine, ...] = ()

    def __post_init__(self) -> None:
        points = np.array(self.points, dtype=np.float64)
        if points.ndim != 2 or points.shape[1] != 2:
            raise ValueError(f"points has shape {points.shape}, expected (N, 2)")
        if not np.isfinite(points).all():
            raise ValueError("points has non-finite coordinates")
        n = points.shape[0]
        triangles = _index_array(self.triangles, "triangles", 3, n)
        edges = _index_array(self.boundary_edges, "boundary_edges", 2, n)
        ids = np.array(self.boundary_ids, dtype=np.int64).reshape(-1)
        if ids.shape[0] != edges.shape[0]:
            raise ValueError(
                f"boundary_ids has {ids.shape[0]} values, boundary_edges has "
                f"{edges.shape[0]} rows: one id per edge"
            )
        check_positive_int(self.surface_id, "surface_id")
        point_data = {}
        for name, values in dict(self.point_data).items():
            array = np.array(values)
            if array.shape[:1] != (n,):
                raise ValueError(
                    f"point_data[{name!r}] has shape {array.shape}, expected "
                    f"({n}, ...): one value per point"
                )
            point_data[str(name)] = array
        crs = None if self.crs is None else CRS.from_user_input(self.crs)
        names = {int(k): str(v) for k, v in dict(self.boundary_names).items()}
        kinds = {int(k): str(v) for k, v in dict(self.boundary_kinds).items()}
        for pid, kind in kinds.items():
            if kind not in SEGMENT_KINDS:
                raise ValueError(
                    f"boundary_kinds[{pid}] is {kind!r}, expected one of "
                    f"{SEGMENT_KINDS}"
                )
        regions = _regions(self.regions, len(triangles), int(self.surface_id))
        region_names = {int(k): str(v) for k, v in dict(self.region_names).items()}
        for name, value in (
            ("lines", _lines(self.lines)),
            ("regions", regions),
            ("region_names", region_names),
            ("points", points),
            ("triangles", triangles),
            ("boundary_edges", edges),
            ("boundary_ids", ids),
            ("surface_id", int(self.surface_id)),
            ("crs", crs),
            ("point_data", point_data),
            ("boundary_names", names),
            ("boundary_kinds", kinds),
        ):
            object.__setattr__(self, name, value)

    def with_point_data(self, **values: NDArray) -> Mesh:
        """Return a copy with more (or replaced) node values.

        Examples
        --------
        >>> m = Mesh([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]], [[0, 1], [1, 2], [2, 0]],
        ...          [1, 1, 1], 1, None)
        >>> sorted(m.with_point_data(depth=[1.0, 2.0, 3.0]).point_data)
        ['depth']
        """
        return Mesh(
            self.points,
            self.triangles,
            self.boundary_edges,
            self.boundary_ids,
            self.surface_id,
            self.crs,
            {**self.point_data, **values},
            self.boundary_names,
            self.boundary_kinds,
            self.regions,
            self.region_names,
            self.lines,
        )

    def line_edges(self) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
        """Return the lines' edges as node indices (L, 2) and their ids (L,).

        Raises
        ------
        ValueError
            If a line's node is not a mesh node (a stage moved or removed it).

        Examples
        --------
        >>> m = Mesh([[0, 0], [2, 0], [1, 1], [1, -1]], [[0, 3, 1], [0, 1, 2]],
        ...          [[0, 3], [3, 1], [1, 2], [2, 0]], [1] * 4, 1, None,
        ...          lines=[MeshLine(5, "cable", [[0, 0], [2, 0]])])
        >>> edges, ids = m.line_edges()
        >>> edges.tolist(), ids.tolist()
        ([[0, 1]], [5])
        """
        if not self.lines:
            return np.empty((0, 2), np.int64), np.empty(0, np.int64)
        keys = self.points[:, 0] + 1j * self.points[:, 1]
        order = np.argsort(keys, kind="stable")
        edges, ids = [], []
        for line in self.lines:
            want = line.xy[:, 0] + 1j * line.xy[:, 1]
            at = np.clip(np.searchsorted(keys[order], want), 0, len(keys) - 1)
            nodes = order[at]
            missing = np.flatnonzero(keys[nodes] != want)
            if len(missing):
                x, y = line.xy[missing[0]]
                raise ValueError(
                    f"line {line.name!r} (id {line.id}): its node at ({x:.6f}, "
                    f"{y:.6f}) is not a node of the mesh"
                )
            edges.append(np.column_stack([nodes[:-1], nodes[1:]]))
            ids.append(np.full(len(nodes) - 1, line.id, dtype=np.int64))
        return np.concatenate(edges).astype(np.int64), np.concatenate(ids)

    @property
    def region_ids(self) -> list[int]:
        """The physical surface ids of the triangles, the domain's first.

        Examples
        --------
        >>> m = Mesh([[0, 0], [1, 0], [0, 1], [1, 1]], [[0, 1, 2], [1, 3, 2]],
        ...          [[0, 1], [1, 3], [3, 2], [2, 0]], [1] * 4, 1, None,
        ...          regions=[20, 1])
        >>> m.region_ids
        [1, 20]
        """
        ids = sorted(set(np.unique(self.regions).tolist()) - {self.surface_id})
        return (
            [self.surface_id, *ids] if (self.regions == self.surface_id).any() else ids
        )


def _lines(values: Iterable[tuple[int, str, ArrayLike]] | None) -> tuple[MeshLine, ...]:
    """Return the lines checked: an id >= 1, a name, two nodes or more."""
    out = []
    for k, line in enumerate(values or ()):
        pid, name, xy = line
        check_positive_int(pid, f"lines[{k}].id")
        xy = np.array(xy, dtype=np.float64)
        if xy.ndim != 2 or xy.shape[1] != 2 or len(xy) < 2:
            raise ValueError(
                f"lines[{k}].xy has shape {xy.shape}, expected (k >= 2, 2)"
            )
        out.append(MeshLine(int(pid), str(name), xy))
    return tuple(out)


def _regions(values: object, m: int, surface_id: int) -> NDArray[np.int64]:
    """Return the triangles' region ids: ``surface_id`` where none are given."""
    if values is None:
        return np.full(m, surface_id, dtype=np.int64)
    array = np.asarray(values)
    if array.shape != (m,):
        raise ValueError(
            f"regions has shape {array.shape}, expected ({m},): one physical "
            "surface id per triangle"
        )
    if array.size and not np.issubdtype(array.dtype, np.integer):
        raise ValueError(f"regions must be integers, got dtype {array.dtype}")
    array = array.astype(np.int64)
    if array.size and array.min() < 1:
        raise ValueError(f"regions has id {int(array.min())}: ids are >= 1")
    return array


def _check_patches(grid: SizeGrid) -> None:
    """Raise ValueError unless the patches are plain grids on whole cells, nested.

    Two patches either do not overlap or one lies inside the other; a patch
    starts and ends on nodes of the finest grid (the base or a patch) it lies
    in.
    """
    patches = tuple(grid.patches)
    object.__setattr__(grid, "patches", patches)
    base = (np.asarray(grid.x, dtype=np.float64), np.asarray(grid.y, dtype=np.float64))
    for k, patch in enumerate(patches):
        if not isinstance(patch, SizeGrid) or patch.patches:
            raise ValueError(f"patches[{k}] must be a SizeGrid without patches")
    boxes = [(p.x[0], p.y[0], p.x[-1], p.y[-1]) for p in patches]
    for k, (patch, box) in enumerate(zip(patches, boxes, strict=True)):
        parents = [
            j
            for j, other in enumerate(boxes)
            if j != k and _inside(box, other) and not _inside(other, box)
        ]
        for j, other in enumerate(boxes):
            overlap = box[0] < other[2] and other[0] < box[2]
            overlap = overlap and box[1] < other[3] and other[1] < box[3]
            if j != k and overlap and not (_inside(box, other) or _inside(other, box)):
                raise ValueError(f"patches[{k}] overlaps patches[{j}]")
        parent = min(
            parents, key=lambda j: patches[j].x[1] - patches[j].x[0], default=None
        )
        x, y = base if parent is None else (patches[parent].x, patches[parent].y)
        for name, axis, ends in (("x", x, patch.x), ("y", y, patch.y)):
            if not np.isin(ends[[0, -1]], axis).all():
                raise ValueError(
                    f"patches[{k}] does not start and end on nodes of the grid "
                    f"it lies in along {name} ({ends[0]:g} to {ends[-1]:g})"
                )


def _inside(box, other) -> bool:
    """Whether ``box`` lies within ``other`` (both (x0, y0, x1, y1))."""
    return bool(
        box[0] >= other[0]
        and box[1] >= other[1]
        and box[2] <= other[2]
        and box[3] <= other[3]
    )


def _index_array(values: object, name: str, width: int, n: int) -> NDArray[np.int64]:
    array = np.asarray(values)
    if array.size == 0:
        array = array.reshape(0, width)
    if array.ndim != 2 or array.shape[1] != width:
        raise ValueError(f"{name} has shape {array.shape}, expected (M, {width})")
    if array.size and not np.issubdtype(array.dtype, np.integer):
        raise ValueError(f"{name} must be integers, got dtype {array.dtype}")
    array = array.astype(np.int64)
    if array.size and (array.min() < 0 or array.max() >= n):
        raise ValueError(
            f"{name} has indices in [{array.min()}, {array.max()}], expected "
            f"[0, {n - 1}] for {n} points"
        )
    return array
