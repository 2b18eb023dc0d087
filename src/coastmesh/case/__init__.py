"""Whole cases: a case file or a :class:`CaseConfig` in, a mesh and its outputs out."""

from __future__ import annotations

from coastmesh.case.config import CaseConfig, StudyCase, load_case, parse_case
from coastmesh.case.run import CaseResult, run_case

__all__ = [
    "CaseConfig",
    "CaseResult",
    "StudyCase",
    "load_case",
    "parse_case",
    "run_case",
]
