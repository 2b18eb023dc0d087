"""A whole case as frozen dataclasses: :class:`CaseConfig` and its parts.

A :class:`CaseConfig` is checked whenever it is built: by the case-file reader
(:func:`coastmesh.read_case`), by hand in Python, or by
:func:`dataclasses.replace`. Each part declares its keys once, on its fields
(:func:`coastmesh.case.schema.key`): their names in the file, how they are
checked, their units and docs. The parts are plain containers until a
``CaseConfig`` holds them.

The field names follow the case file's keys, except where a field says another
key (``physical_id`` is ``id``; ``sets`` is ``[shoreline_sets]``,
``boundaries`` ``[[open_boundaries]]``, ``size`` ``[mesh_size]`` and ``outputs``
``[output]``): ``docs/python-api.md`` lists them. The open-boundary kinds are
in :mod:`coastmesh.case.boundaries`, the size terms' tables in
:mod:`coastmesh.case.terms`.
"""

from __future__ import annotations

from coastmesh.case.config.case import (
    CASE_KINDS,
    PYTHON_SOURCE,
    CaseConfig,
    CaseKeys,
    StudyCase,
)
from coastmesh.case.config.farms import (
    FarmConfig,
    LineConfig,
    RotorLength,
    StructureConfig,
    TurbinesConfig,
    WakeConfig,
)
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
    SiteConfig,
)
from coastmesh.case.config.sizes import (
    TERMS,
    SizeConfig,
    floor,
    term_key,
    terms_of,
    terms_smallest,
)
from coastmesh.case.sources import DepthSourceConfig, RasterConfig

__all__ = [
    "CASE_KINDS",
    "DOCUMENTED",
    "PYTHON_SOURCE",
    "TERMS",
    "CaseConfig",
    "CaseKeys",
    "CleanupConfig",
    "DepthSourceConfig",
    "DomainConfig",
    "FarmConfig",
    "LineConfig",
    "MeshConfig",
    "NodeDepthConfig",
    "OutputConfig",
    "RasterConfig",
    "RegionConfig",
    "RotorLength",
    "RunConfig",
    "ShorelineSetConfig",
    "ShorelinesConfig",
    "SiteConfig",
    "SizeConfig",
    "StructureConfig",
    "StudyCase",
    "TurbinesConfig",
    "WakeConfig",
    "floor",
    "reference_blocks",
    "term_key",
    "terms_of",
    "terms_smallest",
]


def _documented() -> dict[str, type]:
    from coastmesh.case.boundaries import BoundaryConfig, LoxodromeConfig

    classes: list[type] = [
        CaseKeys,
        CaseConfig,
        ShorelinesConfig,
        ShorelineSetConfig,
        RegionConfig,
        SiteConfig,
        FarmConfig,
        TurbinesConfig,
        WakeConfig,
        LineConfig,
        StructureConfig,
        DomainConfig,
        BoundaryConfig,
        LoxodromeConfig,
        SizeConfig,
        MeshConfig,
        RunConfig,
        CleanupConfig,
        NodeDepthConfig,
        DepthSourceConfig,
        OutputConfig,
    ]
    return {kind.__name__: kind for kind in classes}


#: The config classes whose keys ``docs/case-files.md`` lists, by class name (the
#: size terms and the kinds of open boundary have sections of their own:
#: :func:`reference_blocks`).
DOCUMENTED: dict[str, type] = _documented()


def reference_blocks() -> dict[str, str]:
    """Return the generated sections of ``docs/case-files.md``, by marker name.

    ``TERMS``: a section per size term, from its module's docstring and its
    keys; ``BOUNDARY_KINDS``: a section per kind of open boundary, with the
    keys it adds. A new term or kind gets its section from its own module.
    """
    import sys

    from coastmesh.case.boundaries import BOUNDARY_KINDS
    from coastmesh.case.schema.reference import section

    def doc(kind: type) -> tuple[str, str]:
        title, _, body = (sys.modules[kind.__module__].__doc__ or "").partition("\n")
        return title.strip(), body

    terms = [section(*doc(type(t)), t.config) for t in TERMS]
    kinds = [section(*doc(k), k, own=True) for k in BOUNDARY_KINDS.values()]
    return {"TERMS": "\n".join(terms), "BOUNDARY_KINDS": "\n".join(kinds)}
