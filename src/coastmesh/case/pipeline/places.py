"""Places of a site read from a vector file: one polygon, or one line.

``[[farms]]``, ``[[structures]]`` and ``[[lines]]`` each take ``path`` (any
vector file GDAL reads, in its own CRS) and ``layer`` as well as inline lon/lat
points. :func:`file_place` reads the file's polygons (made valid and unioned)
or lines (joined end to end) into one shape in the CRS asked for, and refuses
a file whose shapes do not make one.
"""

from __future__ import annotations

from pathlib import Path

import shapely
from pyproj import CRS

from coastmesh.errors import ConfigError, InputDataError
from coastmesh.geometry import reproject
from coastmesh.io.vectors.vector import read_features

__all__ = ["file_place"]

#: by dimension: (the shapes' word, the one shape's type, joined how, the parts)
_KINDS = {
    2: ("polygons", "Polygon", "areas"),
    1: ("lines", "LineString", "lines"),
}


def file_place(
    path: Path, layer: str | None, crs: CRS, where: str, *, dimension: int, what: str
) -> shapely.Polygon | shapely.LineString:
    """Return the one polygon (``dimension`` 2) or line (1) of a file, in ``crs``.

    Polygons are made valid and unioned; lines are unioned and joined end to
    end. ``what`` names the entry one shape is for (``"farm"``, ``"[[lines]]
    entry"``) in the error for a file whose shapes make several.

    Raises
    ------
    InputDataError
        If the file has no shape of that dimension.
    ConfigError
        If its shapes make more than one.
    """
    word, kind, parts = _KINDS[dimension]
    features = read_features(path, layer=layer)
    geometry = features.geometry[~shapely.is_missing(features.geometry)]
    shapes = geometry[shapely.get_dimensions(geometry) == dimension]
    if not len(shapes):
        raise InputDataError(f"{where}: {path} has no {word}", path=str(path))
    if dimension == 2:
        one = shapely.union_all(shapely.make_valid(shapes))
    else:
        one = shapely.line_merge(shapely.union_all(shapes))
    if features.crs is not None:
        one = reproject(one, features.crs, crs)
    if one.geom_type != kind:
        raise ConfigError(
            f"{where}: the {word} of {path} make {len(shapely.get_parts(one))} "
            f"separate {parts}; give one {what} per {parts[:-1]}"
        )
    return one
