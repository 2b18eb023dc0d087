"""Size terms: each term of the size field a module, registered in :data:`TERMS`.

===================  =======================================================
:class:`Gradations`  ``[[mesh_size.gradations]]``: the paper's gradations
:class:`Bathymetry`  ``[mesh_size.bathymetry]``: tidal wavelength and slope
:class:`Channels`    ``[mesh_size.channels]``: elements across every channel
:class:`Courant`     ``[mesh_size.courant]``: sizes a model runs at its step
:class:`Fields`      ``[[mesh_size.fields]]``: sizes from a raster or results
===================  =======================================================

A term is a :class:`SizeTerm` with its config class. ``[mesh_size]`` has a key
per term in this list, in this order. A new term is a module here and one entry
in :data:`TERMS`.
"""

from __future__ import annotations

from typing import Any

from coastmesh.case.terms.base import SizeTerm
from coastmesh.case.terms.bathymetry import Bathymetry, BathymetryConfig
from coastmesh.case.terms.channels import ChannelConfig, Channels
from coastmesh.case.terms.courant import Courant, CourantConfig
from coastmesh.case.terms.fields import FieldConfig, Fields
from coastmesh.case.terms.gradations import GradationConfig, Gradations

__all__ = [
    "TERMS",
    "Bathymetry",
    "BathymetryConfig",
    "ChannelConfig",
    "Channels",
    "Courant",
    "CourantConfig",
    "FieldConfig",
    "Fields",
    "GradationConfig",
    "Gradations",
    "SizeTerm",
]

#: The size terms, in the order their sizes are applied.
TERMS: tuple[SizeTerm[Any], ...] = (  # each term typed by its settings
    Gradations(),
    Bathymetry(),
    Channels(),
    Courant(),
    Fields(),
)
