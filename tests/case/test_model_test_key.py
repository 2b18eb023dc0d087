"""``[output] model_test``: smoke-test run folders written with a case's outputs."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import pytest
from conftest import EXAMPLE, coarse_example_text
from model_rules import check_adcirc, check_schism

from coastmesh.case import parse_case
from coastmesh.case.result import model_dt
from coastmesh.errors import ConfigError
from coastmesh.io.meshes.model_tests import schism_time_step

ROOT = Path(__file__).parents[2]
#: the example case's own line (it writes both run folders)
LINE = 'model_test = ["adcirc", "schism"]'


def example_with(line: str) -> str:
    """The coarse example with its ``model_test`` line replaced by ``line``."""
    text = coarse_example_text()
    assert text.count(LINE) == 1
    return text.replace(LINE, line)


def test_the_key_takes_model_names():
    text = coarse_example_text()
    assert parse_case(text, EXAMPLE).outputs.model_test == ("adcirc", "schism")
    one = parse_case(example_with('model_test = "schism"'), EXAMPLE)
    assert one.outputs.model_test == ("schism",)
    assert parse_case(example_with(""), EXAMPLE).outputs.model_test == ()


@pytest.mark.parametrize(
    ("value", "message"),
    [
        ('["fvcom"]', "'fvcom': no smoke test for this model; known: adcirc, schism"),
        ('["adcirc", "adcirc"]', "a model is listed twice"),
        ("3", "expected a name or a list of names"),
    ],
)
def test_bad_models_are_named(value, message):
    text = example_with(f"model_test = {value}")
    with pytest.raises(ConfigError, match=message) as info:
        parse_case(text, EXAMPLE)
    assert "output.model_test" in str(info.value)


def test_a_global_case_is_refused_with_why():
    world = ROOT / "examples" / "global" / "world.toml"
    text = world.read_text().replace("[output]", '[output]\nmodel_test = ["adcirc"]', 1)
    assert text != world.read_text()
    with pytest.raises(ConfigError, match="a global case cannot be described") as info:
        parse_case(text, world)
    assert "world.toml" in str(info.value) and "tidal potential" in str(info.value)


def test_a_case_without_depths_is_refused():
    text = example_with('model_test = ["schism"]')
    start = text.index("[bathymetry]")
    end = text.index("\n[", start + 1)
    with pytest.raises(
        ConfigError, match=r"needs depths at the nodes; add \[bathymetry\]"
    ):
        parse_case(text[:start] + text[end + 1 :], EXAMPLE)


@pytest.mark.xdist_group("coarse")
def test_a_case_writes_both_run_folders(coarse_case, tmp_path):
    outputs = dataclasses.replace(
        coarse_case.config.outputs, model_test=("adcirc", "schism"), figures=False
    )
    result = dataclasses.replace(
        coarse_case, config=dataclasses.replace(coarse_case.config, outputs=outputs)
    ).write(tmp_path / "out")
    folder = tmp_path / "out" / "model_test"
    assert "model_test/adcirc/fort.15" in result.files
    assert "model_test/schism/param.nml" in result.files
    assert check_adcirc(folder / "adcirc" / "fort.14") == []
    assert check_schism(folder / "schism" / "hgrid.gr3") == []
    dt = model_dt(coarse_case.report.quality)
    assert dt == coarse_case.report.quality.time_step.courant.dt
    assert f"{dt:g} ! DTDP" in (folder / "adcirc" / "fort.15").read_text()
    # SCHISM at a step of its own rules, not the explicit model's
    step, _ = schism_time_step(coarse_case.mesh)
    assert step != dt
    assert f"dt = {step:g}\n" in (folder / "schism" / "param.nml").read_text()
    assert (folder / "schism" / "adv.gr3").is_file()
    assert (folder / "schism" / "outputs").is_dir()
    # the report gives each test's step, as written
    assert result.report.model_tests == {"adcirc": dt, "schism": step}
    written = json.loads((tmp_path / "out" / "report.json").read_text())
    assert written["model_tests"] == {"adcirc": dt, "schism": step}
    summary = (tmp_path / "out" / "summary.txt").read_text()
    assert f"model tests, time step (s): adcirc {dt:g}, schism {step:g}" in summary


@pytest.mark.parametrize(
    ("value", "message"),
    [
        (
            '{ fort15 = { land = "essential" } }',
            "output.options.fort15: unknown format",
        ),
        ('{ fort14 = { lnd = "x" } }', "output.options.fort14.lnd: not an option"),
        ('{ fort14 = { positive = "up" } }', "it is output.positive"),
        ("{ gr3 = { regions = false } }", "the case writes the region files"),
        ('{ fort14 = "essential" }', "expected a table of options"),
    ],
)
def test_bad_writer_options_are_named(value, message):
    text = coarse_example_text().replace("[output]", f"[output]\noptions = {value}", 1)
    with pytest.raises(ConfigError, match=message):
        parse_case(text, EXAMPLE)


@pytest.mark.xdist_group("coarse")
def test_writer_options_reach_the_writer_and_the_smoke_test(coarse_case, tmp_path):
    from model_rules import parse_grid

    outputs = dataclasses.replace(
        coarse_case.config.outputs,
        formats=("fort14",),
        options={"fort14": {"land": "natural"}},
        model_test=("adcirc",),
        figures=False,
    )
    config = dataclasses.replace(coarse_case.config, outputs=outputs)
    result = dataclasses.replace(coarse_case, config=config).write(tmp_path / "out")
    for path in (
        tmp_path / "out" / f"{result.name}.14",
        tmp_path / "out" / "model_test" / "adcirc" / "fort.14",
    ):
        codes = {code for _, code, _ in parse_grid(path).land}
        assert codes <= {20, 21} and 21 in codes, path
        assert check_adcirc(path) == []
