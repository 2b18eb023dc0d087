"""A whole case as frozen dataclasses: :class:`CaseConfig` and its parts.

A :class:`CaseConfig` is checked whenever it is built: by the case-file reader
(:func:`coastmesh.read_case`), by hand in Python, or by
:func:`dataclasses.replace`. Every value is checked and converted in
``CaseConfig.__post_init__``, with the same messages as the reader's, naming the
key path of the case file (``open_boundaries[2].spacing``); the parts are
plain containers until a ``CaseConfig`` holds them.

In Python, lengths are numbers of metres or strings with a unit (``"10 km"``,
``"0.02 deg"``), areas square metres or ``"0.5 km2"``, durations seconds or
``"12.42 h"``; paths are strings or :class:`pathlib.Path` (relative paths are
relative to the working folder); sequences may be tuples or lists. The keys of
the case file and their defaults are listed in ``docs/case-files.md``; the
field names here follow them, except ``id`` (``physical_id``),
``[shoreline_sets]`` (``sets``), ``[[open_boundaries]]`` (``boundaries``),
``[mesh_size]`` (``size``) and ``[output]`` (``outputs``).
"""

from __future__ import annotations

from coastmesh.case.config.boundaries import (
    BOUNDARY_KINDS,
    BoundaryConfig,
    LoxodromeConfig,
)
from coastmesh.case.config.case import CASE_KINDS, PYTHON_SOURCE, CaseConfig, StudyCase
from coastmesh.case.config.mesh import (
    CleanupConfig,
    MeshConfig,
    NodeDepthConfig,
    OutputConfig,
    RunConfig,
)
from coastmesh.case.config.shorelines import (
    DomainConfig,
    RegionConfig,
    ShorelinesConfig,
    ShorelineSetConfig,
)
from coastmesh.case.config.sizes import (
    BathymetryConfig,
    ChannelConfig,
    CourantConfig,
    GradationConfig,
    SizeConfig,
)
from coastmesh.case.config.sources import DepthSourceConfig

__all__ = [
    "BOUNDARY_KINDS",
    "CASE_KINDS",
    "PYTHON_SOURCE",
    "BathymetryConfig",
    "BoundaryConfig",
    "CaseConfig",
    "ChannelConfig",
    "CleanupConfig",
    "CourantConfig",
    "DepthSourceConfig",
    "DomainConfig",
    "GradationConfig",
    "LoxodromeConfig",
    "MeshConfig",
    "NodeDepthConfig",
    "OutputConfig",
    "RegionConfig",
    "RunConfig",
    "ShorelineSetConfig",
    "ShorelinesConfig",
    "SizeConfig",
    "StudyCase",
]
