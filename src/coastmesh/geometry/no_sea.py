"""Why the shorelines and open boundaries enclose no sea: the error that says so.

:func:`~coastmesh.geometry.build_domain` raises :func:`no_sea_error` when the
noded coast and open boundaries make no sea face. The error names what leaves
the water open:

- an open boundary that lies wholly on land;
- a loose end: one farther than :data:`REACH` from land and from the other
  open boundaries, unless it lies past a crossing. An end that overshoots
  another open boundary (walking in from the end, the first thing the line
  meets is that boundary, and it meets something else farther on) is a
  dangle the domain drops: it leaves nothing open;
- with no loose end, the land the open boundaries reach: when it is in pieces
  that no coast joins within the shoreline data, the sea runs out between
  them. A coast contoured from a DEM at a higher level has less land, and its
  pieces can part where the land between them is lower than the level.

When there is sea, but not around the seed, :func:`open_water_exits` says
where the seed's water runs out of the shoreline data (a fjord or strait cut
by the data's edge, with no open boundary across it).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
import shapely
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.errors import InputDataError
from coastmesh.geometry.earth import metres_per_unit, reproject_points

if TYPE_CHECKING:
    from coastmesh.geometry.domain import OpenBoundary

__all__ = ["REACH", "no_sea_error", "open_water_exits"]

#: An open boundary's end farther than this from land and from the other open
#: boundaries (metres) leaves the water open there, unless it lies past a crossing.
REACH = 1.0


def no_sea_error(
    land: shapely.Geometry, open_boundaries: Sequence[OpenBoundary], crs: CRS
) -> InputDataError:
    """Return the error for shorelines and open boundaries that close no water.

    Parameters
    ----------
    land : shapely (Multi)Polygon
        The merged land, in ``crs``.
    open_boundaries : sequence of OpenBoundary
        The open boundaries, in ``crs``.
    crs : pyproj.CRS
        Their CRS; places are given in lon/lat, distances in km.

    Returns
    -------
    InputDataError
        Its message names each loose end (in lon/lat, with how far it stops
        short) and each boundary wholly on land; or, when there is none, the
        pieces of land the open boundaries reach.
    """
    faults = _loose_ends(land, open_boundaries, crs)
    if not open_boundaries:
        faults.append("there are no open boundaries")
    if faults:
        return InputDataError(
            f"the shorelines and open boundaries enclose no sea: {'; '.join(faults)}. "
            "An open boundary must cross the coast, or meet another open boundary, "
            "at both ends"
        )
    lines = [shapely.LineString(b.coords) for b in open_boundaries]
    return InputDataError(
        "the shorelines and open boundaries enclose no sea: "
        f"{_unclosed(land, lines, open_boundaries, crs)}. The sea must be closed "
        "all round, by the coast and the open boundaries"
    )


def _loose_ends(
    land: shapely.Geometry, open_boundaries: Sequence[OpenBoundary], crs: CRS
) -> list[str]:
    """Name each open boundary wholly on land, and each loose end (lon/lat)."""
    lines = [shapely.LineString(b.coords) for b in open_boundaries]
    coast = shapely.boundary(land)
    unit = metres_per_unit(crs)
    faults = []
    for i, (boundary, line) in enumerate(zip(open_boundaries, lines, strict=True)):
        label = f"open boundary {boundary.name!r} (id {boundary.physical_id})"
        if shapely.covered_by(line, land):
            faults.append(f"{label} lies wholly on land")
            continue
        if line.is_closed:  # a loop: no loose end
            continue
        others = [*lines[:i], *lines[i + 1 :]]
        xy = np.asarray(boundary.coords, dtype=np.float64)[[0, -1]]
        ends = shapely.points(xy)
        gaps = np.min([shapely.distance(g, ends) for g in [land, *others]], axis=0)
        gaps = gaps * unit
        meets = _meetings(line, coast, others)
        lonlat = reproject_points(xy, crs, "EPSG:4326")
        faults += [
            f"{label} ends at ({lon:.4f}, {lat:.4f}) (lon, lat), {gap / 1000:.3g} km "
            "from land and the other open boundaries"
            for end, ((lon, lat), gap) in enumerate(zip(lonlat, gaps, strict=True))
            if gap > REACH and not _past_crossing(meets, end, line.length)
        ]
    return faults


def _meetings(
    line: shapely.LineString, coast: shapely.Geometry, others: list[shapely.LineString]
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Return where ``line`` meets the coast or another open boundary.

    The distances along it (CRS units) of the points it shares with them, and
    whether each is on another open boundary.
    """
    where, on_open = [], []
    for geometry, is_open in [(coast, False), *((o, True) for o in others)]:
        shared = shapely.get_coordinates(shapely.intersection(line, geometry))
        if len(shared):
            where.append(shapely.line_locate_point(line, shapely.points(shared)))
            on_open.append(np.full(len(shared), is_open))
    if not where:
        return np.empty(0), np.empty(0, dtype=bool)
    return np.concatenate(where), np.concatenate(on_open)


def _past_crossing(
    meets: tuple[NDArray[np.float64], NDArray[np.bool_]], end: int, length: float
) -> bool:
    """Whether the line's ``end`` (0: start, 1: end) overshoots an open boundary.

    Walking in from that end, the first point the line shares with anything is
    on another open boundary, and the line meets something farther on: the
    stretch beyond the crossing is a dangle, and the line closes the water
    between its meetings.
    """
    where, on_open = meets
    if len(where) == 0:
        return False
    first = int(np.argmin(where) if end == 0 else np.argmax(where))
    farther = np.abs(where - where[first]) > 1e-9 * length
    return bool(on_open[first] and farther.any())


def _unclosed(
    land: shapely.Geometry,
    lines: list[shapely.LineString],
    open_boundaries: Sequence[OpenBoundary],
    crs: CRS,
) -> str:
    """Say why boundaries with no loose end close no water: the land they reach.

    The boundaries and the pieces of land are the nodes of a graph; a boundary
    is joined to each boundary it meets and, once per stretch of it on land, to
    that piece of land. Water is closed only round a ring of that graph. With
    none, the pieces the boundaries end on (else all they reach) are named,
    each where a boundary comes ashore.
    """
    pieces = shapely.get_parts(land)
    n = len(lines)
    edges = [
        (i, j)
        for i in range(n)
        for j in range(i + 1, n)
        if lines[i].intersects(lines[j])
    ]
    landfalls: dict[int, tuple[int, NDArray[np.float64]]] = {}
    tree = shapely.STRtree(pieces)
    for i, line in enumerate(lines):
        for k in tree.query(line, predicate="intersects"):
            stretches = shapely.get_parts(
                shapely.line_merge(shapely.intersection(line, pieces[k]))
            )
            edges += [(i, n + int(k))] * len(stretches)
            if int(k) not in landfalls:
                at = shapely.get_coordinates(
                    shapely.intersection(line, shapely.boundary(pieces[k]))
                )
                landfalls[int(k)] = (i, at[0] if len(at) else line.coords[0])
    if _has_ring(n + len(pieces), edges):
        return (
            "each open boundary reaches land or another open boundary, and they "
            "make a ring with the coast, but it encloses land only"
        )
    if len(landfalls) < 2:
        return (
            "each open boundary reaches land or another open boundary, but with the "
            "coast they make no closed ring"
        )
    ends = shapely.points(
        np.concatenate([np.asarray(g.coords)[[0, -1]] for g in lines])
    )
    ending = {int(k) for k in tree.query(ends, predicate="within")[1]}
    if len(ending & set(landfalls)) >= 2:  # the land the boundaries end on
        landfalls = {k: v for k, v in landfalls.items() if k in ending}
    xy = np.array([at for _, at in landfalls.values()])
    lonlat = reproject_points(xy, crs, "EPSG:4326")
    where = ", ".join(
        f"{open_boundaries[i].name!r} at ({lon:.4f}, {lat:.4f})"
        for (i, _), (lon, lat) in zip(landfalls.values(), lonlat, strict=True)
    )
    return (
        "each open boundary reaches land or crosses another open boundary, but the "
        f"land they reach is {len(landfalls)} pieces that no coast joins within the "
        f"shoreline data ({where}, lon/lat), so the sea runs out between them (a "
        "coast contoured from a DEM at a higher level has less land: its pieces "
        "part where the land between them is below the level)"
    )


def _has_ring(nodes: int, edges: list[tuple[int, int]]) -> bool:
    """Whether the multigraph with these edges has a cycle (union-find)."""
    parent = list(range(nodes))

    def root(a: int) -> int:
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    for a, b in edges:
        ra, rb = root(a), root(b)
        if ra == rb:
            return True
        parent[ra] = rb
    return False


#: Places named in :func:`open_water_exits`'s text.
_EXITS_SHOWN = 3


def open_water_exits(
    seed: tuple[float, float],
    land: shapely.Geometry,
    open_boundaries: Sequence[OpenBoundary],
    crs: CRS,
) -> str:
    """Say where the water around ``seed`` runs out of the shoreline data.

    The data's frame is the box round the land and the open boundaries. Noded
    with it, the coast and the open boundaries split the frame into faces; the
    seed's, when no sea face holds the seed, reaches the frame where the frame
    is not on land: there its water runs out (a fjord cut by a shoreline file's
    box, a strait with no open boundary across it).

    Parameters
    ----------
    seed : (float, float)
        The seed, in ``crs``.
    land : shapely (Multi)Polygon
        The merged land, in ``crs``.
    open_boundaries : sequence of OpenBoundary
        The open boundaries, in ``crs``.
    crs : pyproj.CRS
        Their CRS; places are given in lon/lat.

    Returns
    -------
    str
        The loose ends of the open boundaries, if any (as
        :func:`no_sea_error` names them: the water most likely runs round
        them); else ``"the water around it runs out of the shoreline data at N
        places, the nearest at (lon, lat), ..."``, nearest the seed first;
        empty when no such place is found.

    Examples
    --------
    >>> land = shapely.box(0, 0, 10, 4).union(shapely.box(0, 6, 10, 10))
    >>> open_water_exits((5.0, 5.0), land, [], CRS.from_epsg(3857))[:64]
    'the water around it runs out of the shoreline data at 2 places, '
    """
    loose = _loose_ends(land, open_boundaries, crs)
    if loose:
        return (
            f"{'; '.join(loose)}: the water runs round "
            f"{'them' if len(loose) > 1 else 'it'}. An open boundary must cross "
            "the coast, or meet another open boundary, at both ends"
        )
    lines = [shapely.LineString(b.coords) for b in open_boundaries]
    frame = shapely.envelope(shapely.union_all([land, *lines]))
    linework = shapely.node(
        shapely.union_all([shapely.boundary(land), *lines, shapely.boundary(frame)])
    )
    faces = shapely.get_parts(shapely.polygonize(shapely.get_parts(linework)))
    point = shapely.Point(seed)
    holding = [f for f in faces if shapely.covers(f, point)]
    if not holding:
        return ""
    gaps = shapely.intersection(
        shapely.difference(shapely.boundary(frame), land), holding[0]
    )
    parts = (
        [g for g in shapely.get_parts(shapely.line_merge(gaps)) if g.length > 0]
        if not gaps.is_empty
        else []
    )
    if not parts:
        return ""
    mids = shapely.line_interpolate_point(parts, 0.5, normalized=True)
    xy = shapely.get_coordinates(mids)
    order = np.argsort(np.hypot(xy[:, 0] - seed[0], xy[:, 1] - seed[1]))
    lonlat = reproject_points(xy[order[:_EXITS_SHOWN]], crs, "EPSG:4326")
    where = ", ".join(f"({lon:.4f}, {lat:.4f})" for lon, lat in lonlat)
    nearest = "the nearest at " if len(parts) > 1 else ""
    return (
        f"the water around it runs out of the shoreline data at {len(parts)} "
        f"place{'s' if len(parts) > 1 else ''}, {nearest}{where} (lon, lat): "
        "widen the shorelines there (their bbox or file), or close that water "
        "with an open boundary"
    )
