"""Size terms: each term of the size field a module, registered in ``SizeConfig``.

===================  =======================================================
:class:`Gradations`  ``[[mesh_size.gradations]]``: the paper's gradations
:class:`Bathymetry`  ``[mesh_size.bathymetry]``: tidal wavelength and slope
:class:`Channels`    ``[mesh_size.channels]``: elements across every channel
:class:`Courant`     ``[mesh_size.courant]``: sizes a model runs at its step
:class:`Fields`      ``[[mesh_size.fields]]``: sizes from a raster or results
===================  =======================================================

A term is a :class:`SizeTerm` with its config class. A new term is a module
here and its line in :class:`~coastmesh.case.config.SizeConfig` (its key of
``[mesh_size]``, :func:`~coastmesh.case.config.sizes.term_key`): the registry,
whose order is the order the terms' sizes are applied
(:data:`coastmesh.case.config.TERMS`).
"""

from __future__ import annotations

from coastmesh.case.terms.base import AnyTerm, SizeTerm
from coastmesh.case.terms.bathymetry import Bathymetry, BathymetryConfig
from coastmesh.case.terms.channels import ChannelConfig, Channels
from coastmesh.case.terms.courant import Courant, CourantConfig
from coastmesh.case.terms.fields import FieldConfig, Fields
from coastmesh.case.terms.gradations import GradationConfig, Gradations

__all__ = [
    "AnyTerm",
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
