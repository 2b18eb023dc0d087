"""The kinds of case (``[domain] kind``): the table the case-file checks ask.

Each kind's rules are a row of ``DOMAIN_KINDS``; the reader, the checks and the
dumper ask it, and the pipeline picks the kind's strategy from ``STRATEGIES``.
"""

from __future__ import annotations

import re

import pytest

from coastmesh.case import dump_case, parse_case
from coastmesh.case.config.kinds import DEFAULT_KIND, DOMAIN_KINDS, domain_kind
from coastmesh.case.pipeline import STRATEGIES, strategy_of
from coastmesh.case.pipeline.strategy import Regional
from coastmesh.case.pipeline.world import Global
from coastmesh.errors import ConfigError

#: a case of kind KIND: one set, its boundary table TABLE (a line), and EXTRA
CASE = """
[case]
name = "t"

[shorelines]
path = "/data/coast.gpkg"

[shoreline_sets.coast]
id = 10

[domain]
kind = "{kind}"

[[{table}]]
name = "cut"
id = 2
kind = "polyline"
points = [[-5.0, 36.0], [-5.5, 35.8]]

[mesh_size]
h_max = "50 km"
{extra}
"""

FARM = """
[[farms]]
name = "farm"
id = 30
polygon = [[0.0, 0.0], [0.1, 0.0], [0.1, 0.1], [0.0, 0.1]]
"""
STRUCTURE = """
[[structures]]
name = "wall"
id = 31
polygon = [[0.0, 0.0], [0.1, 0.0], [0.1, 0.1], [0.0, 0.1]]
"""
MODEL_TEST = """
[output]
model_test = ["schism"]
"""


def case(kind: str, extra: str = "", table: str | None = None) -> str:
    """A case file of ``kind`` with its own table of boundaries (or ``table``)."""
    table = DOMAIN_KINDS[kind].boundaries if table is None else table
    return CASE.format(kind=kind, table=table, extra=extra)


def test_the_kinds_are_the_key_s_choices_and_the_default_is_regional():
    assert list(DOMAIN_KINDS) == ["regional", "global"]
    assert DEFAULT_KIND == "regional"
    assert parse_case(case("regional"), "t.toml").domain.kind == "regional"
    with pytest.raises(ConfigError, match="expected one of 'regional', 'global'"):
        parse_case(case("regional").replace('"regional"', '"lake"'), "t.toml")
    # any other value is the default kind: the key's check reports it
    assert domain_kind("lake") is domain_kind(None) is domain_kind(["global"])
    assert domain_kind(None).name == DEFAULT_KIND


def test_every_kind_has_a_strategy():
    assert set(STRATEGIES) == set(DOMAIN_KINDS)
    for kind in DOMAIN_KINDS:
        config = parse_case(case(kind), "t.toml")
        assert isinstance(strategy_of(config), STRATEGIES[kind])
    assert Global.on_sphere and not Regional.on_sphere


@pytest.mark.parametrize("kind", list(DOMAIN_KINDS))
@pytest.mark.parametrize("extra", [FARM, STRUCTURE])
def test_a_kind_that_refuses_sites_refuses_them_with_its_reason(kind, extra):
    refused = DOMAIN_KINDS[kind].refuses_sites
    if refused is None:
        assert parse_case(case(kind, extra), "t.toml").domain.kind == kind
        return
    with pytest.raises(ConfigError) as info:
        parse_case(case(kind, extra), "t.toml")
    assert str(info.value) == f"t.toml: {refused}"


def test_a_global_case_refuses_farms_turbines_lines_and_structures():
    with pytest.raises(ConfigError) as info:
        parse_case(case("global", FARM), "t.toml")
    assert str(info.value) == (
        "t.toml: farms, turbines, lines and structures are for regional cases; a "
        "global case has none"
    )


@pytest.mark.parametrize("kind", list(DOMAIN_KINDS))
def test_a_kind_that_refuses_model_tests_says_why_first(kind):
    refused = DOMAIN_KINDS[kind].refuses_model_tests
    with pytest.raises(ConfigError) as info:
        parse_case(case(kind, MODEL_TEST), "t.toml")
    what = "t.toml: output.model_test = ['schism']"
    if refused is None:  # on to the case's depths
        assert str(info.value) == (
            f"{what}: a model needs depths at the nodes; add [bathymetry]"
        )
    else:
        assert str(info.value) == f"{what}: {refused}"
    assert ("a global case cannot be described" in str(info.value)) == (
        kind == "global"
    )


def test_each_kind_refuses_another_kind_s_table_of_boundaries():
    with pytest.raises(ConfigError) as info:
        parse_case(case("regional", table="cuts"), "t.toml")
    assert str(info.value) == (
        't.toml: [[cuts]] are for global cases ([domain] kind = "global"); a '
        "regional case gives its open boundaries as [[open_boundaries]]"
    )
    with pytest.raises(ConfigError) as info:
        parse_case(case("global", table="open_boundaries"), "t.toml")
    assert str(info.value).startswith(
        "t.toml: [[open_boundaries]] ['cut']: a global case meshes the whole "
        "ocean, which has no open boundary. To cut a sea off the ocean"
    )
    # its own table is read as the case's open boundaries
    for kind in DOMAIN_KINDS:
        config = parse_case(case(kind), "t.toml")
        assert [b.name for b in config.boundaries] == ["cut"]


def test_a_dump_writes_the_keys_of_its_kind_alone():
    for kind, row in DOMAIN_KINDS.items():
        config = parse_case(case(kind), "t.toml")
        text = dump_case(config)
        assert f"[[{row.boundaries}]]" in text
        others = {k for r in DOMAIN_KINDS.values() for k in r.keys} - set(row.keys)
        domain = text.split("[domain]")[1].split("\n[")[0]
        written = set(re.findall(r"^(\w+) = ", domain, flags=re.MULTILINE))
        assert not others & written
        assert ("kind" in written) == ("kind" in row.keys)
        assert parse_case(text, "t.toml").domain == config.domain
