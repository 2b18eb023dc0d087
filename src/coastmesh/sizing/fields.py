"""Sizes from a field: a value on the size grid, mapped to an element size.

The maths of ``[[mesh_size.fields]]`` (the term is
:mod:`coastmesh.case.terms.fields`):

* :class:`SizeMapping`: value to size, by a table of thresholds, a linear
  ramp between two values, or a power law; where a value asks for nothing the
  size is ``inf`` (the term does not apply there);
* :func:`triangles_on_grid`: a triangle mesh's node or triangle values on the
  nodes of a regular grid, linear inside each triangle;
* :func:`node_gradients`: the gradient of node values on a triangle mesh,
  in metres also on longitude/latitude nodes (speed gradients, vorticity).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from coastmesh.errors import ConfigError
from coastmesh.geometry.earth import EARTH_RADIUS

__all__ = [
    "MAPPINGS",
    "SizeMapping",
    "node_gradients",
    "triangles_on_grid",
]

#: The kinds of mapping from a value to a size.
MAPPINGS = ("thresholds", "ramp", "power")

#: Candidate (triangle, grid node) pairs tested at once by
#: :func:`triangles_on_grid`: about 100 MB of work arrays.
_PAIRS = 2_000_000


@dataclass(frozen=True)
class SizeMapping:
    """A value-to-size mapping (sizes in metres).

    Attributes
    ----------
    kind : {"thresholds", "ramp", "power"}
        * ``"thresholds"``: ``values`` strictly increasing, one size each; a
          value in ``[values[k], values[k+1])`` gets ``sizes[k]``, the last
          from ``values[-1]`` up. Below ``values[0]`` nothing applies (begin
          with ``-inf`` to cover every value). The sizes go one way (all
          down or all up).
        * ``"ramp"``: two values (increasing) and two sizes; linear in
          between. Beyond the end with the larger size nothing applies (the
          term only refines); beyond the other end its size holds.
        * ``"power"``: ``h = sizes[0] * (v / values[0]) ** exponent`` where
          ``v > 0``; nothing applies where ``v <= 0``.
    values, sizes : tuple of float
        As ``kind`` needs them.
    exponent : float
        The power law's exponent (negative: finer where the value is larger).
    where : str
        What the mapping is called in errors (``"mesh_size.fields[0]"``).

    Raises
    ------
    ConfigError
        If the values or sizes do not fit ``kind``: a size not positive and
        finite, values not strictly increasing, sizes not all one way, the
        wrong count, a zero exponent.

    Examples
    --------
    >>> m = SizeMapping("thresholds", (2.0, 3.0), (100.0, 50.0))
    >>> m.sizes_of(np.array([1.0, 2.0, 2.5, 3.0, np.nan])).tolist()
    [inf, 100.0, 100.0, 50.0, inf]
    >>> SizeMapping("ramp", (1.0, 2.0), (300.0, 50.0)).sizes_of(
    ...     np.array([0.5, 1.5, 4.0])).tolist()
    [inf, 175.0, 50.0]
    >>> SizeMapping("power", (2.0,), (50.0,), exponent=-1.0).sizes_of(
    ...     np.array([1.0, 4.0, 0.0])).tolist()
    [100.0, 25.0, inf]
    """

    kind: str
    values: tuple[float, ...]
    sizes: tuple[float, ...]
    exponent: float = -1.0
    where: str = "mapping"

    def __post_init__(self) -> None:
        """Check the values and sizes against the kind."""
        where = self.where
        if self.kind not in MAPPINGS:
            raise ConfigError(
                f"{where}.mapping = {self.kind!r}: use one of {', '.join(MAPPINGS)}"
            )
        values = np.asarray(self.values, dtype=np.float64)
        sizes = np.asarray(self.sizes, dtype=np.float64)
        want = {"thresholds": None, "ramp": 2, "power": 1}[self.kind]
        if len(sizes) != len(values) or not len(values):
            raise ConfigError(
                f"{where}: {len(values)} values and {len(sizes)} sizes; give one "
                "size per value"
            )
        if want is not None and len(values) != want:
            raise ConfigError(
                f"{where}: a {self.kind} mapping takes {want} value(s) and "
                f"{want} size(s), not {len(values)}"
            )
        bad = [float(h) for h in sizes if not (np.isfinite(h) and h > 0)]
        if bad:
            raise ConfigError(
                f"{where}.sizes = {list(self.sizes)}: {bad[0]:g} is not a positive size"
            )
        if np.isnan(values).any() or (np.diff(values) <= 0).any():
            raise ConfigError(
                f"{where}.values = {list(self.values)}: must be strictly increasing"
            )
        if self.kind == "ramp" and not np.isfinite(values).all():
            raise ConfigError(f"{where}.values = {list(self.values)}: must be finite")
        if self.kind == "power" and not (values[0] > 0 and np.isfinite(values[0])):
            raise ConfigError(
                f"{where}.values = {list(self.values)}: the reference value must be > 0"
            )
        if self.kind == "power" and not (
            self.exponent != 0 and np.isfinite(self.exponent)
        ):
            raise ConfigError(f"{where}.exponent = {self.exponent:g}: must not be 0")
        step = np.diff(sizes)
        if self.kind == "thresholds" and (step > 0).any() and (step < 0).any():
            raise ConfigError(
                f"{where}.sizes = {list(self.sizes)}: not ordered; they must all "
                "decrease or all increase along the values"
            )

    @property
    def smallest(self) -> float:
        """The smallest size the mapping gives (the power law: its reference size)."""
        return float(min(self.sizes))

    def sizes_of(self, value: ArrayLike) -> NDArray[np.float64]:
        """Return the size for each value; ``inf`` where nothing applies (and NaN)."""
        v = np.asarray(value, dtype=np.float64)
        out = np.full(v.shape, np.inf)
        ok = np.isfinite(v)
        values = np.asarray(self.values, dtype=np.float64)
        sizes = np.asarray(self.sizes, dtype=np.float64)
        if self.kind == "thresholds":
            k = np.searchsorted(values, v[ok], side="right") - 1
            out[ok] = np.where(k >= 0, sizes[np.maximum(k, 0)], np.inf)
        elif self.kind == "ramp":
            (v0, v1), (h0, h1) = values, sizes
            t = np.clip((v[ok] - v0) / (v1 - v0), 0.0, 1.0)
            h = h0 + t * (h1 - h0)
            coarse_end = v[ok] < v0 if h0 >= h1 else v[ok] > v1
            out[ok] = np.where(coarse_end & (h0 != h1), np.inf, h)
        else:
            positive = ok & (v > 0)
            with np.errstate(over="ignore"):  # a value near 0: no bound (inf)
                out[positive] = sizes[0] * (v[positive] / values[0]) ** self.exponent
        return out


def triangles_on_grid(
    points: NDArray[np.float64],
    triangles: NDArray[np.int64],
    x: NDArray[np.float64],
    y: NDArray[np.float64],
    values: NDArray[np.float64],
    *,
    per: str = "node",
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Sample a triangle mesh's values at the nodes of a regular grid.

    Parameters
    ----------
    points : ndarray of shape (n, 2)
        The mesh's nodes, in the grid's coordinates.
    triangles : ndarray of shape (m, 3)
        Node indices, 0-based.
    x, y : ndarray of shape (nx,), (ny,)
        The grid's node coordinates, ascending and evenly spaced.
    values : ndarray of shape (n,) or (m,)
        One value per node (``per="node"``: linear in each triangle) or per
        triangle (``per="triangle"``: constant in each). NaN stays NaN.
    per : {"node", "triangle"}
        Where ``values`` are.

    Returns
    -------
    values : ndarray of shape (ny, nx)
        The value at each grid node inside a triangle; NaN elsewhere.
    inside : ndarray of bool of shape (ny, nx)
        The grid nodes inside (or on the edge of) a triangle of the mesh.

    Examples
    --------
    >>> pts = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]])
    >>> v, inside = triangles_on_grid(pts, np.array([[0, 1, 2]]),
    ...     np.array([0.0, 1.0, 2.0]), np.array([0.0, 1.0]), np.array([0.0, 2.0, 4.0]))
    >>> v.tolist(), inside.tolist()
    ([[0.0, 1.0, 2.0], [2.0, 3.0, nan]], [[True, True, True], [True, True, False]])
    """
    # By hand: the point location of matplotlib (TrapezoidMapTriFinder) took
    # 42 s to build for a 1-million-node mesh, and xugrid's needs numba. A
    # regular grid makes location a scan of each triangle's bounding box.
    if per not in ("node", "triangle"):
        raise ValueError(f"per = {per!r}: use 'node' or 'triangle'")
    x = np.asarray(x, dtype=np.float64)
    y = np.asarray(y, dtype=np.float64)
    out = np.full((len(y), len(x)), np.nan)
    inside = np.zeros((len(y), len(x)), dtype=bool)
    tri = np.asarray(triangles, dtype=np.int64)
    if not len(tri) or len(x) < 2 or len(y) < 2:
        return out, inside
    corners = np.asarray(points, dtype=np.float64)[tri]  # (m, 3, 2)
    dx, dy = x[1] - x[0], y[1] - y[0]
    i0, i1 = _span(corners[:, :, 0], x[0], dx, len(x))
    j0, j1 = _span(corners[:, :, 1], y[0], dy, len(y))
    counts = np.maximum(i1 - i0 + 1, 0) * np.maximum(j1 - j0 + 1, 0)
    todo = np.flatnonzero(counts > 0)
    vals = np.asarray(values, dtype=np.float64)
    for chunk in _chunks(todo, counts[todo]):
        t = np.repeat(chunk, counts[chunk])
        start = np.cumsum(counts[chunk]) - counts[chunk]
        k = np.arange(len(t)) - np.repeat(start, counts[chunk])
        width = (i1 - i0 + 1)[t]
        ii, jj = i0[t] + k % width, j0[t] + k // width
        lam = _barycentric(corners[t], x[ii], y[jj])
        ok = (lam >= -1e-9).all(axis=1)
        t, ii, jj, lam = t[ok], ii[ok], jj[ok], lam[ok]
        if per == "node":
            value = (lam * vals[tri[t]]).sum(axis=1)
        else:
            value = vals[t]
        out[jj, ii] = value
        inside[jj, ii] = True
    return out, inside


def _span(
    coords: NDArray[np.float64], origin: float, step: float, n: int
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """Return the first and last grid index inside each triangle's extent."""
    lo = np.ceil((coords.min(axis=1) - origin) / step - 1e-9).astype(np.int64)
    hi = np.floor((coords.max(axis=1) - origin) / step + 1e-9).astype(np.int64)
    return np.maximum(lo, 0), np.minimum(hi, n - 1)


def _chunks(
    todo: NDArray[np.int64], counts: NDArray[np.int64]
) -> list[NDArray[np.int64]]:
    """Split the triangles so that each chunk tests about :data:`_PAIRS` pairs."""
    edges = np.searchsorted(np.cumsum(counts), np.arange(_PAIRS, counts.sum(), _PAIRS))
    return [c for c in np.split(todo, edges + 1) if len(c)]


def _barycentric(
    corners: NDArray[np.float64], px: NDArray[np.float64], py: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Return the barycentric coordinates of points in their triangles, (k, 3).

    A degenerate triangle (no area) gives -inf: no point is inside it.
    """
    ax, ay = corners[:, 0, 0], corners[:, 0, 1]
    bx, by = corners[:, 1, 0] - ax, corners[:, 1, 1] - ay
    cx, cy = corners[:, 2, 0] - ax, corners[:, 2, 1] - ay
    qx, qy = px - ax, py - ay
    det = bx * cy - by * cx
    with np.errstate(divide="ignore", invalid="ignore"):
        l1 = (qx * cy - qy * cx) / det
        l2 = (bx * qy - by * qx) / det
    lam = np.column_stack([1.0 - l1 - l2, l1, l2])
    lam[det == 0] = -np.inf
    return lam


def node_gradients(
    points: NDArray[np.float64],
    triangles: NDArray[np.int64],
    values: NDArray[np.float64],
    *,
    lonlat: bool = False,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Return the gradient of node values at the nodes, per metre.

    Each triangle's gradient is that of the linear function through its
    corners' values; a node's is the mean of its triangles', weighted by
    their areas. A triangle with a NaN corner counts for nothing (a node with
    none left gets NaN).

    Parameters
    ----------
    points : ndarray of shape (n, 2)
        The nodes: metres, or longitude/latitude degrees with ``lonlat``
        (each triangle then measured in metres on a sphere of radius
        :data:`~coastmesh.geometry.earth.EARTH_RADIUS` around its first
        corner, ``R cos(lat) dlon`` by ``R dlat``, across the antimeridian).
    triangles : ndarray of shape (m, 3)
        Node indices, 0-based.
    values : ndarray of shape (n,)
        One value per node.
    lonlat : bool
        Whether ``points`` are longitude/latitude.

    Returns
    -------
    gx, gy : ndarray of shape (n,)
        The gradient's east (x) and north (y) components.

    Examples
    --------
    >>> pts = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])
    >>> gx, gy = node_gradients(pts, np.array([[0, 1, 2], [1, 3, 2]]),
    ...                         np.array([0.0, 2.0, 3.0, 5.0]))
    >>> gx.tolist(), gy.tolist()
    ([2.0, 2.0, 2.0, 2.0], [3.0, 3.0, 3.0, 3.0])
    """
    p = np.asarray(points, dtype=np.float64)
    tri = np.asarray(triangles, dtype=np.int64)
    v = np.asarray(values, dtype=np.float64)[tri]  # (m, 3)
    d1 = p[tri[:, 1]] - p[tri[:, 0]]
    d2 = p[tri[:, 2]] - p[tri[:, 0]]
    if lonlat:
        d1[:, 0] = (d1[:, 0] + 180.0) % 360.0 - 180.0
        d2[:, 0] = (d2[:, 0] + 180.0) % 360.0 - 180.0
        east = np.radians(1.0) * EARTH_RADIUS * np.cos(np.radians(p[tri[:, 0], 1]))
        north = np.radians(1.0) * EARTH_RADIUS
        d1 *= np.column_stack([east, np.full_like(east, north)])
        d2 *= np.column_stack([east, np.full_like(east, north)])
    det = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]
    f1, f2 = v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        tgx = (f1 * d2[:, 1] - f2 * d1[:, 1]) / det
        tgy = (f2 * d1[:, 0] - f1 * d2[:, 0]) / det
    area = np.abs(det) / 2.0
    good = np.isfinite(tgx) & np.isfinite(tgy) & (area > 0)
    weight = np.where(good, area, 0.0)
    n, nodes = len(p), tri.ravel()
    total = np.bincount(nodes, np.repeat(weight, 3), minlength=n)
    sx = np.bincount(
        nodes, np.repeat(np.where(good, tgx, 0.0) * weight, 3), minlength=n
    )
    sy = np.bincount(
        nodes, np.repeat(np.where(good, tgy, 0.0) * weight, 3), minlength=n
    )
    with np.errstate(divide="ignore", invalid="ignore"):
        return sx / total, sy / total
