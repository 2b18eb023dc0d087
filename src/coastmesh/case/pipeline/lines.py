"""``[[lines]]``: lines inside the sea that the mesh follows, with an id.

A cable route, a weir crest, a channel's thalweg, a breakwater's centre line:
:func:`read_lines` reads each (lon/lat points, or a vector file of lines in
any CRS, joined end to end) into the meshing CRS and checks it against the
sea and the site: it lies in the water, clear of the coast and the open
boundaries, crosses no farm or footprint outline, and neither crosses nor
touches another line. The mesher embeds it
(:class:`~coastmesh.meshing.parts.inner.Inner` ``lines``): its edges are mesh
edges, a 1-D physical group of its id in msh files.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import shapely
from pyproj import CRS

from coastmesh.case.config import CaseConfig
from coastmesh.case.pipeline.places import file_place
from coastmesh.errors import ConfigError
from coastmesh.geometry import reproject

__all__ = ["SiteLine", "read_lines"]

_LONLAT = CRS.from_epsg(4326)

#: A line of a site: (name, id, line in the meshing CRS, h or None).
SiteLine = tuple[str, int, shapely.LineString, float | None]


def read_lines(
    config: CaseConfig,
    crs: CRS,
    sea: shapely.Geometry,
    outlines: Sequence[tuple[str, shapely.Polygon]],
) -> tuple[SiteLine, ...]:
    """Return the case's lines in ``crs``, each checked; ``outlines`` by name.

    Raises
    ------
    ConfigError
        Naming the line: not simple, not wholly in the sea (on land, outside
        the domain, across the coast), touching the domain's boundary, across
        a farm's or a footprint's outline (``outlines``), or across or
        touching another line.
    """
    out: list[SiteLine] = []
    for k, ln in enumerate(config.lines):
        where = f"{config.label}: lines[{k}] ({ln.name!r})"
        if ln.points is not None:
            line = reproject(shapely.LineString(ln.points), _LONLAT, crs)
        else:
            assert ln.path is not None  # _validate: points or a path
            line = file_place(
                ln.path, ln.layer, crs, where, dimension=1, what="[[lines]] entry"
            )
        _check(line, where, sea, outlines, out)
        out.append((ln.name, ln.id, line, ln.h))
    return tuple(out)


def _check(
    line: shapely.LineString,
    where: str,
    sea: shapely.Geometry,
    outlines: Sequence[tuple[str, shapely.Polygon]],
    others: list[SiteLine],
) -> None:
    if not line.is_simple or line.length <= 0:
        raise ConfigError(f"{where}: the line crosses itself or has no length")
    if not sea.intersects(line):
        raise ConfigError(
            f"{where}: the line lies on land or outside the domain; a line must "
            "lie in the sea that is meshed"
        )
    if not sea.contains(line):
        outside = line.difference(sea).length
        raise ConfigError(
            f"{where}: the line crosses the coast or an open boundary "
            f"({outside:,.1f} m of it, {outside / line.length:.1%}, lie outside "
            "the sea); a line must lie wholly in the sea that is meshed"
        )
    if sea.boundary.distance(line) <= 0:
        raise ConfigError(
            f"{where}: the line touches the domain's boundary (the coast or an "
            "open boundary); keep its ends in the water, an element away"
        )
    for name, polygon in outlines:
        if polygon.boundary.intersects(line):
            raise ConfigError(f"{where}: the line crosses the outline of {name!r}")
    for name, _, other, _ in others:
        if other.intersects(line):
            raise ConfigError(f"{where}: the line crosses or touches line {name!r}")


def line_coords(lines: Sequence[SiteLine]) -> list[tuple[np.ndarray, int, str]]:
    """Return the lines as :class:`~coastmesh.meshing.parts.inner.Inner` takes them."""
    return [(np.asarray(line.coords), pid, name) for name, pid, line, _ in lines]
