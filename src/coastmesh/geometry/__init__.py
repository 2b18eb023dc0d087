"""Geometry: shoreline approximation, loxodromes on WGS84, model domains."""

from __future__ import annotations

from coastmesh.geometry.domain import (
    DomainReport,
    OpenBoundary,
    build_domain,
    polygon_areas,
)
from coastmesh.geometry.rhumb import (
    Loxodrome,
    blend_loxodromes,
    great_circle,
    paper_bearing,
)
from coastmesh.geometry.shoreline import (
    ShorelineReport,
    check_coordinates,
    densify_long_edges,
    land_polygons,
    simplify_shorelines,
)

__all__ = [
    "DomainReport",
    "Loxodrome",
    "OpenBoundary",
    "ShorelineReport",
    "blend_loxodromes",
    "build_domain",
    "check_coordinates",
    "densify_long_edges",
    "great_circle",
    "land_polygons",
    "paper_bearing",
    "polygon_areas",
    "simplify_shorelines",
]
