"""Geometry on shapely arrays: shoreline approximation, and later domains."""

from __future__ import annotations

from coastmesh.geometry.shoreline import ShorelineReport, simplify_shorelines

__all__ = ["ShorelineReport", "simplify_shorelines"]
