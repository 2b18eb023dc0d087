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


FARM_EXAMPLE = EXAMPLE.with_name("inner_sound_farm.toml")
#: docs/sites.md's structure, a gradation naming it, and turbines from a file
MORE_SITE = """
[[structures]]
name = "pier"
id = 30
polygon = [[-3.1372, 58.6415], [-3.1362, 58.6415], [-3.1362, 58.6445],
           [-3.1372, 58.6445]]

[[mesh_size.gradations]]
lines = ["pier"]
h_min = "25 m"
d_grade = "4 km"

[[turbines]]
name = "spares"
farm = "meygen"
path = "spares.csv"
crs = "EPSG:32630"
diameter = "20 m"

[[wakes]]
of = "meygen"
bearing = 100
length = "1 km"
sides = "flood"
"""


def test_check_lists_every_site_entry_and_what_it_is_checked_against(run_cli, tmp_path):
    case = tmp_path / "site.toml"
    case.write_text(FARM_EXAMPLE.read_text() + MORE_SITE)
    result = run_cli("run", "--check", case)
    assert result.exit_code == 0, result.output
    head, *lines = result.output.splitlines()
    assert head.startswith(f"{case}: OK: 3 shoreline sets, 2 regions, ")
    assert (
        "4 gradations, 1 farm, 4 turbines and 1 file of turbines, 2 wakes, 1 line, "
        "1 structure; output"
    ) in head
    turbines = [(-3.145, 58.659), (-3.14, 58.659), (-3.135, 58.659), (-3.13, 58.659)]
    assert lines == [
        "  farm 'meygen': region 20, h 20 m; a polygon of 4 points, 1.55 km2",
        "  turbines 'phase_1a': disc footprints, regions 100 to 103, h 0.25 D "
        "(4.5 m), spacing 1 D (18 m), clearance 1 D (18 m), in farm 'meygen'",
        *(
            f"    turbine 'phase_1a_{n + 1}' at {lon}, {lat}, D 18 m, region {100 + n}"
            for n, (lon, lat) in enumerate(turbines)
        ),
        # turbines from a file: their D is the file's, unknown to the check
        "  turbines 'spares': a node each, h 0.25 D, spacing 1 D, clearance 1 D, in "
        f"farm 'meygen'; from {tmp_path / 'spares.csv'} (x, y in EPSG:32630), D 20 "
        "m unless the file gives it",
        "  wake of turbines 'phase_1a': bearing 100 deg, length 20 D (360 m) both "
        "ways, h 0.5 D (9 m)",
        "  wake of farm 'meygen': bearing 100 deg, length 1,000 m flood side, h the "
        "farm's (20 m)",
        "  line 'array_cable': id 40; 2 points, 1,103 m long; h 9 m",
        "  structure 'pier': boundary id 30; a polygon of 4 points, 19,405 m2",
    ]
    # a case without a site lists none of it
    plain = run_cli("run", "--check", EXAMPLE)
    assert plain.exit_code == 0, plain.output
    assert len(plain.output.splitlines()) == 1
    for word in ("farm", "turbine", "wake", "line", "structure"):
        assert not re.search(rf"\b{word}", plain.output), word


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
