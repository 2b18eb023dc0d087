"""Geometry on shapely arrays: shoreline approximation, and later domains."""

from __future__ import annotations

from coastmesh.geometry.shoreline import (
    ShorelineReport,
    check_coordinates,
    simplify_shorelines,
)

__all__ = ["ShorelineReport", "check_coordinates", "simplify_shorelines"]
