"""Whole cases: a case file or a :class:`CaseConfig` in, a mesh and its outputs out.

=========================  ==================================================
:func:`read_case`          a case file -> :class:`CaseConfig` (or a study)
:func:`parse_case`         case-file text -> :class:`CaseConfig`
:func:`dump_case`          :class:`CaseConfig` -> case-file text
:func:`build_case`         a case -> :class:`CaseResult`, in memory
:func:`domain_size_field`  the size stage alone, on a domain built in Python
:func:`run_case`           build, then :meth:`CaseResult.write`
:class:`CaseConfig`        a whole case, checked when built; its parts below
:class:`CaseResult`        mesh, domain, size field, :class:`CaseReport`
=========================  ==================================================

The parts of a :class:`CaseConfig`, one per table of the case file, are
:class:`ShorelinesConfig`, :class:`ShorelineSetConfig`, :class:`RegionConfig`,
the open-boundary kinds (:class:`LoxodromeBoundary`, :class:`BlendBoundary`
with :class:`LoxodromeConfig`, :class:`GreatCircleBoundary`,
:class:`PolylineBoundary`: each a :class:`BoundaryConfig`),
:class:`DomainConfig`, :class:`SizeConfig` (with a table per size term:
:class:`GradationConfig`, :class:`BathymetryConfig`, :class:`ChannelConfig`,
:class:`CourantConfig`), :class:`MeshConfig`, :class:`NodeDepthConfig`,
:class:`CleanupConfig`, :class:`OutputConfig` and :class:`RunConfig`.
"""

from __future__ import annotations

from coastmesh.case.boundaries import (
    BlendBoundary,
    BoundaryConfig,
    GreatCircleBoundary,
    LoxodromeBoundary,
    LoxodromeConfig,
    PolylineBoundary,
)
from coastmesh.case.build import build_case
from coastmesh.case.config import (
    CaseConfig,
    CleanupConfig,
    DomainConfig,
    MeshConfig,
    NodeDepthConfig,
    OutputConfig,
    RegionConfig,
    RunConfig,
    ShorelinesConfig,
    ShorelineSetConfig,
    SiteConfig,
    SizeConfig,
    StudyCase,
)
from coastmesh.case.dump import dump_case
from coastmesh.case.parse import parse_case, read_case
from coastmesh.case.pipeline.size import domain_size_field
from coastmesh.case.pipeline.state import ShorelineSetReport
from coastmesh.case.report import CaseReport, MeshReport
from coastmesh.case.result import CaseResult
from coastmesh.case.run import run_case
from coastmesh.case.terms import (
    BathymetryConfig,
    ChannelConfig,
    CourantConfig,
    GradationConfig,
)

__all__ = [
    "BathymetryConfig",
    "BlendBoundary",
    "BoundaryConfig",
    "CaseConfig",
    "CaseReport",
    "CaseResult",
    "ChannelConfig",
    "CleanupConfig",
    "CourantConfig",
    "DomainConfig",
    "GradationConfig",
    "GreatCircleBoundary",
    "LoxodromeBoundary",
    "LoxodromeConfig",
    "MeshConfig",
    "MeshReport",
    "NodeDepthConfig",
    "OutputConfig",
    "PolylineBoundary",
    "RegionConfig",
    "RunConfig",
    "ShorelineSetConfig",
    "ShorelineSetReport",
    "ShorelinesConfig",
    "SiteConfig",
    "SizeConfig",
    "StudyCase",
    "build_case",
    "domain_size_field",
    "dump_case",
    "parse_case",
    "read_case",
    "run_case",
]
