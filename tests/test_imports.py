"""Importing the core does not import the heavy or optional libraries.

Each check runs in a fresh interpreter; they all start at once to keep this quick.
"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

HEAVY = {"gmsh", "matplotlib", "rasterio", "pyogrio", "click"}

STATEMENTS = {
    # the package itself, errors, pca and geometry come with the shoreline module
    "core": (
        "import coastmesh.geometry.shoreline, coastmesh.types, coastmesh.data, "
        "coastmesh.geometry, coastmesh.depth, coastmesh.sizing, coastmesh.pca, "
        "coastmesh.meshing"
    ),
    "msh": "import coastmesh.io.meshes.msh",
    "cli": "import coastmesh.cli.main",
    "vector": "import coastmesh.io.vectors.vector",
    "raster": "import coastmesh.io.rasters.raster",
    "plot": "import coastmesh.plot, coastmesh.commands",
}


@pytest.fixture(scope="module")
def loaded() -> dict[str, set[str]]:
    """Top-level modules in ``sys.modules`` after each statement."""
    report = "print(json.dumps(sorted({m.split('.')[0] for m in sys.modules})))"
    runs = {
        name: subprocess.Popen(
            [sys.executable, "-c", f"import sys, json\n{statement}\n{report}"],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        for name, statement in STATEMENTS.items()
    }
    found = {}
    for name, run in runs.items():
        out, err = run.communicate(timeout=120)
        assert run.returncode == 0, err
        found[name] = set(json.loads(out))
    return found


def test_core_modules_stay_light(loaded):
    assert "coastmesh" in loaded["core"] and "numpy" in loaded["core"]
    assert loaded["core"] & HEAVY == set()


def test_msh_io_does_not_load_gmsh(loaded):
    """Only meshing/gmsh/model.py talks to gmsh, and only while meshing."""
    assert loaded["msh"] & {"gmsh", "matplotlib", "rasterio", "pyogrio"} == set()


def test_command_line_help_does_not_load_the_io_stack(loaded):
    assert "click" in loaded["cli"]
    assert (
        loaded["cli"] & {"matplotlib", "rasterio", "pyogrio", "xarray", "gmsh"} == set()
    )


def test_vector_io_does_not_load_raster_or_plot_libraries(loaded):
    assert "pyogrio" in loaded["vector"]
    assert loaded["vector"] & {"matplotlib", "rasterio", "xarray", "click"} == set()


def test_raster_io_does_not_load_vector_or_plot_libraries(loaded):
    assert "rasterio" in loaded["raster"]
    # rasterio itself imports click
    assert loaded["raster"] & {"matplotlib", "pyogrio", "gmsh"} == set()


def test_plots_and_pipeline_load_matplotlib_only_when_plotting(loaded):
    assert "pyogrio" in loaded["plot"]
    assert loaded["plot"] & {"matplotlib", "rasterio", "xarray", "click"} == set()


def test_entry_point_main(capsys):
    from coastmesh import __version__
    from coastmesh.cli.main import main

    assert main(["--version"]) == 0
    assert __version__ in capsys.readouterr().out
    assert main(["--show-versions"]) == 0
    shown = capsys.readouterr().out
    assert "GDAL" in shown and "shapely" in shown and "GEOS" in shown
    assert main(["simplify-shoreline"]) == 2
    assert "Missing argument 'IN'" in capsys.readouterr().err


def test_the_version_is_the_one_pyproject_gives():
    """coastmesh.version, the one place in the package, is pyproject.toml's."""
    import tomllib
    from pathlib import Path

    import coastmesh
    from coastmesh.version import __version__

    project = tomllib.loads(
        (Path(__file__).parents[1] / "pyproject.toml").read_text(encoding="utf-8")
    )["project"]
    assert __version__ == coastmesh.__version__ == project["version"]
