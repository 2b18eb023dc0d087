"""Slots: water narrower than a width, to be closed as land before meshing."""

from __future__ import annotations

import numpy as np
import shapely
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.geometry.earth import reproject
from coastmesh.sizing.channel import slots
from coastmesh.sizing.terms import projected
from coastmesh.types import Domain

__all__ = ["domain_slots", "off_open_boundaries"]


def domain_slots(
    domain: Domain, mesh_crs: CRS | str, width: float
) -> NDArray[np.object_]:
    """Return the slots of the domain's water narrower than ``width``, as land.

    :func:`~coastmesh.sizing.channel.slots` of the domain (in ``mesh_crs``,
    metres), grown by ``width / 10`` so that they overlap the land, in the
    domain's CRS; none that touches an open boundary (it must still cross the
    coast there to close the domain). :func:`coastmesh.build_case` closes the
    slots narrower than half of ``h_min`` whatever ``narrow`` says: no element
    fits in them, and their tips make the worst elements of a mesh.
    """
    mesh_crs = CRS.from_user_input(mesh_crs)
    thin = slots(projected(domain, [domain.polygon], mesh_crs)[0], width)
    if not len(thin):
        return thin
    grown = reproject(shapely.buffer(thin, width / 10), mesh_crs, domain.crs)
    return off_open_boundaries(grown, domain)


def off_open_boundaries(
    polygons: NDArray[np.object_], domain: Domain
) -> NDArray[np.object_]:
    """Drop the polygons that touch an open boundary of the domain."""
    opened = [shapely.LineString(s.coords) for s in domain.segments if s.kind == "open"]
    if not opened or not len(polygons):
        return polygons
    return polygons[~shapely.intersects(polygons, shapely.union_all(opened))]
