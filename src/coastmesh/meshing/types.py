"""Data types of the meshing stage: domains, size grids and meshes.

All are frozen dataclasses, validated when built; constructors never read files.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
import shapely
from numpy.typing import NDArray
from pyproj import CRS

__all__ = ["BoundarySegment", "Domain", "Mesh", "SizeGrid"]

SEGMENT_KINDS = ("shoreline", "open")


@dataclass(frozen=True, slots=True)
class BoundarySegment:
    """A piece of a domain boundary with its physical id.

    Parameters
    ----------
    coords : array_like of shape (k, 2), k >= 2
        The vertices, in the domain CRS; stored as a new float64 array.
    kind : {"shoreline", "open"}
        Land boundary or open (sea) boundary.
    name : str
        A label, used in messages.
    physical_id : int
        The physical id given to the mesh edges of this segment; > 0.

    Raises
    ------
    ValueError
        If ``coords`` has the wrong shape or non-finite values, ``kind`` is unknown
        or ``physical_id`` is not a positive integer.

    Examples
    --------
    >>> s = BoundarySegment([[0, 0], [1, 0]], "open", "south", 2)
    >>> s.coords.dtype, s.physical_id
    (dtype('float64'), 2)
    """

    coords: NDArray[np.float64]
    kind: Literal["shoreline", "open"]
    name: str
    physical_id: int

    def __post_init__(self) -> None:
        coords = np.array(self.coords, dtype=np.float64)
        if coords.ndim != 2 or coords.shape[1] != 2 or coords.shape[0] < 2:
            raise ValueError(
                f"segment {self.name!r}: coords has shape {coords.shape}, "
                "expected (k, 2) with k >= 2"
            )
        if not np.isfinite(coords).all():
            bad = int(np.flatnonzero(~np.isfinite(coords).all(axis=1))[0])
            raise ValueError(
                f"segment {self.name!r}: coords vertex {bad} is not finite"
            )
        if self.kind not in SEGMENT_KINDS:
            raise ValueError(
                f"segment {self.name!r}: kind is {self.kind!r}, expected one of "
                f"{SEGMENT_KINDS}"
            )
        _check_positive_int(self.physical_id, f"segment {self.name!r}: physical_id")
        coords.flags.writeable = False
        object.__setattr__(self, "coords", coords)
        object.__setattr__(self, "physical_id", int(self.physical_id))

    @property
    def closed(self) -> bool:
        """Whether the segment is a whole ring (first vertex equals last)."""
        return bool((self.coords[0] == self.coords[-1]).all())


@dataclass(frozen=True, slots=True)
class Domain:
    """A polygon to mesh, its boundary split into tagged segments, and its CRS.

    Parameters
    ----------
    polygon : shapely.Polygon
        A valid polygon; holes are islands.
    segments : sequence of BoundarySegment
        Ordered pieces of the rings: each ring of ``polygon`` is covered by a run of
        consecutive segments, each starting where the previous one ends, the last
        ending where the first starts. A ring may be a single closed segment.
    crs : pyproj.CRS
        CRS of the polygon and segment coordinates; anything
        :meth:`pyproj.CRS.from_user_input` takes is converted.
    surface_id : int, default 1
        The physical id of the triangles; > 0.

    Raises
    ------
    ValueError
        If the polygon is not a valid Polygon, or the segments do not form closed
        rings matching the polygon's rings.

    Examples
    --------
    >>> import shapely
    >>> ring = [[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]]
    >>> d = Domain(
    ...     shapely.Polygon(ring),
    ...     (BoundarySegment(ring, "shoreline", "coast", 1),),
    ...     crs="EPSG:32630",
    ... )
    >>> d.surface_id, d.crs.to_epsg()
    (1, 32630)
    """

    polygon: shapely.Polygon
    segments: tuple[BoundarySegment, ...]
    crs: CRS
    surface_id: int = 1

    def __post_init__(self) -> None:
        if not isinstance(self.polygon, shapely.Polygon) or self.polygon.is_empty:
            raise ValueError(
                f"polygon must be a non-empty shapely Polygon, got "
                f"{type(self.polygon).__name__}"
            )
        if not self.polygon.is_valid:
            raise ValueError(
                f"polygon is invalid: {shapely.is_valid_reason(self.polygon)}"
            )
        segments = tuple(self.segments)
        for i, segment in enumerate(segments):
            if not isinstance(segment, BoundarySegment):
                raise ValueError(
                    f"segments[{i}] is a {type(segment).__name__}, expected "
                    "BoundarySegment"
                )
        _check_positive_int(self.surface_id, "surface_id")
        object.__setattr__(self, "segments", segments)
        object.__setattr__(self, "crs", CRS.from_user_input(self.crs))
        object.__setattr__(self, "surface_id", int(self.surface_id))
        _check_rings(self.polygon, segments)

    def rings(self) -> list[tuple[BoundarySegment, ...]]:
        """Return the segments grouped by ring, in order.

        Returns
        -------
        list of tuple of BoundarySegment
            One tuple per closed run of consecutive segments.
        """
        return _chain(self.segments)


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

    def __post_init__(self) -> None:
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
        for name, array in (*axes.items(), ("values", values)):
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
        _check_positive_int(self.surface_id, "surface_id")
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
        for name, value in (
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


def _check_positive_int(value: object, name: str) -> None:
    if isinstance(value, bool) or not isinstance(value, int | np.integer):
        raise ValueError(f"{name} is {value!r}, expected an integer > 0")
    if value <= 0:
        raise ValueError(f"{name} is {value}, expected an integer > 0")


def _chain(
    segments: tuple[BoundarySegment, ...],
) -> list[tuple[BoundarySegment, ...]]:
    """Group consecutive segments into closed rings; raise if one stays open."""
    rings: list[tuple[BoundarySegment, ...]] = []
    current: list[BoundarySegment] = []
    for i, segment in enumerate(segments):
        if current and not (current[-1].coords[-1] == segment.coords[0]).all():
            raise ValueError(
                f"segments[{i}] ({segment.name!r}) starts at "
                f"{tuple(segment.coords[0])}, but segments[{i - 1}] "
                f"({current[-1].name!r}) ends at {tuple(current[-1].coords[-1])} "
                "and does not close its ring"
            )
        current.append(segment)
        if (segment.coords[-1] == current[0].coords[0]).all():
            rings.append(tuple(current))
            current = []
    if current:
        raise ValueError(
            f"segments from {current[0].name!r} to {current[-1].name!r} do not "
            "close a ring: the last end point must equal the first start point"
        )
    return rings


def _check_rings(
    polygon: shapely.Polygon, segments: tuple[BoundarySegment, ...]
) -> None:
    """Check that the segments chain into exactly the rings of the polygon."""
    rings = _chain(segments)
    expected = 1 + len(polygon.interiors)
    if len(rings) != expected:
        raise ValueError(
            f"segments form {len(rings)} closed rings, polygon has {expected} "
            "(the exterior and one per hole)"
        )
    coords = [
        np.concatenate([s.coords[:-1] for s in ring] + [ring[0].coords[:1]])
        for ring in rings
    ]
    if any(len(c) < 4 for c in coords):
        raise ValueError("segments form a ring with fewer than 3 distinct vertices")
    areas = [abs(shapely.area(shapely.Polygon(c))) for c in coords]
    shell = int(np.argmax(areas))
    rebuilt = shapely.Polygon(
        coords[shell], [c for i, c in enumerate(coords) if i != shell]
    )
    if not rebuilt.is_valid or not shapely.equals(rebuilt, polygon):
        raise ValueError(
            "segments do not cover the polygon's rings: the rings they form differ "
            "from the polygon's exterior and holes"
        )
