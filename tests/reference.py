"""Literal, slow reference implementations of the algorithms, step by step.

These follow the issue's contract (the paper's section II) word for word, with
explicit loops and dense linear algebra, so the fast kernels can be checked
against something obviously right. Never import them from the package.
"""

from __future__ import annotations

import math

import numpy as np


def _pca_reconstruct(columns: np.ndarray, modes: int) -> np.ndarray:
    """Centre each column, C = S S^T / M, project on the leading eigenvectors, add
    the mean back. ``columns`` is (L, M); returns the reconstructed (L, M)."""
    means = columns.mean(axis=0)
    s = columns - means[None, :]
    m = s.shape[1]
    cov = s @ s.T / m
    values, vectors = np.linalg.eigh(cov)
    order = np.argsort(values)[::-1]
    a = vectors[:, order[:modes]]
    return a @ (a.T @ s) + means[None, :]


def simplify_contour_reference(coords, window, modes, *, closed):
    """One partition per point, x and y apart, averaging over overlaps."""
    xy = np.asarray(coords, dtype=np.float64)
    n = len(xy)
    if n < window:
        return None
    starts = range(n) if closed else range(n - window + 1)
    members = []  # the point indices of each partition
    for k in starts:
        members.append([(k + i) % n for i in range(window)])
    out = np.empty((n, 2))
    for dim in range(2):
        s = np.empty((window, len(members)))
        for col, idx in enumerate(members):
            for row, p in enumerate(idx):
                s[row, col] = xy[p, dim]
        rebuilt = _pca_reconstruct(s, modes)
        total = np.zeros(n)
        count = np.zeros(n)
        for col, idx in enumerate(members):
            for row, p in enumerate(idx):
                total[p] += rebuilt[row, col]
                count[p] += 1
        out[:, dim] = total / count
    return out


def simplify_raster_reference(values, window, modes):
    """All windows wholly inside the grid with no missing cell, flattened row-major."""
    grid = np.asarray(values, dtype=np.float64)
    wy, wx = (window, window) if np.isscalar(window) else window
    ny, nx = grid.shape
    starts = []
    for ky in range(ny - wy + 1):
        for kx in range(nx - wx + 1):
            block = grid[ky : ky + wy, kx : kx + wx]
            if np.isfinite(block).all():
                starts.append((ky, kx))
    out = grid.copy()
    if not starts:
        return out
    s = np.empty((wy * wx, len(starts)))
    for col, (ky, kx) in enumerate(starts):
        s[:, col] = grid[ky : ky + wy, kx : kx + wx].ravel()
    rebuilt = _pca_reconstruct(s, modes)
    total = np.zeros_like(grid)
    count = np.zeros_like(grid)
    for col, (ky, kx) in enumerate(starts):
        total[ky : ky + wy, kx : kx + wx] += rebuilt[:, col].reshape(wy, wx)
        count[ky : ky + wy, kx : kx + wx] += 1
    covered = count > 0
    out[covered] = total[covered] / count[covered]
    return out


def simplify_contour_dense(coords, window, modes, *, closed):
    """The same literal algorithm with numpy instead of Python loops: it builds the
    L x M partition matrix explicitly, solves the full dense eigenproblem, and
    averages offset by offset. This is the baseline the benchmark measures against."""
    xy = np.asarray(coords, dtype=np.float64)
    n = len(xy)
    if n < window:
        return None
    m = n if closed else n - window + 1
    index = (np.arange(window)[:, None] + np.arange(m)[None, :]) % n  # (L, M)
    out = np.empty((n, 2))
    for dim in range(2):
        rebuilt = _pca_reconstruct(xy[index, dim], modes)
        total = np.zeros(n)
        count = np.zeros(n)
        for row in range(window):
            np.add.at(total, index[row], rebuilt[row])
            np.add.at(count, index[row], 1.0)
        out[:, dim] = total / count
    return out


def simplify_raster_dense(values, window, modes):
    """Literal raster algorithm with numpy: explicit (L, M) window matrix."""
    grid = np.asarray(values, dtype=np.float64)
    wy, wx = (window, window) if np.isscalar(window) else window
    view = np.lib.stride_tricks.sliding_window_view(grid, (wy, wx))
    valid = np.isfinite(view).all(axis=(2, 3))
    ky, kx = np.nonzero(valid)
    out = grid.copy()
    if len(ky) == 0:
        return out
    s = view[ky, kx].reshape(len(ky), wy * wx).T  # (L, M)
    rebuilt = _pca_reconstruct(s, modes)
    total = np.zeros_like(grid)
    count = np.zeros_like(grid)
    for i in range(wy):
        for j in range(wx):
            np.add.at(total, (ky + i, kx + j), rebuilt[i * wx + j])
            np.add.at(count, (ky + i, kx + j), 1.0)
    covered = count > 0
    out[covered] = total[covered] / count[covered]
    return out


def limit_gradation_brute(size, spacing, rate):
    """Largest field below ``size`` with slope <= ``rate``: min over all cells.

    ``h(p) = min_q size(q) + rate |p - q|`` by the all-pairs distance matrix,
    O(N^2) memory. Returns ``(distances, h)``.
    """
    ny, nx = size.shape
    yy, xx = np.mgrid[0:ny, 0:nx]
    p = np.column_stack([yy.ravel() * spacing[0], xx.ravel() * spacing[1]])
    d = np.hypot(*(p[:, None, :] - p[None, :, :]).transpose(2, 0, 1))
    return d, (size.ravel()[None, :] + rate * d).min(axis=1).reshape(size.shape)


def distance_to_points_geodesic(lon, lat, line_lon, line_lat):
    """Shortest WGS84 geodesic from each (lon, lat) to any of the line's vertices.

    One ``Geod.inv`` call per node against every vertex: the literal reference of
    ``coastmesh.sizing.distance_to_lines`` (densify the lines first).
    """
    from pyproj import Geod

    geod = Geod(ellps="WGS84")
    out = np.empty(len(lon))
    for i, (a, b) in enumerate(zip(lon, lat, strict=True)):
        out[i] = geod.inv(
            np.full_like(line_lon, a), np.full_like(line_lat, b), line_lon, line_lat
        )[2].min()
    return out


def bilinear_loop(rx, ry, values, px, py, *, clamp=False):
    """Bilinear interpolation one point at a time.

    The literal reference of ``coastmesh.geometry.grids.interpolate_bilinear``
    (ascending ``rx``, ``ry``), which depth rasters, size grids and the
    sphere's size grid use: with ``clamp`` a point outside the nodes is first
    moved onto the grid's nearest edge, without it it is NaN; the cell is the
    last whose low corner is at or below the point (the last cell for a point
    on the last column or row); only the corners with a weight count, and the
    value is NaN if one of those is missing.
    """
    out = np.full(len(px), np.nan)
    if len(rx) < 2 or len(ry) < 2:
        return out
    for k, (given_x, given_y) in enumerate(zip(px, py, strict=True)):
        x, y = given_x, given_y
        if clamp:
            x = min(max(x, rx[0]), rx[-1])
            y = min(max(y, ry[0]), ry[-1])
        if not (rx[0] <= x <= rx[-1] and ry[0] <= y <= ry[-1]):
            continue
        i = max(m for m in range(len(rx) - 1) if rx[m] <= x)
        j = max(m for m in range(len(ry) - 1) if ry[m] <= y)
        tx = (x - rx[i]) / (rx[i + 1] - rx[i])
        ty = (y - ry[j]) / (ry[j + 1] - ry[j])
        corners = [
            ((1 - tx) * (1 - ty), values[j, i]),
            (tx * (1 - ty), values[j, i + 1]),
            ((1 - tx) * ty, values[j + 1, i]),
            (tx * ty, values[j + 1, i + 1]),
        ]
        weighted = [(w, v) for w, v in corners if w > 0]
        if any(np.isnan(v) for _, v in weighted):
            continue
        out[k] = sum(w * v for w, v in weighted)
    return out


def nearest_loop(rx, ry, values, px, py):
    """The value of the nearest node, one point at a time.

    The literal reference of ``coastmesh.geometry.grids.interpolate_nearest``
    (ascending ``rx``, ``ry``): along each axis the node at the least distance
    (the lower one at a tie), NaN for a point more than half a cell beyond the
    outer nodes (half the outer spacing on each side; a single node, exactly on
    it).
    """
    out = np.full(len(px), np.nan)

    def node(axis, p):
        if len(axis) == 1:
            return 0 if p == axis[0] else None
        if (
            not axis[0] - (axis[1] - axis[0]) / 2
            <= p
            <= axis[-1] + (axis[-1] - axis[-2]) / 2
        ):
            return None
        distances = [abs(p - a) for a in axis]
        best = min(distances)
        return distances.index(best)

    for k, (x, y) in enumerate(zip(px, py, strict=True)):
        i, j = node(rx, x), node(ry, y)
        if i is not None and j is not None:
            out[k] = values[j, i]
    return out


def rank_channels_loop(labels, width, area, kept):
    """Kept labels, largest area first, numbered 1, 2, ...; each one's widest nodes.

    The literal reference of ``coastmesh.sizing.narrow.rank_channels``: the
    labels ``1 .. len(kept) - 1`` with ``kept`` set, sorted by area, largest
    first (Python's sort is stable: equal areas keep the order of their
    labels); every node of each relabelled; its widest node the first met in
    row-major order, and all its widest nodes (scipy's ``maximum_position``,
    which the fast code uses, may pick any of them).
    """
    chosen = [old for old in range(1, len(kept)) if kept[old]]
    chosen.sort(key=lambda old: -area[old])
    ny, nx = labels.shape
    out = np.zeros((ny, nx), dtype=np.int32)
    found = []
    for new, old in enumerate(chosen, start=1):
        best = None
        for r in range(ny):
            for c in range(nx):
                if labels[r, c] == old:
                    out[r, c] = new
                    if best is None or width[r, c] > width[best]:
                        best = (r, c)
        widest = {
            (r, c)
            for r in range(ny)
            for c in range(nx)
            if labels[r, c] == old and width[r, c] == width[best]
        }
        found.append((best[0], best[1], float(area[old]), float(width[best]), widest))
    return out, found


def plane_scale_from_angle(r, radius):
    """The stereographic scale ``2 / (1 + cos c)`` at the angle ``c`` from the
    plane's centre of a point ``r`` from it in the plane (``r = 2 R tan(c /
    2)``): the literal reference of ``coastmesh.geometry.sphere.plane_scale``."""
    c = 2.0 * math.atan(r / (2.0 * radius))
    return 2.0 / (1.0 + math.cos(c))


def write_fort14_loop(path, mesh, depth, open_strings, land_strings):
    """fort.14 written one line at a time: the literal reference for timing."""
    with open(path, "w") as f:
        f.write("reference\n")
        f.write(f"{len(mesh.triangles)} {len(mesh.points)}\n")
        for k, ((x, y), d) in enumerate(zip(mesh.points, depth, strict=True), 1):
            f.write(f"{k} {x!r} {y!r} {d!r}\n")
        for k, (a, b, c) in enumerate(mesh.triangles, 1):
            f.write(f"{k} 3 {a + 1} {b + 1} {c + 1}\n")
        f.write(f"{len(open_strings)}\n{sum(len(s) for s in open_strings)}\n")
        for s in open_strings:
            f.write(f"{len(s)} 0\n")
            for n in s:
                f.write(f"{n + 1}\n")
        f.write(f"{len(land_strings)}\n{sum(len(s) for s in land_strings)}\n")
        for s in land_strings:
            f.write(f"{len(s)} 0\n")
            for n in s:
                f.write(f"{n + 1}\n")


def bilinear_wet_loop(rx, ry, depth, px, py):
    """Bilinear interpolation over the wet cells alone, one point at a time.

    The literal reference of ``coastmesh.depth.raster.interpolate_wet``: the
    weights of the four cells around a point, renormalised over the cells with
    ``depth > 0``; 0 where every weighted cell is dry; NaN outside the cell
    centres or where a weighted cell is missing.
    """
    out = np.full(len(px), np.nan)
    for k, (x, y) in enumerate(zip(px, py, strict=True)):
        if not (rx[0] <= x <= rx[-1] and ry[0] <= y <= ry[-1]):
            continue
        i = min(int(np.searchsorted(rx, x, side="right")) - 1, len(rx) - 2)
        j = min(int(np.searchsorted(ry, y, side="right")) - 1, len(ry) - 2)
        tx = (x - rx[i]) / (rx[i + 1] - rx[i])
        ty = (y - ry[j]) / (ry[j + 1] - ry[j])
        corners = [
            ((1 - tx) * (1 - ty), depth[j, i]),
            (tx * (1 - ty), depth[j, i + 1]),
            ((1 - tx) * ty, depth[j + 1, i]),
            (tx * ty, depth[j + 1, i + 1]),
        ]
        weighted = [(w, v) for w, v in corners if w > 0]
        if any(np.isnan(v) for _, v in weighted):
            continue
        wet = [(w, v) for w, v in weighted if v > 0]
        total = sum(w for w, _ in wet)
        out[k] = sum(w * v for w, v in wet) / total if wet else 0.0
    return out


def triangles_on_grid_loop(points, triangles, x, y, values, per="node"):
    """Each grid node, each triangle: is the node inside (by the signs of the
    three edge cross products)? Then the linear interpolant through the
    triangle's corners (solved as a 3 x 3 system), or the triangle's value."""
    points = np.asarray(points, dtype=np.float64)
    out = np.full((len(y), len(x)), np.nan)
    inside = np.zeros((len(y), len(x)), dtype=bool)
    for j, py in enumerate(y):
        for i, px in enumerate(x):
            for t, tri in enumerate(triangles):
                a, b, c = points[tri[0]], points[tri[1]], points[tri[2]]
                area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
                if area == 0:
                    continue
                s = []
                for p, q in ((a, b), (b, c), (c, a)):
                    cross = (q[0] - p[0]) * (py - p[1]) - (q[1] - p[1]) * (px - p[0])
                    s.append(cross * np.sign(area))
                if min(s) < -1e-9 * abs(area):
                    continue
                if per == "node":
                    m = np.array(
                        [[a[0], a[1], 1.0], [b[0], b[1], 1.0], [c[0], c[1], 1.0]]
                    )
                    coef = np.linalg.solve(m, np.asarray(values)[list(tri)])
                    out[j, i] = coef[0] * px + coef[1] * py + coef[2]
                else:
                    out[j, i] = values[t]
                inside[j, i] = True
                break
    return out, inside


def node_gradients_loop(points, triangles, values):
    """Each triangle: the plane through its corners' values (a 3 x 3 solve);
    each node: the area-weighted mean of its triangles' slopes."""
    n = len(points)
    sx, sy, total = np.zeros(n), np.zeros(n), np.zeros(n)
    for tri in triangles:
        p = np.asarray(points, dtype=np.float64)[list(tri)]
        v = np.asarray(values, dtype=np.float64)[list(tri)]
        d1, d2 = p[1] - p[0], p[2] - p[0]
        area = abs(d1[0] * d2[1] - d1[1] * d2[0]) / 2
        if area == 0 or not np.isfinite(v).all():
            continue
        coef = np.linalg.solve(np.column_stack([p, np.ones(3)]), v)
        for node in tri:
            sx[node] += coef[0] * area
            sy[node] += coef[1] * area
            total[node] += area
    with np.errstate(invalid="ignore", divide="ignore"):
        return sx / total, sy / total


def size_mapping_loop(kind, values, sizes, exponent, v):
    """The mapping of one value, by the words of its docs."""
    if not np.isfinite(v):
        return np.inf
    if kind == "thresholds":
        size = np.inf
        for threshold, h in zip(values, sizes, strict=False):
            if v >= threshold:
                size = h
        return size
    if kind == "ramp":
        (v0, v1), (h0, h1) = values, sizes
        if h0 >= h1 and h0 != h1 and v < v0:
            return np.inf
        if h0 < h1 and v > v1:
            return np.inf
        if v <= v0:
            return h0
        if v >= v1:
            return h1
        return h0 + (v - v0) / (v1 - v0) * (h1 - h0)
    if v <= 0:
        return np.inf
    with np.errstate(over="ignore"):
        return np.float64(sizes[0]) * (np.float64(v) / values[0]) ** exponent


def cut_hole_reference(points, triangles, polygon, grow=None):
    """The hole a patch cuts, by the words of ``coastmesh.case.patch.cut``.

    Each triangle that meets ``polygon`` goes (one shapely test per triangle);
    or, with ``grow = (removed, hit, nodes)`` (a hole's triangles, how many of
    them met its polygon, and nodes: ``grow_hole``), the hole's triangles and
    every triangle with one of the nodes go.
    Then, again and again until nothing changes, every triangle goes that has a
    node where the hole touches itself (more than two of the hole's boundary
    edges there), or a node on the hole's boundary that kept triangles still
    use and where the removed triangles' angles add up to less than 45
    degrees (a sharp corner of the hole). Returns a dict:

    - ``error``: None, or why the hole is refused: ``"no element"`` meets the
      polygon, ``"in two"`` (the kept triangles are more pieces than the mesh
      was), ``"holes"`` (the removed ones are more than one piece),
      ``"touches itself"`` (a node is still on more than two of the hole's
      boundary edges);
    - ``removed``: bool per triangle;
    - ``edges``: the hole's boundary edges ``(a, b)``, the hole on their left,
      each mapped to True for a seam (a kept triangle has it too);
    - ``inner``: the sorted nodes only removed triangles use, off the hole's
      boundary;
    - ``widened``: how many went though they do not meet the polygon.
    """
    import math

    import shapely

    points = [tuple(map(float, p)) for p in np.asarray(points)]
    triangles = [tuple(int(v) for v in t) for t in np.asarray(triangles)]
    if grow is None:
        removed = [
            shapely.Polygon([points[v] for v in t]).intersects(polygon)
            for t in triangles
        ]
        if not any(removed):
            return {"error": "no element"}
        hit = sum(removed)
    else:
        before, hit, nodes = grow
        nodes = {int(v) for v in nodes}
        removed = [
            bool(before[i]) or any(v in nodes for v in t)
            for i, t in enumerate(triangles)
        ]

    def angle(t, corner):
        a, b, c = (points[t[(corner + k) % 3]] for k in range(3))
        u = (b[0] - a[0], b[1] - a[1])
        v = (c[0] - a[0], c[1] - a[1])
        cos = (u[0] * v[0] + u[1] * v[1]) / (math.hypot(*u) * math.hypot(*v))
        return math.degrees(math.acos(max(-1.0, min(1.0, cos))))

    owners = {}  # each edge: the triangles that have it
    for i, t in enumerate(triangles):
        for a, b in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            owners.setdefault(frozenset((a, b)), []).append(i)

    def hole_edges():
        """The removed triangles' edges no other removed triangle has."""
        out = {}
        for i, t in enumerate(triangles):
            if not removed[i]:
                continue
            for a, b in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
                others = [j for j in owners[frozenset((a, b))] if j != i]
                if not any(removed[j] for j in others):
                    out[(a, b)] = len(others) == 1
        return out

    while True:
        edges = hole_edges()
        opened = set()
        for node in {v for edge in edges for v in edge}:
            if sum(node in edge for edge in edges) > 2:
                opened.add(node)  # the hole touches itself here
            inside = sum(
                angle(t, t.index(node))
                for i, t in enumerate(triangles)
                if removed[i] and node in t
            )
            kept = any(node in t for i, t in enumerate(triangles) if not removed[i])
            if kept and inside < 45.0:
                opened.add(node)  # a sharp corner
        more = [
            i
            for i, t in enumerate(triangles)
            if not removed[i] and any(v in opened for v in t)
        ]
        if not more:
            break
        for i in more:
            removed[i] = True

    def pieces(chosen):
        """Groups of the chosen triangles joined through shared edges."""
        left, count = set(chosen), 0
        while left:
            count += 1
            todo = [left.pop()]
            while todo:
                i = todo.pop()
                for j in list(left):
                    if len(set(triangles[i]) & set(triangles[j])) == 2:
                        left.remove(j)
                        todo.append(j)
        return count

    everything = range(len(triangles))
    if pieces([i for i in everything if not removed[i]]) > pieces(everything):
        return {"error": "in two"}
    if pieces([i for i in everything if removed[i]]) > 1:
        return {"error": "holes"}
    edges = hole_edges()
    if any(sum(v in edge for edge in edges) > 2 for v in range(len(points))):
        return {"error": "touches itself"}
    on_ring = {v for edge in edges for v in edge}
    inner = sorted(
        v
        for v in range(len(points))
        if v not in on_ring
        and any(v in t for i, t in enumerate(triangles) if removed[i])
        and not any(v in t for i, t in enumerate(triangles) if not removed[i])
    )
    return {
        "error": None,
        "removed": np.array(removed),
        "edges": edges,
        "inner": np.array(inner, dtype=np.int64),
        "widened": sum(removed) - hit,
    }


def bridge_loop(mask, segments):
    """Closing of each tile by each segment, ORed: cell by cell, placement by placement.

    ``segments`` are lists of (dy, dx) offsets, each holding (0, 0) and
    symmetric about it. A cell is in a segment's closing when every placement
    of the segment that covers it meets the mask or leaves the tile.
    """
    tiles, rows, cols = mask.shape
    out = mask.copy()
    for t in range(tiles):
        for y in range(rows):
            for x in range(cols):
                if mask[t, y, x]:
                    continue
                for cells in segments:
                    closed = True
                    for oy, ox in cells:  # the placement with (y, x) at offset o
                        hit = False
                        for dy, dx in cells:
                            yy, xx = y - oy + dy, x - ox + dx
                            if (
                                not (0 <= yy < rows and 0 <= xx < cols)
                                or mask[t, yy, xx]
                            ):
                                hit = True
                                break
                        if not hit:
                            closed = False
                            break
                    if closed:
                        out[t, y, x] = True
                        break
    return out
