"""The docs: every Python example runs, and every name they show exists.

Each page's ```python blocks run in order, in one namespace, in a fresh folder
with ``examples/`` beside it (the pages name ``examples/...`` from the top of
the repository). A block whose first line starts with ``# sketch`` shows code
for another program (Thetis) and is not run.
"""

from __future__ import annotations

import ast
import importlib
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).parents[2]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
BLOCK = re.compile(r"```python\n(.*?)```", re.S)


def _blocks(page: Path) -> list[str]:
    return BLOCK.findall(page.read_text(encoding="utf-8"))


RUNNABLE = [p for p in PAGES if any(not b.startswith("# sketch") for b in _blocks(p))]
#: the output of this command, which pages run before their Python examples
RUN = "coastmesh run examples/orkney/pentland_firth.toml"


@pytest.mark.slow
@pytest.mark.parametrize("page", RUNNABLE, ids=lambda p: p.name)
def test_page_examples_run(page, tmp_path, example_run):
    """Run the page's Python blocks in order, in a fresh interpreter."""
    shutil.copytree(ROOT / "examples", tmp_path / "examples")
    # the examples' relative paths reach the bundled data in src/
    (tmp_path / "src").symlink_to(ROOT / "src")
    if RUN in page.read_text(encoding="utf-8"):  # as if the page's command had run
        shutil.copytree(example_run[1], tmp_path / "out/examples/pentland_firth")
    blocks = [b for b in _blocks(page) if not b.startswith("# sketch")]
    script = tmp_path / f"{page.stem}.py"
    script.write_text(
        "import warnings\nwarnings.simplefilter('ignore')\n" + "\n".join(blocks)
    )
    run = subprocess.run(
        [sys.executable, str(script)],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=600,
        check=False,
    )
    assert run.returncode == 0, f"{page.name}:\n{run.stdout}\n{run.stderr}"


def test_sketches_say_why():
    for page in PAGES:
        for block in _blocks(page):
            if block.startswith("# sketch"):
                assert "not run" in block.splitlines()[0], page


# `coastmesh.x.y` as the docs write them in text and tables
DOTTED = re.compile(r"`(coastmesh(?:\.[A-Za-z_][A-Za-z0-9_]*)+)(?:\(|`)")


def _shown_names() -> set[tuple[str, str]]:
    """(module, name) pairs the docs show: in text, and imported in examples."""
    shown = set()
    for page in PAGES:
        for dotted in DOTTED.findall(page.read_text(encoding="utf-8")):
            module, _, name = dotted.rpartition(".")
            shown.add((module, name))
        for block in _blocks(page):
            for node in ast.walk(ast.parse(block)):
                if isinstance(node, ast.ImportFrom) and node.module.startswith(
                    "coastmesh"
                ):
                    shown |= {(node.module, alias.name) for alias in node.names}
    return shown


@pytest.mark.parametrize("module,name", sorted(_shown_names()))
def test_every_name_the_docs_show_exists(module, name):
    try:
        owner = importlib.import_module(module)
    except ModuleNotFoundError:
        # `coastmesh.io.read_mesh` is module `coastmesh.io`, name `read_mesh`;
        # `coastmesh.meshing.cleanup.fixes` is a module itself
        importlib.import_module(f"{module}.{name}")
        return
    if not hasattr(owner, name):
        importlib.import_module(f"{module}.{name}")  # a submodule
        return
    if hasattr(owner, "__all__") and not name.startswith("_"):
        is_module = type(getattr(owner, name)).__name__ == "module"
        assert is_module or name in owner.__all__, f"{module}.__all__ lacks {name}"


@pytest.mark.parametrize(
    "package",
    [
        "coastmesh",
        "coastmesh.case",
        "coastmesh.commands",
        "coastmesh.geometry",
        "coastmesh.io",
        "coastmesh.meshing",
        "coastmesh.pca",
        "coastmesh.plot",
        "coastmesh.sizing",
        "coastmesh.types",
    ],
)
def test_every_exported_name_imports(package):
    module = importlib.import_module(package)
    missing = [name for name in module.__all__ if not hasattr(module, name)]
    assert missing == [], missing
    assert sorted(module.__all__) == sorted(set(module.__all__))


def test_the_generated_tables_are_current():
    """The docs' key and format tables are as the config classes and registry say."""
    run = subprocess.run(
        [sys.executable, str(ROOT / "scripts" / "doc_tables.py"), "--check"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert run.returncode == 0, run.stdout + run.stderr
    from coastmesh.case.config import DOCUMENTED
    from coastmesh.case.schema.reference import MARKER

    marked = {m[1] for m in MARKER.findall((ROOT / "docs/case-files.md").read_text())}
    assert marked >= set(DOCUMENTED) - {"CaseConfig"} | {"TERMS", "BOUNDARY_KINDS"}, (
        "every config class has its table of keys in docs/case-files.md"
    )
    assert "<!-- formats -->" in (ROOT / "docs" / "formats.md").read_text()
