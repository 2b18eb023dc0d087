"""Geometry: shorelines, loxodromes on WGS84, model domains, and the Earth.

========================  =====================================================
:mod:`.shoreline`         PCA approximation of whole shoreline layers
:mod:`.layers`            checks, repairs and densifying of shoreline layers
:mod:`.dem`               land polygons contoured from an elevation grid
:mod:`.stitch`            one land geometry from shoreline sets by region
:mod:`.rhumb`             loxodromes and great circles for open boundaries
:mod:`.domain`            the sea polygon and its tagged boundary
:mod:`.no_sea`            why a coast and open boundaries enclose no sea
:mod:`.earth`             reprojection, earth-centred coordinates, lengths
:mod:`.projection`        the conformal CRS meshes are made in, scale factors
:mod:`.sphere`            lon/lat and vectors, the stereographic plane
:mod:`.world`             the world ocean in a stereographic plane
:mod:`.closing`           narrow water closed, on rasters of that plane
:mod:`.cells`             land on cells: winding numbers, morphology, tracing
:mod:`.grids`             regular grids: the cell of a point, bilinear values
:mod:`.inlets`            narrow inlets found along a coast, cut off
:mod:`.unions`            unions of many polygons that overlay only what meets
========================  =====================================================
"""

from __future__ import annotations

from coastmesh.geometry.closing import close_narrow_water
from coastmesh.geometry.dem import land_from_grid
from coastmesh.geometry.domain import (
    DomainReport,
    OpenBoundary,
    build_domain,
    domain_with_land,
    domain_with_structures,
    polygon_areas,
    smaller_than,
)
from coastmesh.geometry.earth import (
    EARTH_RADIUS,
    METRES_PER_DEGREE,
    arc_lengths,
    earth_centred,
    metres_per_unit,
    reproject,
    reproject_points,
    transformer,
)
from coastmesh.geometry.grids import interpolate_bilinear
from coastmesh.geometry.layers import (
    check_coordinates,
    densify_long_edges,
    land_polygons,
    valid_polygons,
)
from coastmesh.geometry.rhumb import (
    Loxodrome,
    blend_loxodromes,
    great_circle,
    paper_bearing,
)
from coastmesh.geometry.shoreline import ShorelineReport, simplify_shorelines
from coastmesh.geometry.sphere import plane_crs
from coastmesh.geometry.stitch import ShorelineSet, StitchReport, stitch_shorelines
from coastmesh.geometry.world import (
    WorldLand,
    WorldOcean,
    join_dateline,
    polar_ring,
    world_land,
    world_ocean,
)

__all__ = [
    "EARTH_RADIUS",
    "METRES_PER_DEGREE",
    "DomainReport",
    "Loxodrome",
    "OpenBoundary",
    "ShorelineReport",
    "ShorelineSet",
    "StitchReport",
    "WorldLand",
    "WorldOcean",
    "arc_lengths",
    "blend_loxodromes",
    "build_domain",
    "check_coordinates",
    "close_narrow_water",
    "densify_long_edges",
    "domain_with_land",
    "domain_with_structures",
    "earth_centred",
    "great_circle",
    "interpolate_bilinear",
    "join_dateline",
    "land_from_grid",
    "land_polygons",
    "metres_per_unit",
    "paper_bearing",
    "plane_crs",
    "polar_ring",
    "polygon_areas",
    "reproject",
    "reproject_points",
    "simplify_shorelines",
    "smaller_than",
    "stitch_shorelines",
    "transformer",
    "valid_polygons",
    "world_land",
    "world_ocean",
]
