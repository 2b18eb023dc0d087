"""Geometry: shoreline approximation on shapely arrays, loxodromes on WGS84."""

from __future__ import annotations

from coastmesh.geometry.rhumb import Loxodrome, blend_loxodromes, paper_bearing
from coastmesh.geometry.shoreline import (
    ShorelineReport,
    check_coordinates,
    simplify_shorelines,
)

__all__ = [
    "Loxodrome",
    "ShorelineReport",
    "blend_loxodromes",
    "check_coordinates",
    "paper_bearing",
    "simplify_shorelines",
]
