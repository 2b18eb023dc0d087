"""``coastmesh run``: the command line of whole cases."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from conftest import assert_clean_failure

from coastmesh.data import path as data_path

EXAMPLE = Path(__file__).parents[2] / "examples" / "orkney" / "pentland_firth.toml"


@pytest.fixture
def case_file(tmp_path):
    """The example, coarse, with absolute data paths, in a temporary folder."""
    text = EXAMPLE.read_text()
    for old, new in {
        "../../src/coastmesh/data/orkney_gshhg_f.geojson": data_path(
            "orkney_gshhg_f.geojson"
        ).as_posix(),
        "../../src/coastmesh/data/etopo1_0.1deg_orkney_wide.tif": data_path(
            "etopo1_0.1deg_orkney_wide.tif"
        ).as_posix(),
        'h_min = "150 m"': 'h_min = "800 m"',
        'h_min = "400 m"': 'h_min = "1 km"',
        'h_min = "1 km"': 'h_min = "1.5 km"',
    }.items():
        assert old in text, old
        text = text.replace(old, new)
    text = re.sub(r"^output = .*\n", "", text, flags=re.M)  # the default: out/NAME
    # one format and no figures: a quick run
    text = re.sub(
        r"^formats = .*$", 'formats = ["msh2"]\nfigures = false', text, flags=re.M
    )
    path = tmp_path / "case.toml"
    path.write_text(text)
    return path


def test_help_describes_the_case_file(run_cli):
    result = run_cli("run", "--help")
    assert result.exit_code == 0
    for words in ("CASE.toml", "--output", "--check", "--overwrite", "open boundaries"):
        assert words in result.output
    assert "--workers" in result.output


@pytest.mark.filterwarnings("ignore::coastmesh.meshing.SmallIslandWarning")
def test_workers_give_the_same_mesh_in_parts(run_cli, case_file, tmp_path):
    text = case_file.read_text().replace("[mesh]\n", "[mesh]\nparts = 3\n")
    assert "parts = 3" in text
    case_file.write_text(text)
    meshes = []
    for workers in ("1", "2"):
        out = tmp_path / f"w{workers}"
        result = run_cli("run", case_file, "-o", out, "--workers", workers)
        assert result.exit_code == 0, result.output
        meshes.append((out / "pentland_firth.msh").read_bytes())
    assert meshes[0] == meshes[1]  # byte for byte
    bad = run_cli("run", case_file, "-o", tmp_path / "w0", "--workers", "0")
    assert bad.exit_code == 2 and "--workers" in bad.output
    assert not (tmp_path / "w0").exists()


@pytest.mark.filterwarnings("ignore::coastmesh.meshing.SmallIslandWarning")
def test_run_writes_the_case_and_a_summary(run_cli, case_file, tmp_path):
    result = run_cli("run", case_file, "--output", tmp_path / "mesh")
    assert result.exit_code == 0, result.output
    assert "pentland_firth:" in result.output and "nodes" in result.output
    assert "summary.txt" in result.output
    names = sorted(p.name for p in (tmp_path / "mesh").iterdir())
    assert names == [
        "case.toml",
        "domain.gpkg",
        "model_test",  # the example's ADCIRC and SCHISM smoke-test folders
        "pentland_firth.msh",
        "quality.json",
        "quality.txt",
        "report.json",
        "size.tif",
        "summary.txt",
    ]
    assert sorted(p.name for p in (tmp_path / "mesh" / "model_test").iterdir()) == [
        "adcirc",
        "schism",
    ]
    # a second run refuses to overwrite, then --overwrite replaces
    again = run_cli("run", case_file, "--output", tmp_path / "mesh")
    assert again.exit_code == 1 and "--overwrite" in again.output
    forced = run_cli("run", case_file, "-o", tmp_path / "mesh", "--overwrite")
    assert forced.exit_code == 0, forced.output


def test_default_output_is_relative_to_the_case_file(run_cli, case_file):
    result = run_cli("run", "--check", case_file)
    assert result.exit_code == 0
    assert str(case_file.parent / "out" / "pentland_firth") in result.output


def test_unknown_key_is_a_usage_error_naming_it(run_cli, case_file, tmp_path):
    case_file.write_text(case_file.read_text().replace("[mesh]", "[mesh]\nsed = 1"))
    result = run_cli("run", case_file, "-o", tmp_path / "x")
    assert_clean_failure(result, "unknown key 'mesh.sed'", code=2)
    assert not (tmp_path / "x").exists()


def test_missing_data_file_names_it(run_cli, case_file, tmp_path):
    text = case_file.read_text().replace("orkney_gshhg_f.geojson", "gone.geojson")
    case_file.write_text(text)
    result = run_cli("run", case_file, "-o", tmp_path / "x")
    assert result.exit_code == 1
    assert "gone.geojson" in result.output
    assert not (tmp_path / "x").exists()
    assert not list(tmp_path.glob("x.partial*"))


def test_missing_case_file(run_cli, tmp_path):
    result = run_cli("run", tmp_path / "nope.toml")
    assert result.exit_code == 2 and "no such case file" in result.output


def test_python_dash_m_returns_the_exit_code(tmp_path):
    """``python -m coastmesh`` exits non-zero on bad input, as the script does."""
    import subprocess
    import sys

    missing = tmp_path / "missing.toml"
    done = subprocess.run(
        [sys.executable, "-m", "coastmesh", "run", str(missing)],
        capture_output=True,
        text=True,
        check=False,
    )
    assert done.returncode == 2  # a missing case file is a bad argument
    assert "missing.toml: no such case file" in done.stderr
    assert not (tmp_path / "out").exists()
