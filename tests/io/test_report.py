"""write_report: a report's to_dict() as JSON and its summary() as text, together."""

from __future__ import annotations

import json
from dataclasses import dataclass

import numpy as np
import pytest

from coastmesh.errors import ConfigError, FormatError, OutputExistsError
from coastmesh.io import write_report
from coastmesh.types import Report


@dataclass(frozen=True, slots=True)
class Counts(Report):
    nodes: int
    sizes: np.ndarray
    note: str = "ok"

    def summary(self) -> str:
        return f"{self.nodes} nodes\nsizes {self.sizes.min()}..{self.sizes.max()}"


@pytest.fixture
def report() -> Counts:
    return Counts(4, np.array([1.5, 2.0]))


def test_json_and_summary(tmp_path, report, folder_listing):
    write_report(tmp_path / "r.json", report, summary=tmp_path / "r.txt")
    assert folder_listing(tmp_path) == ["r.json", "r.txt"]
    text = (tmp_path / "r.json").read_text(encoding="utf-8")
    assert (
        json.loads(text)
        == report.to_dict()
        == {
            "nodes": 4,
            "sizes": [1.5, 2.0],
            "note": "ok",
        }
    )
    assert text.startswith('{\n  "nodes": 4') and text.endswith("}\n")
    assert (tmp_path / "r.txt").read_text() == "4 nodes\nsizes 1.5..2.0\n"


def test_json_alone(tmp_path, report, folder_listing):
    write_report(tmp_path / "sub" / "r.json", report)
    assert folder_listing(tmp_path / "sub") == ["r.json"]


@pytest.mark.parametrize("existing", ["r.json", "r.txt"])
def test_existing_files_are_refused_without_overwrite(
    tmp_path, report, folder_listing, existing
):
    (tmp_path / existing).write_text("mine")
    with pytest.raises(OutputExistsError, match=existing):
        write_report(tmp_path / "r.json", report, summary=tmp_path / "r.txt")
    assert folder_listing(tmp_path) == [existing]
    assert (tmp_path / existing).read_text() == "mine"
    write_report(
        tmp_path / "r.json", report, summary=tmp_path / "r.txt", overwrite=True
    )
    assert folder_listing(tmp_path) == ["r.json", "r.txt"]
    assert (tmp_path / existing).read_text() != "mine"


def test_nothing_is_written_when_the_summary_cannot_be(tmp_path, report):
    (tmp_path / "blocker").write_text("a file where a folder should be")
    with pytest.raises(OSError):
        write_report(
            tmp_path / "r.json", report, summary=tmp_path / "blocker" / "r.txt"
        )
    assert sorted(p.name for p in tmp_path.iterdir()) == ["blocker"]


def test_nothing_is_written_when_a_method_fails(tmp_path, folder_listing):
    @dataclass(frozen=True, slots=True)
    class Broken(Report):
        nodes: int

        def summary(self) -> str:
            raise RuntimeError("no summary")

    with pytest.raises(RuntimeError, match="no summary"):
        write_report(tmp_path / "r.json", Broken(1), summary=tmp_path / "r.txt")
    assert folder_listing(tmp_path) == []


def test_data_json_cannot_hold(tmp_path):
    class Raw:
        def to_dict(self):
            return {"x": float("nan")}

        def summary(self):
            return "raw"

    with pytest.raises(FormatError, match=r"r\.json: the report's to_dict\(\) is not"):
        write_report(tmp_path / "r.json", Raw())
    assert list(tmp_path.iterdir()) == []


def test_what_is_not_a_report(tmp_path, report):
    with pytest.raises(TypeError, match=r"dict, which has no to_dict\(\)"):
        write_report(tmp_path / "r.json", {"nodes": 1})
    with pytest.raises(ConfigError, match="given for two outputs"):
        write_report(tmp_path / "r.json", report, summary=tmp_path / "r.json")
    assert list(tmp_path.iterdir()) == []
