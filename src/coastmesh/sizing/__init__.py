"""Mesh-size fields: gradation from shoreline sets, combination, gradation limit."""

from __future__ import annotations

from coastmesh.sizing.bathymetry import (
    M2_PERIOD,
    depth_on_grid,
    slope_size,
    wavelength_size,
)
from coastmesh.sizing.distance import distance_to_lines
from coastmesh.sizing.field import Gradation, size_field
from coastmesh.sizing.gradation import gradation_size, limit_gradation
from coastmesh.sizing.units import EARTH_RADIUS, to_metres

__all__ = [
    "EARTH_RADIUS",
    "M2_PERIOD",
    "Gradation",
    "depth_on_grid",
    "distance_to_lines",
    "gradation_size",
    "limit_gradation",
    "size_field",
    "slope_size",
    "to_metres",
    "wavelength_size",
]
