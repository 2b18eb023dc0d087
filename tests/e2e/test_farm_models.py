"""The tidal-array example with smoke-test run folders: the models' rules hold.

``examples/orkney/inner_sound_farm.toml`` (a farm region, four turbine
footprints, an array cable) run once, end to end, with ``[output] model_test``:
its fort.14, hgrid.gr3 and SELAFIN files and the ADCIRC and SCHISM run folders
follow each model's rules (``tests/model_rules.py``), and the run folders hold
the case's own time step.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import pytest
from conftest import model_rule_breaks
from model_rules import check_adcirc, check_schism

from coastmesh.case import parse_case, run_case
from coastmesh.case.result import model_dt
from coastmesh.io.meshes.model_tests import schism_time_step

#: a whole case, end to end: run by `pytest -m slow` (and .ci/run)
pytestmark = pytest.mark.slow

CASE = Path(__file__).parents[2] / "examples" / "orkney" / "inner_sound_farm.toml"


@pytest.fixture(scope="module")
def farm(tmp_path_factory):
    text = CASE.read_text()
    assert "[output]" in text
    text = text.replace("[output]", '[output]\nmodel_test = ["adcirc", "schism"]', 1)
    out = tmp_path_factory.mktemp("farm") / "inner_sound_farm"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = run_case(parse_case(text, CASE), output=out)
    return result, out


def test_the_models_rules_hold(farm, tmp_path):
    result, out = farm
    assert model_rule_breaks(result.mesh, tmp_path) == []
    assert check_adcirc(out / "model_test" / "adcirc" / "fort.14") == []
    assert check_schism(out / "model_test" / "schism" / "hgrid.gr3") == []


def test_the_run_folders_hold_the_cases_time_step(farm):
    """ADCIRC at the case's step; SCHISM, implicit, at its own rules' step."""
    result, out = farm
    dt = model_dt(result.report.quality)
    assert f"{dt:g} ! DTDP" in (out / "model_test" / "adcirc" / "fort.15").read_text()
    step, _ = schism_time_step(result.mesh)
    param = (out / "model_test" / "schism" / "param.nml").read_text()
    assert f"  dt = {step:g}\n" in param
    # the farm and footprints are regions: the region files sit beside the grids
    assert (out / "inner_sound_farm.13").exists()
