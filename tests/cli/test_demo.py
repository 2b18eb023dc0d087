"""``coastmesh demo``: the README's main command."""

from __future__ import annotations

import pytest
from conftest import assert_clean_failure

import coastmesh.commands.demo
from coastmesh.io.rasters.raster import read_raster
from coastmesh.io.vectors.vector import read_features

FULL_OUTPUTS = sorted(
    [
        f"norway_west_L{w}_r{r}.{ext}"
        for w, r in ((100, 1), (500, 1), (100, 5))
        for ext in ("gpkg", "png")
    ]
    + [f"orkney_etopo1_8x8_r{r}.{ext}" for r in (1, 16, 48) for ext in ("tif", "png")]
    + ["README.txt", "pentland_firth"]
)


@pytest.fixture
def small_demo(monkeypatch):
    """Run one shoreline and one raster step instead of six."""
    monkeypatch.setattr(coastmesh.commands.demo, "_DEMO_SHORELINES", ((500, 1),))
    monkeypatch.setattr(coastmesh.commands.demo, "_DEMO_RASTERS", ((8, 16),))
    monkeypatch.setattr(coastmesh.commands.demo, "_DEMO_CASES", 0)


@pytest.fixture
def tiny_demo(monkeypatch):
    """Run the raster step only."""
    monkeypatch.setattr(coastmesh.commands.demo, "_DEMO_SHORELINES", ())
    monkeypatch.setattr(coastmesh.commands.demo, "_DEMO_RASTERS", ((8, 16),))
    monkeypatch.setattr(coastmesh.commands.demo, "_DEMO_CASES", 0)


def test_demo_writes_results_and_says_where(
    run_cli, tmp_path, small_demo, folder_listing
):
    out = tmp_path / "demo"
    result = run_cli("demo", out)
    assert result.exit_code == 0, result.output
    assert folder_listing(tmp_path) == ["demo"]
    assert folder_listing(out) == [
        "README.txt",
        "norway_west_L500_r1.gpkg",
        "norway_west_L500_r1.png",
        "orkney_etopo1_8x8_r16.png",
        "orkney_etopo1_8x8_r16.tif",
    ]
    assert f"results in {out}/" in result.stdout
    assert "norway_west_L500_r1.png" in result.stdout
    coast = read_features(out / "norway_west_L500_r1.gpkg")
    assert coast.crs.to_epsg() == 4326 and len(coast) > 0
    assert read_raster(out / "orkney_etopo1_8x8_r16.tif").shape == (51, 101)
    readme = (out / "README.txt").read_text()
    assert "GSHHG" in readme and "ETOPO1" in readme
    assert "window 500 points, 1 mode" in readme


def test_demo_default_folder_is_out(
    run_cli, tmp_path, tiny_demo, monkeypatch, folder_listing
):
    monkeypatch.chdir(tmp_path)
    result = run_cli("demo")
    assert result.exit_code == 0, result.output
    assert folder_listing(tmp_path) == ["out"]


def test_demo_refuses_a_full_folder(run_cli, tmp_path, tiny_demo):
    out = tmp_path / "demo"
    out.mkdir()
    (out / "mine.txt").write_text("keep")
    result = run_cli("demo", out)
    assert result.exit_code == 1
    assert str(out) in result.output and "--overwrite" in result.output
    assert sorted(p.name for p in out.iterdir()) == ["mine.txt"]
    result = run_cli("demo", out, "--overwrite")
    assert result.exit_code == 0, result.output
    assert not (out / "mine.txt").exists()
    assert (out / "README.txt").exists()


def test_a_failing_demo_leaves_nothing(run_cli, tmp_path, tiny_demo, monkeypatch):
    def broken(*args, **kwargs):
        raise OSError(28, "No space left on device", "somewhere")

    monkeypatch.setattr(coastmesh.commands.demo, "simplify_raster_file", broken)
    result = run_cli("demo", tmp_path / "demo")
    assert_clean_failure(result, "No space left on device")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.slow
def test_full_demo(run_cli, tmp_path, folder_listing):
    out = tmp_path / "out"
    result = run_cli("demo", out)
    assert result.exit_code == 0, result.output
    assert folder_listing(out) == FULL_OUTPUTS
    assert len(result.stdout.strip().splitlines()) == 15  # 2 lines per step + 1
    case = out / "pentland_firth"
    for name in (
        "pentland_firth.msh",
        "pentland_firth.14",
        "quality.txt",
        "figures/mesh.png",
        "figures/depth.png",
        "summary.txt",
        "model_test/adcirc/fort.15",
        "model_test/schism/param.nml",
    ):
        assert (case / name).is_file(), name
    assert "pentland_firth/figures/mesh.png" in result.stdout.splitlines()[-1]
