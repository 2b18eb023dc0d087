"""Open boundaries: one class per kind, each with its keys and its geometry.

==========================  ===================================================
:class:`LoxodromeBoundary`  ``kind = "loxodrome"``: a rhumb line on WGS84
:class:`BlendBoundary`      ``kind = "blend"``: the paper's blended loxodromes
:class:`GreatCircleBoundary`  ``kind = "great_circle"``: a geodesic
:class:`PolylineBoundary`   ``kind = "polyline"``: points, or a file's line
==========================  ===================================================

Every kind is a :class:`BoundaryConfig` (a name, an ``id``, a ``spacing``) with
keys of its own (:func:`coastmesh.case.schema.key`) and a ``line(crs, spacing)``
method that draws it. A case file's ``kind`` picks the class from
:data:`BOUNDARY_KINDS`. A new kind is a module here and one entry in that tuple.
"""

from __future__ import annotations

from coastmesh.case.boundaries.base import BoundaryConfig
from coastmesh.case.boundaries.blend import BlendBoundary
from coastmesh.case.boundaries.great_circle import GreatCircleBoundary
from coastmesh.case.boundaries.loxodrome import LoxodromeBoundary, LoxodromeConfig
from coastmesh.case.boundaries.polyline import PolylineBoundary

__all__ = [
    "BOUNDARY_KINDS",
    "BlendBoundary",
    "BoundaryConfig",
    "GreatCircleBoundary",
    "LoxodromeBoundary",
    "LoxodromeConfig",
    "PolylineBoundary",
]

#: The open-boundary kinds, by the value of ``kind`` that selects each.
BOUNDARY_KINDS: dict[str, type[BoundaryConfig]] = {
    kind.kind: kind
    for kind in (
        LoxodromeBoundary,
        BlendBoundary,
        GreatCircleBoundary,
        PolylineBoundary,
    )
}
