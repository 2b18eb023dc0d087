"""Mesh-size fields: the grid they live on, the kernels of the terms, the combination.

=================================  ===========================================
:class:`PlaneGrid`                 a size grid regular in the meshing CRS
:class:`SphereGrid`                a longitude/latitude grid of the world
:func:`combine`                    size terms into one field: by minimum, the
                                   floor, lower bounds, ``h_max``, the limit
:class:`TermSizes`                 what one term asks of the field
:class:`SizeFieldReport`           the grid, the range, each term's report
:func:`size_field`                 gradations from lines, combined by minimum
:class:`Gradation`                 the paper's gradation from a set of lines
:func:`distance_to_lines`          true distances on the Earth, on a grid
:func:`gradation_size`             ``h_min``, ``d_hold``, ``d_grade``, ``h_max``
:func:`limit_gradation`            a bound on the size's slope
:func:`limit_gradation_sphere`     the same on a world grid
:func:`wavelength_size`            elements per tidal wavelength
:func:`slope_size`                 elements per bathymetric slope
:func:`local_width`                the width of the water on a grid
:func:`courant_bounds`             sizes that keep a Courant number in a window
:func:`to_metres`                  ``"10 km"``, ``"0.02 deg"`` to metres
=================================  ===========================================

The size terms of a case (gradations from named boundaries, bathymetry,
channels, Courant) are :mod:`coastmesh.case.terms`, each built on these. Depth
rasters and their sampling are in :mod:`coastmesh.depth`.
"""

from __future__ import annotations

from coastmesh.sizing.bathymetry import M2_PERIOD, slope_size, wavelength_size
from coastmesh.sizing.channel import local_width
from coastmesh.sizing.combine import (
    Applied,
    Combined,
    SizeFieldReport,
    TermSizes,
    combine,
)
from coastmesh.sizing.courant import CourantReport, courant_bounds, wave_speed
from coastmesh.sizing.distance import distance_to_lines
from coastmesh.sizing.field import size_field
from coastmesh.sizing.gradation import (
    DEFAULT_RATE,
    Gradation,
    gradation_size,
    limit_gradation,
)
from coastmesh.sizing.grid import Grid, PlaneGrid, SphereGrid
from coastmesh.sizing.narrow import ChannelReport, NarrowChannel
from coastmesh.sizing.slots import domain_slots
from coastmesh.sizing.sphere import limit_gradation_sphere
from coastmesh.sizing.units import EARTH_RADIUS, to_metres

__all__ = [
    "DEFAULT_RATE",
    "EARTH_RADIUS",
    "M2_PERIOD",
    "Applied",
    "ChannelReport",
    "Combined",
    "CourantReport",
    "Gradation",
    "Grid",
    "NarrowChannel",
    "PlaneGrid",
    "SizeFieldReport",
    "SphereGrid",
    "TermSizes",
    "combine",
    "courant_bounds",
    "distance_to_lines",
    "domain_slots",
    "gradation_size",
    "limit_gradation",
    "limit_gradation_sphere",
    "local_width",
    "size_field",
    "slope_size",
    "to_metres",
    "wave_speed",
    "wavelength_size",
]
