"""The channel term on a world lon/lat grid: widths by great-circle distance.

The width of the water at a node is, as on a plane grid
(:mod:`coastmesh.sizing.channel`), the diameter of the largest disk in the
water that holds it. On a :class:`~coastmesh.sizing.grid.SphereGrid` the
grid's steps have no one length (the east-west step shrinks with the cosine
of the latitude; the last column is the first meridian again; a row at a
pole is one point), so the disks are measured on the sphere itself:

1. *The edge of the water* is the midpoint (on the sphere) of every grid step
   from a water node to a node that is not water: east-west (across the
   antimeridian too) and north-south; past a first or last row that is not a
   pole, half a step beyond it (outside the grid is land, as on a plane).
2. *The depth* of a water node is its great-circle distance to the nearest
   point of that edge.
3. A disk of radius ``r`` fits where the depth is at least ``r``; the nodes it
   holds are those within ``r`` (great-circle) of such a centre. The width at
   a node is ``2 r`` for the largest ``r`` whose disks hold it, over radii in
   geometric steps of :data:`~coastmesh.sizing.channel.RADIUS_STEP` from half
   the grid's north-south step; a node no such disk holds gets twice its
   depth.

Every distance is a chord of the unit sphere in a k-d tree
(:class:`scipy.spatial.cKDTree`), turned into an arc, so the antimeridian and
the poles need no special case. The depth is 1-Lipschitz, so a centre can
only hold a node of depth below ``r`` if its own depth is below ``2 r``: each
radius looks at that band of centres alone, and the cost follows the coasts.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray
from scipy import ndimage
from scipy.spatial import cKDTree

from coastmesh.errors import ConfigError
from coastmesh.geometry.earth import EARTH_RADIUS
from coastmesh.geometry.sphere import lonlat_to_xyz
from coastmesh.sizing.channel import RADIUS_STEP
from coastmesh.sizing.narrow import NARROW_ELEMENTS, rank_channels

__all__ = [
    "sphere_narrow_channels",
    "sphere_over_land",
    "sphere_water_mask",
    "sphere_width",
]

#: Relative tolerance of the comparisons of distances with radii: a centre at
#: exactly ``r`` from the edge fits, whatever the rounding of the arcs.
TOLERANCE = 1e-9


def sphere_width(
    water: NDArray[np.bool_],
    lat: NDArray[np.float64],
    *,
    max_width: float,
    step: float = RADIUS_STEP,
) -> NDArray[np.float64]:
    """Return the width of the water at each node of a world lon/lat grid (metres).

    Parameters
    ----------
    water : ndarray of bool, shape (ny, nx + 1)
        The water at the nodes of a grid of equal steps from longitude -180 to
        180 (the last column is the first meridian again).
    lat : ndarray of shape (ny,)
        The rows' latitudes, degrees, ascending and equally spaced.
    max_width : float
        Widths at or above this (metres) come out as ``inf``.
    step : float
        The ratio of successive radii (> 1).

    Returns
    -------
    ndarray of shape (ny, nx + 1)
        The diameter of the largest disk in the water that holds the node,
        rounded down to the radii measured (the module notes); 0 on land;
        ``inf`` where at least ``max_width``.

    Examples
    --------
    A strait four columns (445 km) wide along the meridians, across the
    equator: rounded down by a radius step and up to a cell, as on a plane
    (:func:`~coastmesh.sizing.channel.local_width`):

    >>> lat = np.arange(-20.0, 21.0, 1.0)
    >>> water = np.zeros((41, 361), bool); water[:, 10:14] = True
    >>> w = sphere_width(water, lat, max_width=2e6)
    >>> round(float(w[20, 11]) / 1e3), round(float(w[20, 13]) / 1e3), float(w[20, 0])
    (296, 296, 0.0)
    """
    water, lat = _grid(water, lat)
    ny, nx = water.shape
    if ny < 2 or not max_width > 0 or not step > 1:
        raise ConfigError(
            f"{ny} rows, max_width = {max_width}, step = {step}: need 2 rows or "
            "more, max_width > 0 and step > 1"
        )
    xyz = _nodes(nx, lat)
    radii = [0.5 * EARTH_RADIUS * math.radians(float(lat[1] - lat[0]))]
    while radii[-1] < max_width / 2:
        radii.append(radii[-1] * step)
    depth = _depth(water, lat, xyz, reach=2.5 * radii[-1])
    width = np.where(water, np.inf, 0.0)
    done = _held(water, depth, xyz, radii[-1])
    for r in reversed(radii[:-1]):
        new = _held(water, depth, xyz, r) & ~done
        width[new] = 2 * r
        done |= new
    rest = water & ~done  # no disk of the smallest radius holds it
    width[rest] = 2 * depth[rest]
    return np.hstack([width, width[:, :1]])


def sphere_water_mask(
    inside: NDArray[np.bool_],
    lat: NDArray[np.float64],
    shore: NDArray[np.float64],
    opened: NDArray[np.float64],
) -> NDArray[np.bool_]:
    """Return the water: inside the domain, or outside but nearer open than shore.

    As :func:`~coastmesh.sizing.channel.water_mask` on a plane (the sea goes on
    past an open boundary), with great-circle distances to points of the
    lines.

    Parameters
    ----------
    inside : ndarray of bool, shape (ny, nx + 1)
        The nodes inside the domain (the last column is the first again).
    lat : ndarray of shape (ny,)
        The rows' latitudes, degrees.
    shore, opened : ndarray of shape (n, 2)
        Points along the shorelines and the open boundaries, lon/lat degrees,
        closer together than the grid's step.

    Examples
    --------
    >>> inside = np.zeros((3, 9), bool); inside[:, :3] = True
    >>> shore = np.array([[-180.0, 0.0]]); opened = np.array([[-80.0, 0.0]])
    >>> sphere_water_mask(inside, np.array([-10.0, 0.0, 10.0]), shore,
    ...                   opened).astype(int)[1].tolist()
    [1, 1, 1, 1, 1, 1, 0, 0, 1]
    """
    inside, lat = _grid(inside, lat)
    water = inside.copy()
    if len(opened):
        if len(shore):
            xyz = _nodes(inside.shape[1], lat)[~inside]
            to_shore, _ = cKDTree(lonlat_to_xyz(shore)).query(xyz)
            to_open, _ = cKDTree(lonlat_to_xyz(opened)).query(xyz)
            water[~inside] = to_open < to_shore
        else:
            water[:] = True
    return np.hstack([water, water[:, :1]])


def sphere_over_land(
    term: NDArray[np.float64],
    water: NDArray[np.bool_],
    lat: NDArray[np.float64],
    *,
    reach: float = math.inf,
) -> NDArray[np.float64]:
    """Return ``term`` with each land node given its nearest water node's value.

    :func:`~coastmesh.sizing.channel.over_land` on a world grid: nearest by
    great-circle distance, across the antimeridian and the poles. Land nodes
    farther than ``reach`` (metres) from any water node get ``inf``: no bound
    (no mesh is made there; far inland, the search would cost the most).

    Examples
    --------
    Eight nodes round the equator, 45 degrees (5,004 km) apart:

    >>> term = np.array([[1.0, 2, 3, 4, 5, 6, 7, 8, 1]])
    >>> water = np.array([[1, 0, 0, 0, 0, 1, 1, 1, 1]], bool)
    >>> sphere_over_land(term, water, np.array([0.0])).tolist()
    [[1.0, 1.0, 1.0, 6.0, 6.0, 6.0, 7.0, 8.0, 1.0]]
    >>> sphere_over_land(term, water, np.array([0.0]), reach=6e6).tolist()
    [[1.0, 1.0, inf, inf, 6.0, 6.0, 7.0, 8.0, 1.0]]
    """
    wet, lat = _grid(water, lat)
    values = np.asarray(term, dtype=np.float64)[:, :-1]
    if wet.all() or not wet.any():
        return np.asarray(term, dtype=np.float64).copy()
    xyz = _nodes(wet.shape[1], lat)
    bound = _chord(reach) * (1 + TOLERANCE) if math.isfinite(reach) else np.inf
    chord, nearest = cKDTree(xyz[wet]).query(xyz[~wet], distance_upper_bound=bound)
    found = np.isfinite(chord)
    out = values.copy()
    land = np.full(len(chord), np.inf)
    land[found] = values[wet][nearest[found]]
    out[~wet] = land
    return np.hstack([out, out[:, :1]])


def sphere_narrow_channels(
    width: NDArray[np.float64],
    inside: NDArray[np.bool_],
    lat: NDArray[np.float64],
    *,
    h_min: float,
    margin: float = 0.0,
    min_length: float | None = None,
) -> tuple[NDArray[np.int32], list[tuple[int, int, float, float]]]:
    """Label the water narrower than ``NARROW_ELEMENTS * h_min`` on a world grid.

    :func:`~coastmesh.sizing.narrow.narrow_channels` on a
    :class:`~coastmesh.sizing.grid.SphereGrid`: the stretches are joined
    across the antimeridian (8 neighbours), their areas are the nodes' areas
    on the sphere (:meth:`~coastmesh.sizing.grid.SphereGrid.areas`), and a
    stretch's length (the tip of a corner is shorter than ``min_length``) is
    the diagonal of its rows and columns, the columns at their widest (the
    latitude nearest the equator), the shortest way round. A node counts only
    if its width plus ``margin`` (metres: what the widths may be rounded down
    by, a grid step) is still narrow: water the grid cannot tell from wider
    water is not called narrow.

    Returns
    -------
    labels : ndarray of int32, shape (ny, nx + 1)
        0 outside any narrow stretch, else its number, largest first (the last
        column is the first again).
    channels : list of (row, col, area_m2, width_m)
        Its widest node (``col < nx``), its area and its greatest width.

    Examples
    --------
    A strait of two columns across the antimeridian, 20 rows long:

    >>> width = np.full((20, 37), np.inf); width[:, [0, 35, 36]] = 5e5
    >>> labels, found = sphere_narrow_channels(
    ...     width, np.ones((20, 37), bool), np.arange(-95.0, 96.0, 10.0)[:20],
    ...     h_min=5e5)
    >>> int(labels.max()), len(found), found[0][3]
    (1, 1, 500000.0)
    """
    inside, lat = _grid(inside, lat)
    width = np.asarray(width, dtype=np.float64)[:, :-1]
    ny, nx = inside.shape
    narrow = inside & (width + margin < NARROW_ELEMENTS * h_min)
    labels, count = _wrapped_labels(narrow)
    if count == 0:
        return np.hstack([labels, labels[:, :1]]), []
    if min_length is None:
        min_length = NARROW_ELEMENTS * h_min
    area = np.bincount(labels.ravel(), _areas(nx, lat).ravel(), minlength=count + 1)
    rows, cols = np.nonzero(labels)
    order = np.argsort(labels[rows, cols], kind="stable")
    starts = np.searchsorted(labels[rows, cols][order], np.arange(1, count + 2))
    dlat = math.radians(float(lat[1] - lat[0])) if ny > 1 else 0.0
    length = np.zeros(count + 1)
    for k in range(count):
        part = order[starts[k] : starts[k + 1]]
        r, c = rows[part], cols[part]
        wide = math.cos(math.radians(float(np.min(np.abs(lat[r])))))
        span = _circular_span(np.unique(c), nx) * 2 * math.pi / nx * wide
        length[k + 1] = EARTH_RADIUS * math.hypot((r.max() - r.min() + 1) * dlat, span)
    labels, found = rank_channels(labels, width, area, length >= min_length)
    return np.hstack([labels, labels[:, :1]]), found


def _grid(
    values: NDArray[np.bool_], lat: NDArray[np.float64]
) -> tuple[NDArray[np.bool_], NDArray[np.float64]]:
    """Check a world grid's mask and rows; return the mask's own columns."""
    values = np.asarray(values, dtype=bool)
    lat = np.asarray(lat, dtype=np.float64)
    if values.ndim != 2 or values.shape[0] != lat.size or values.shape[1] < 5:
        raise ConfigError(
            f"the grid has shape {values.shape}; lat has {lat.size} rows: need "
            "(ny, nx + 1) with nx >= 4, the last column the first meridian again"
        )
    return values[:, :-1], lat


def _nodes(nx: int, lat: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return the nodes' unit vectors, (ny, nx, 3), columns from longitude -180."""
    lon = -180.0 + 360.0 / nx * np.arange(nx)
    glon, glat = np.meshgrid(lon, lat)
    xyz = lonlat_to_xyz(np.column_stack([glon.ravel(), glat.ravel()]))
    return xyz.reshape(len(lat), nx, 3)


def _areas(nx: int, lat: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return the area each node stands for, m2 (``R^2 dlon dlat cos(lat)``)."""
    dlat = math.radians(float(lat[1] - lat[0])) if lat.size > 1 else 0.0
    cell = EARTH_RADIUS**2 * (2 * math.pi / nx) * dlat
    return np.repeat((cell * np.cos(np.radians(lat)))[:, None], nx, axis=1)


def _edge_points(
    water: NDArray[np.bool_], lat: NDArray[np.float64], xyz: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Return the edge of the water as unit vectors (the module notes, step 1)."""
    ny, nx = water.shape
    east = np.roll(water, -1, axis=1)
    points = [xyz[water != east] + np.roll(xyz, -1, axis=1)[water != east]]
    north = water[:-1] != water[1:]
    points.append(xyz[:-1][north] + xyz[1:][north])
    dlat = float(lat[1] - lat[0]) if ny > 1 else 1.0
    lon = -180.0 + 360.0 / nx * np.arange(nx)
    for row, beyond in ((0, lat[0] - dlat / 2), (ny - 1, lat[-1] + dlat / 2)):
        if abs(lat[row]) < 90.0 and water[row].any():
            ring = np.column_stack([lon, np.full(nx, np.clip(beyond, -90.0, 90.0))])
            points.append(lonlat_to_xyz(ring[water[row]]))
    edges = np.concatenate(points)
    norm = np.linalg.norm(edges, axis=1)
    unit: NDArray[np.float64] = edges[norm > 0] / norm[norm > 0, None]
    return unit


def _depth(
    water: NDArray[np.bool_],
    lat: NDArray[np.float64],
    xyz: NDArray[np.float64],
    *,
    reach: float,
) -> NDArray[np.float64]:
    """Great-circle distance of each water node to the edge; ``inf`` past ``reach``."""
    depth = np.full(water.shape, np.inf)
    edges = _edge_points(water, lat, xyz)
    if not len(edges) or not water.any():
        return depth
    chord, _ = cKDTree(edges).query(
        xyz[water], distance_upper_bound=_chord(reach) * (1 + TOLERANCE)
    )
    depth[water] = _arc(chord)
    return depth


def _held(
    water: NDArray[np.bool_],
    depth: NDArray[np.float64],
    xyz: NDArray[np.float64],
    r: float,
) -> NDArray[np.bool_]:
    """Water nodes within ``r`` of a centre, a node at least ``r`` from the edge."""
    centres = water & (depth >= r * (1 - TOLERANCE))
    near = water & ~centres
    held = centres.copy()
    band = centres & (depth < 2.5 * r)  # only these can reach a node of `near`
    if not near.any() or not band.any():
        return held
    bound = _chord(r * (1 + TOLERANCE))
    chord, _ = cKDTree(xyz[band]).query(xyz[near], distance_upper_bound=bound * 1.001)
    held[near] = chord <= bound
    return held


def _wrapped_labels(mask: NDArray[np.bool_]) -> tuple[NDArray[np.int32], int]:
    """Label 8-connected stretches, joined across the antimeridian."""
    ext = np.hstack([mask, mask[:, :1]])
    labels, count = ndimage.label(ext, structure=np.ones((3, 3)))
    root = np.arange(count + 1)

    def find(k: int) -> int:
        while root[k] != k:
            root[k] = root[root[k]]
            k = root[k]
        return k

    for a, b in zip(labels[:, 0], labels[:, -1], strict=True):
        if a and b:
            ra, rb = find(a), find(b)
            root[max(ra, rb)] = min(ra, rb)
    final = np.array([find(k) for k in range(count + 1)])
    used = np.unique(final[1:]) if count else np.array([], dtype=np.int64)
    renumber = np.zeros(count + 1, dtype=np.int32)
    renumber[used] = np.arange(1, len(used) + 1, dtype=np.int32)
    return renumber[final][labels[:, :-1]], len(used)


def _circular_span(columns: NDArray[np.int64], nx: int) -> int:
    """Return the fewest consecutive columns (round the world) holding ``columns``."""
    gaps = np.diff(np.concatenate([columns, [columns[0] + nx]]))
    return int(nx - gaps.max() + 1)


def _chord(arc: float) -> float:
    """Return the unit sphere's chord of an arc of ``arc`` metres on the Earth."""
    return 2.0 * math.sin(min(arc / EARTH_RADIUS, math.pi) / 2.0)


def _arc(chord: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return the arcs (metres on the Earth) of unit-sphere chords; inf stays inf."""
    with np.errstate(invalid="ignore"):
        arc = 2.0 * EARTH_RADIUS * np.arcsin(np.minimum(chord / 2.0, 1.0))
    return np.where(np.isinf(chord), np.inf, arc)
