"""The bathymetry PCA study (the paper's figure 4): parsing, outputs, numbers.

The study runs once on a 21 x 21 cell clip of the bundled Orkney ETOPO1 grid with
8 x 8 windows; its tables are checked against the GeoTIFFs read back with rasterio
and against a literal eigen-decomposition of the window covariance.
"""

from __future__ import annotations

import contextlib
import csv
import itertools
import json
from pathlib import Path

import numpy as np
import pytest
import rasterio
import rasterio.windows
from reference import simplify_raster_dense

from coastmesh.case import StudyCase, read_case
from coastmesh.case.schema import Table
from coastmesh.case.studies.bathymetry import (
    BathymetryStudyConfig,
    parse_study,
    run_study,
)
from coastmesh.data import path as data_path
from coastmesh.errors import ConfigError, InputDataError

EXAMPLE = Path(__file__).parents[3] / "examples" / "orkney_bathymetry" / "orkney.toml"
BBOX = (-4.0, 58.0, -2.0, 60.0)  # 21 x 21 cells around Orkney and Caithness
MODES = (1, 16, 32, 48)
FILES = {
    *(f"orkney_r{m}.tif" for m in (*MODES, 64)),
    "table.md",
    "table.csv",
    "study.json",
    *(f"figures/{n}.png" for n in ("maps", "surfaces", "spectrum", "rms")),
}


def _quiet(label):
    return contextlib.nullcontext(lambda done, total: None)


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    """Run the study once; record each stage's label and its progress calls."""
    calls: dict[str, list[tuple[int, int]]] = {}

    @contextlib.contextmanager
    def stage(label):
        calls[label] = []
        yield lambda done, total: calls[label].append((done, total))

    config = BathymetryStudyConfig(
        data_path("etopo1_0.1deg_orkney_wide.tif"), BBOX, 8, MODES, "orkney"
    )
    folder = tmp_path_factory.mktemp("bathymetry")
    result = run_study(config, folder, stage)
    return config, folder, result, calls


@pytest.fixture(scope="module")
def source_grid(study):
    """The input cells under the output grid, read from the source with rasterio."""
    config, folder, _, _ = study
    with rasterio.open(folder / "orkney_r64.tif") as out:
        bounds, shape = out.bounds, out.shape
    with rasterio.open(config.path) as src:
        window = rasterio.windows.from_bounds(*bounds, transform=src.transform)
        grid = src.read(1, window=window.round_offsets().round_lengths())
    assert grid.shape == shape == (21, 21)
    return grid.astype(np.float64)


def _read(path):
    with rasterio.open(path) as dataset:
        return dataset.read(1)


def _parse(data):
    table = Table(data, "study", "case.toml")
    return parse_study(table, lambda value, key: Path("/cases") / value)


# parsing


def test_parse_defaults_and_resolves_the_path():
    config = _parse({"path": "data/orkney.tif"})
    assert config == BathymetryStudyConfig(
        Path("/cases/data/orkney.tif"), None, 8, (1, 16, 32, 48), "orkney"
    )


def test_parse_reads_every_key():
    config = _parse(
        {
            "path": "a.tif",
            "bbox": [-4, 58, -2, 60],
            "window": 4,
            "modes": [2, 16],
            "prefix": "clip",
        }
    )
    assert config == BathymetryStudyConfig(
        Path("/cases/a.tif"), (-4.0, 58.0, -2.0, 60.0), 4, (2, 16), "clip"
    )
    assert _parse({"path": "a.tif", "window": 4}).modes == (1, 4, 8, 12)


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        ({"colour": "red"}, r"case\.toml: unknown key 'study\.colour'"),
        ({"modes": [1, 65]}, r"study\.modes\[1\] = 65: must be <= window\*\*2 = 64"),
        (
            {"window": 4, "modes": [17]},
            r"study\.modes\[0\] = 17: must be <= window\*\*2 = 16",
        ),
        ({"modes": [0]}, r"study\.modes\[0\] = 0: expected an integer >= 1"),
        ({"modes": [2, 2]}, r"study\.modes = \[2, 2\]: a mode count is repeated"),
        ({"modes": []}, r"study\.modes = \[\]: expected a list"),
        ({"window": 1}, r"study\.window = 1: expected an integer >= 2"),
        ({"bbox": [1, 2, 0, 3]}, r"study\.bbox = .*minx < maxx"),
        ({"prefix": "a/b"}, r"study\.prefix = 'a/b'"),
    ],
)
def test_parse_errors_name_the_key(extra, message):
    with pytest.raises(ConfigError, match=message):
        _parse({"path": "a.tif", **extra})


def test_parse_needs_a_path():
    with pytest.raises(ConfigError, match=r"study\.path: is missing"):
        _parse({"window": 8})


def test_config_checks_itself():
    with pytest.raises(ConfigError, match=r"modes\[0\] = 20: must be <= window"):
        BathymetryStudyConfig(Path("a.tif"), window=4, modes=(20,))


def test_example_case_parses():
    case = read_case(EXAMPLE)
    assert isinstance(case, StudyCase)
    assert (case.name, case.kind) == ("orkney_bathymetry", "bathymetry")
    # the repository's data file (the installed package may sit elsewhere)
    assert case.study.path.is_file()
    assert case.study.path.name == data_path("etopo1_0.1deg_orkney_wide.tif").name
    assert case.study == BathymetryStudyConfig(
        case.study.path, None, 8, (1, 16, 32, 48), "orkney"
    )
    assert case.output == EXAMPLE.parents[2] / "out" / "examples" / "orkney_bathymetry"


# running


def test_run_writes_every_file(study):
    _, folder, result, calls = study
    assert set(result.files) == FILES and len(result.files) == len(FILES)
    written = {p.relative_to(folder).as_posix() for p in folder.rglob("*.*")}
    assert written == FILES
    for name in FILES:
        head = (folder / name).read_bytes()[:8]
        if name.endswith(".png"):
            assert head == b"\x89PNG\r\n\x1a\n", name
        assert (folder / name).stat().st_size > 100, name
    # every stage reports and ends at its total; all 64 approximations are counted
    assert len(calls) == 5
    assert all(c and c[-1][0] == c[-1][1] for c in calls.values())
    assert calls["approximations with 1 .. 64 modes"][-1] == (64, 64)
    assert [r["modes"] for r in result.rows] == [*MODES, 64]
    assert "1: 44.1" in result.summary() and "12 files" in result.summary()


def test_all_modes_give_the_input_back(study, source_grid):
    _, folder, result, _ = study
    back = _read(folder / "orkney_r64.tif")
    assert back.dtype == np.float64
    assert np.sqrt(np.mean((back - source_grid) ** 2)) < 1e-8
    assert result.rows[-1]["rms_m"] < 1e-8
    assert result.rows[-1]["energy_fraction"] == 1.0


def test_more_modes_means_a_smaller_difference(study):
    _, folder, result, _ = study
    rms = [r["rms_m"] for r in result.rows]
    assert all(a > b for a, b in itertools.pairwise(rms))
    curve = json.loads((folder / "study.json").read_text())["curve"]
    assert [c["modes"] for c in curve] == list(range(1, 65))
    assert np.all(np.diff([c["rms_m"] for c in curve]) <= 1e-9)
    assert curve[0]["rms_m"] > 40  # 1 mode on real relief: tens of metres


def test_table_matches_the_geotiffs(study, source_grid):
    _, folder, result, _ = study
    with (folder / "table.csv").open(newline="") as stream:
        table = list(csv.DictReader(stream))
    markdown = (folder / "table.md").read_text().splitlines()[2:7]
    report = json.loads((folder / "study.json").read_text())
    assert report["rows"] == list(result.rows)
    for row, line, expected in zip(table, markdown, result.rows, strict=True):
        diff = _read(folder / f"orkney_r{row['modes']}.tif") - source_grid
        rms, worst = np.sqrt(np.mean(diff**2)), np.abs(diff).max()
        assert float(row["rms_m"]) == pytest.approx(rms, rel=1e-9, abs=1e-9)
        assert float(row["max_abs_diff_m"]) == pytest.approx(worst, rel=1e-9, abs=1e-9)
        assert float(row["rms_m"]) == expected["rms_m"]
        cells = [c.strip() for c in line.strip("|").split("|")]
        assert int(cells[0]) == expected["modes"]
        assert float(cells[1]) == pytest.approx(rms, abs=5e-4)


def test_energy_kept_matches_the_literal_covariance(study, source_grid):
    """Sum of the leading eigenvalues of C = S S^T / M over all, window by window."""
    _, folder, result, _ = study
    columns = []
    for i in range(21 - 8 + 1):
        for j in range(21 - 8 + 1):
            window = source_grid[i : i + 8, j : j + 8].ravel()
            columns.append(window - window.mean())
    s = np.array(columns).T  # (64, M)
    eigenvalues = np.sort(np.linalg.eigvalsh(s @ s.T / s.shape[1]))[::-1]
    kept = np.cumsum(eigenvalues.clip(0)) / eigenvalues.clip(0).sum()
    for row in result.rows:
        assert row["energy_fraction"] == pytest.approx(kept[row["modes"] - 1], 1e-9)
    spectrum = json.loads((folder / "study.json").read_text())["eigenvalues"]
    np.testing.assert_allclose(spectrum, eigenvalues, atol=1e-9 * eigenvalues[0])


def test_rasters_match_the_literal_algorithm(study, source_grid):
    _, folder, _, _ = study
    for modes in (1, 32):
        expected = simplify_raster_dense(source_grid, 8, modes)
        np.testing.assert_allclose(
            _read(folder / f"orkney_r{modes}.tif"), expected, atol=1e-7
        )


def test_too_small_a_raster_is_refused(tmp_path):
    config = BathymetryStudyConfig(
        data_path("etopo1_0.1deg_orkney_wide.tif"), (-3.3, 58.8, -2.9, 59.2)
    )
    with pytest.raises(
        InputDataError,
        match=r"orkney_wide.tif: 5 x 5 cells is smaller than one window \(window = 8\)",
    ):
        run_study(config, tmp_path, _quiet)
