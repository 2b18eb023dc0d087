"""Whether a cut's crossings of the water are clean, and what they cost.

:func:`~coastmesh.meshing.parts.cuts.cut_lines` tries straight cuts and scores
each by :func:`edges_across`: the target edges along its crossings of the
water, plus :data:`PENALTY` for a crossing that would make thin triangles
(too short, ending near a curve's or a cut's end, or meeting the coast at
under :data:`MIN_CROSSING` degrees). :class:`Turned` and :func:`wet` find
the crossings with overlays local to the line.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import shapely
from numpy.typing import NDArray

from coastmesh.geometry.projection import sample_size
from coastmesh.types import SizeGrid

__all__ = [
    "MIN_CROSSING",
    "PENALTY",
    "Coast",
    "Turned",
    "chord_edges",
    "coast_tree",
    "edges_across",
    "near_ends",
    "tight",
    "wet",
]

#: A cut crossing the coast at a smaller angle (degrees), or crossing water
#: under two target edges wide, is penalised by this many edges.
MIN_CROSSING = 35.0
PENALTY = 1e6

#: What a cut's crossings are checked against (:func:`chord_edges`): the
#: coast's R-tree (:func:`coast_tree`), an R-tree of the curves' end points (or
#: None), the ends of the cuts chosen so far, and their crossings of the water.
Coast = tuple[
    shapely.STRtree,
    shapely.STRtree | None,
    list[NDArray[np.float64]],
    list[shapely.LineString],
]


def coast_tree(polygon: shapely.Polygon) -> shapely.STRtree:
    """Return an R-tree of the polygon's boundary, one segment per edge."""
    rings = shapely.get_rings(shapely.get_parts(polygon))
    segments = []
    for ring in rings:
        xy = shapely.get_coordinates(ring)
        segments.append(shapely.linestrings(np.stack([xy[:-1], xy[1:]], axis=1)))
    return shapely.STRtree(np.concatenate(segments))


class Turned:
    """The water turned so that cuts normal to ``direction`` run along y.

    :func:`wet` clips the water to a thin box around an axis-parallel line;
    an oblique line's box would hold most of the water. Turning the water once
    per direction keeps every candidate's overlay local.
    """

    def __init__(self, polygon: Any, direction: tuple[float, float]) -> None:
        c, s = direction
        self.direction = direction
        self.axis = s == 0.0 or c == 0.0
        self.polygon = polygon
        if not self.axis:
            self.forward = np.array([[c, -s], [s, c]])  # xy @ forward: along, across
            self.turned = shapely.transform(polygon, lambda xy: xy @ self.forward)

    def chords(self, line: shapely.LineString) -> list[shapely.LineString]:
        """Return the crossings of the water by ``line``, in its own coordinates."""
        if self.axis:
            crossed = wet(self.polygon, line)
        else:
            xy = shapely.get_coordinates(line) @ self.forward
            xy[:, 0] = xy[:, 0].mean()  # exactly along y, for the thin clip
            back = self.forward.T
            crossed = shapely.transform(
                wet(self.turned, shapely.LineString(xy)), lambda uv: uv @ back
            )
        return [
            g
            for g in shapely.get_parts(crossed)
            if g.geom_type == "LineString" and not g.is_empty
        ]


def wet(polygon: Any, line: shapely.LineString) -> Any:
    """Return the part of ``line`` (straight, along x or y) in ``polygon``.

    The polygon is clipped to a box one map unit around the line first, so the
    overlay sees only the edges near the line: 18 times faster on the NW
    shelf's water (43,000 vertices), the crossings the same to 1e-10 m. A clip
    GEOS cannot overlay (it may be invalid) falls back to the whole polygon.
    """
    x0, y0, x1, y1 = line.bounds
    near = shapely.clip_by_rect(polygon, x0 - 1.0, y0 - 1.0, x1 + 1.0, y1 + 1.0)
    try:
        return shapely.intersection(near, line)
    except shapely.errors.GEOSException:
        return shapely.intersection(polygon, line)


def edges_across(
    grid: SizeGrid, coast: Coast, chords: list[shapely.LineString]
) -> tuple[float, list[shapely.LineString]]:
    """Return the target edges along a cut's crossings (``chords``), plus penalties.

    Each crossing that is not clean (:func:`chord_edges`) adds
    :data:`PENALTY`: it would make thin triangles. The crossings are
    returned too.
    """
    if not chords:
        return np.inf, []  # cuts nothing: never the best
    score = 0.0
    for chord in chords:
        edges, clean = chord_edges(grid, coast, chord)
        score += edges
        if not clean:
            # a penalised line is never cut along (any clean one beats it, and
            # with none the region is not cut): its other chords do not matter
            return score + PENALTY, chords
    return score, chords


def chord_edges(
    grid: SizeGrid, coast: Coast, chord: shapely.LineString
) -> tuple[float, bool]:
    """Return the target edges along one crossing, and whether it is clean.

    A crossing is not clean (it would make thin triangles) if it is shorter
    than two target edges, ends within half a target edge of one of
    ``coast[1]``'s points or within one of an earlier cut's end (``coast[2]``),
    or comes nearer the coast or an earlier cut (``coast[0]``, ``coast[3]``)
    than ``sin(35 deg) min(s, 2 h)`` at a distance ``s >= 2 h`` from its
    nearer end (it meets the coast at under 35 degrees, or runs along it).
    """
    a, b = np.asarray(chord.coords)[[0, -1]]
    length = float(np.hypot(*(b - a)))
    h_ends = sample_size(grid, np.stack([a, b]))
    n = int(np.clip(2.0 * length / h_ends.min(), 16, 512))
    t = np.linspace(0.0, 1.0, n + 1)
    xy = a + t[:, None] * (b - a)
    h = sample_size(grid, xy)
    edges = float(length * np.mean(1.0 / h))
    clean = not (
        edges < 2.0 or near_ends(coast, a, b, h_ends) or tight(coast, xy, h, t, length)
    )
    return edges, clean


def near_ends(
    coast: Coast,
    a: NDArray[np.float64],
    b: NDArray[np.float64],
    h_ends: NDArray[np.float64],
) -> bool:
    """Whether a chord ends near a curve's end (half an edge) or a cut's (an edge)."""
    if coast[1] is not None:
        _, to_end = coast[1].query_nearest(
            shapely.points([a, b]), return_distance=True, all_matches=False
        )
        if (to_end < 0.5 * h_ends).any():
            return True
    if coast[2]:  # two cuts meeting a third within h leave a sliver of it
        joints = np.asarray(coast[2])
        gaps = np.hypot(*(joints[None, :, :] - np.stack([a, b])[:, None, :]).T)
        return bool((gaps.T.min(axis=1) < h_ends).any())
    return False


def tight(
    coast: Coast,
    xy: NDArray[np.float64],
    h: NDArray[np.float64],
    t: NDArray[np.float64],
    length: float,
) -> bool:
    """Whether a chord comes nearer the coast or a cut than ``sin(35 deg) min(s, 2 h)``.

    Only points at ``s >= 2 h`` from the nearer end count: within two target
    edges of its ends the coast's own roughness (below the size: the resampled
    boundary has two points per edge) is noise. Each point asks the R-tree for
    coast within its own limit only (``dwithin``), not for its nearest edge.
    """
    s = length * np.minimum(t, 1.0 - t)
    need = np.sin(np.radians(MIN_CROSSING)) * np.minimum(s, 2.0 * h)
    far = (s >= 2.0 * h)[1:-1]
    points, limit = xy[1:-1][far], 0.999 * need[1:-1][far]
    if not len(points):
        return False
    near = coast[0].query(shapely.points(points), predicate="dwithin", distance=limit)
    if near.shape[1]:
        return True
    if coast[3]:  # earlier cuts count as coast: no thin strip between cuts
        earlier = shapely.multilinestrings(coast[3])
        return bool(shapely.dwithin(earlier, shapely.points(points), limit).any())
    return False
