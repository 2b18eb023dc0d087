"""Mesh-size fields: gradation from shoreline sets, bathymetry terms, limits.

=================================  ===========================================
:func:`domain_size_field`          the size over a whole domain: gradations
                                   from named boundaries, bathymetry terms,
                                   floor, ceiling and gradation limit
:class:`BoundaryGradation`         a gradation from named boundary segments
:func:`size_field_with_report`     the same, with the report of every term
:class:`BathymetrySize`            wavelength and slope terms from a raster
:class:`ChannelSize`               elements across every channel (on by
                                   default)
:class:`CourantSize`               a Courant-number window at a time step
:func:`local_width`                the width of the water on a grid
:func:`domain_width`               the width of a domain's water
:func:`size_field`                 gradations from lines, combined by minimum
:class:`Gradation`                 the paper's gradation from a set of lines
:func:`distance_to_lines`          true distances on the Earth, on a grid
:func:`gradation_size`             ``h_min``, ``d_hold``, ``d_grade``, ``h_max``
:func:`limit_gradation`            a bound on the size's slope
:func:`wavelength_size`            elements per tidal wavelength
:func:`slope_size`                 elements per bathymetric slope
:func:`to_metres`                  ``"10 km"``, ``"0.02 deg"`` to metres
=================================  ===========================================

Depth rasters and their sampling are in :mod:`coastmesh.depth`.
"""

from __future__ import annotations

from coastmesh.sizing.bathymetry import M2_PERIOD, slope_size, wavelength_size
from coastmesh.sizing.channel import ChannelReport, NarrowChannel, local_width
from coastmesh.sizing.distance import distance_to_lines
from coastmesh.sizing.domain import (
    BathymetrySize,
    BoundaryGradation,
    SizeField,
    SizeFieldReport,
    domain_size_field,
    domain_slots,
    size_field_with_report,
)
from coastmesh.sizing.field import Gradation, size_field
from coastmesh.sizing.gradation import DEFAULT_RATE, gradation_size, limit_gradation
from coastmesh.sizing.sphere import limit_gradation_sphere, sphere_size_field
from coastmesh.sizing.terms import (
    ChannelSize,
    CourantReport,
    CourantSize,
    courant_bounds,
    domain_width,
)
from coastmesh.sizing.units import EARTH_RADIUS, to_metres

__all__ = [
    "DEFAULT_RATE",
    "EARTH_RADIUS",
    "M2_PERIOD",
    "BathymetrySize",
    "BoundaryGradation",
    "ChannelReport",
    "ChannelSize",
    "CourantReport",
    "CourantSize",
    "Gradation",
    "NarrowChannel",
    "SizeField",
    "SizeFieldReport",
    "courant_bounds",
    "distance_to_lines",
    "domain_size_field",
    "domain_slots",
    "domain_width",
    "gradation_size",
    "limit_gradation",
    "limit_gradation_sphere",
    "local_width",
    "size_field",
    "size_field_with_report",
    "slope_size",
    "sphere_size_field",
    "to_metres",
    "wavelength_size",
]
