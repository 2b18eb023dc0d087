"""Reports as data: every report has summary() and to_dict(), and JSON takes it."""

from __future__ import annotations

import dataclasses
import importlib
import json
import pkgutil
from pathlib import Path

import numpy as np
import pytest

import coastmesh
from coastmesh.types import Report
from coastmesh.types.report import json_ready


def _all_reports() -> list[type]:
    for info in pkgutil.walk_packages(coastmesh.__path__, "coastmesh."):
        if not info.name.startswith("coastmesh.cli"):
            importlib.import_module(info.name)
    found, todo = [], list(Report.__subclasses__())
    while todo:
        cls = todo.pop()
        found.append(cls)
        todo += cls.__subclasses__()
    return sorted(found, key=lambda c: c.__qualname__)


REPORTS = _all_reports()


def test_the_package_has_its_reports():
    names = {cls.__name__ for cls in REPORTS}
    assert {
        "CaseReport",
        "QualityReport",
        "CleanupReport",
        "DepthReport",
        "DomainReport",
        "StitchReport",
        "ShorelineReport",
        "RasterReport",
        "ConvertResult",
        "ShorelineStudyResult",
        "BathymetryStudyResult",
    } <= names


@pytest.mark.parametrize("cls", REPORTS, ids=lambda c: c.__qualname__)
def test_every_report_is_a_frozen_dataclass_with_a_summary(cls):
    assert dataclasses.is_dataclass(cls)
    assert cls.__dataclass_params__.frozen
    assert cls.summary is not Report.summary, f"{cls.__name__} has no summary()"


def test_json_ready_converts_what_reports_hold():
    @dataclasses.dataclass(frozen=True, slots=True)
    class Inner(Report):
        value: float

        def summary(self) -> str:
            return str(self.value)

    @dataclasses.dataclass(frozen=True, slots=True)
    class Outer(Report):
        inner: Inner
        by_id: dict[int, int]
        ids: np.ndarray
        path: Path
        missing: float | None
        hidden: int = dataclasses.field(default=0, metadata={"to_dict": False})

        def summary(self) -> str:
            return "outer"

    report = Outer(
        Inner(np.float32(0.5)),
        {2: np.int64(7)},
        np.arange(3),
        Path("a/b"),
        float("nan"),
    )
    data = report.to_dict()
    assert data == {
        "inner": {"value": 0.5},
        "by_id": {"2": 7},
        "ids": [0, 1, 2],
        "path": "a/b",
        "missing": None,
    }
    assert json.loads(json.dumps(data)) == data
    with pytest.raises(TypeError, match="cannot put a object"):
        json_ready(object())
