"""Mesh-size fields: gradation from shoreline sets, combination, gradation limit."""

from __future__ import annotations

from coastmesh.sizing.distance import distance_to_lines
from coastmesh.sizing.field import Gradation, size_field
from coastmesh.sizing.gradation import gradation_size, limit_gradation
from coastmesh.sizing.units import EARTH_RADIUS, to_metres

__all__ = [
    "EARTH_RADIUS",
    "Gradation",
    "distance_to_lines",
    "gradation_size",
    "limit_gradation",
    "size_field",
    "to_metres",
]
