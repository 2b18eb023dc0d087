"""The package layout: imports point one way, no private names across packages,
small modules.

The layers are an import-linter contract in ``pyproject.toml``; this runs it, so
the README's test command (and CI) enforces it.
"""

from __future__ import annotations

import ast
import os
import shutil
import subprocess
import sys
import warnings
from pathlib import Path

import pytest

ROOT = Path(__file__).parents[1]
PACKAGE = ROOT / "src" / "coastmesh"
MAX_LINES = 500


def _modules() -> list[Path]:
    return sorted(p for p in PACKAGE.rglob("*.py") if "__pycache__" not in p.parts)


def test_import_contracts_hold():
    """pca -> geometry -> sizing -> meshing -> io -> plot -> case -> commands -> cli."""
    command = shutil.which("lint-imports") or str(
        Path(sys.executable).parent / "lint-imports"
    )
    # the tree's own modules, not a coastmesh installed (maybe stale) beside it
    path = os.pathsep.join(
        p for p in (str(ROOT / "src"), os.environ.get("PYTHONPATH")) if p
    )
    run = subprocess.run(
        [command, "--no-cache", str(ROOT / "pyproject.toml")],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
        env={**os.environ, "PYTHONPATH": path},
    )
    assert run.returncode == 0, run.stdout + run.stderr
    assert "0 broken" in run.stdout


def _package_of(module: str) -> str:
    """``coastmesh.io.meshes.msh`` -> ``io``; top-level modules are their own
    package."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else ""


@pytest.mark.parametrize("path", _modules(), ids=lambda p: str(p.relative_to(PACKAGE)))
def test_no_private_names_across_packages(path):
    here = _package_of(
        "coastmesh." + ".".join(path.relative_to(PACKAGE).with_suffix("").parts)
    )
    tree = ast.parse(path.read_text(encoding="utf-8"))
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and (node.module or "").startswith(
            "coastmesh"
        ):
            module = node.module
            if _package_of(module) == here:
                continue
            private = [p for p in module.split(".") if p.startswith("_")]
            names = [a.name for a in node.names if a.name.startswith("_")]
            names = [n for n in names if n != "__version__"]
            assert not private and not names, (
                f"{path.relative_to(ROOT)}:{node.lineno} imports private "
                f"{module} {names}"
            )
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if (
                    alias.name.startswith("coastmesh")
                    and _package_of(alias.name) != here
                ):
                    assert not any(p.startswith("_") for p in alias.name.split(".")), (
                        f"{path.relative_to(ROOT)}:{node.lineno} imports {alias.name}"
                    )


def test_modules_are_small():
    """Over about 500 lines, a module may hold more than one idea: a warning.

    A warning, not a failure: a module is split along what it does, never to
    fit a line count.
    """
    sizes = {
        str(p.relative_to(PACKAGE)): len(p.read_text(encoding="utf-8").splitlines())
        for p in _modules()
    }
    large = {name: n for name, n in sizes.items() if n > MAX_LINES}
    if large:
        warnings.warn(
            f"modules over {MAX_LINES} lines (does each hold one idea?): {large}",
            UserWarning,
            stacklevel=1,
        )
    assert all(n > 0 for n in sizes.values())


FUNCTION_LINES = 80


def _code_lines(node: ast.FunctionDef | ast.AsyncFunctionDef, lines: list[str]) -> int:
    """Lines of ``node`` that are neither blank, a comment nor its docstring."""
    docstring = set()
    body = node.body
    if (
        body
        and isinstance(body[0], ast.Expr)
        and isinstance(body[0].value, ast.Constant)
        and isinstance(body[0].value.value, str)
    ):
        docstring = set(range(body[0].lineno, body[0].end_lineno + 1))
    return sum(
        1
        for number in range(node.lineno, node.end_lineno + 1)
        if number not in docstring
        and lines[number - 1].strip()
        and not lines[number - 1].strip().startswith("#")
    )


def test_code_lines_count_neither_docstring_blanks_nor_comments():
    """Blank lines inside a docstring are not code, and are not taken off twice."""
    source = '''def f(x):
    """Summary.

    More text.

    """
    # a comment

    y = x + 1
    return y
'''
    node = ast.parse(source).body[0]
    assert _code_lines(node, source.splitlines()) == 3


@pytest.mark.parametrize("path", _modules(), ids=lambda p: str(p.relative_to(PACKAGE)))
def test_functions_are_short(path):
    """No function has more than 80 lines of code.

    Code is every line from ``def`` to the function's last line that is not
    blank, not a comment and not in its docstring (nested functions count
    towards the function that holds them).
    """
    text = path.read_text(encoding="utf-8")
    lines = text.splitlines()
    for node in ast.walk(ast.parse(text)):
        if not isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            continue
        code = _code_lines(node, lines)
        assert code <= FUNCTION_LINES, (
            f"{path.relative_to(ROOT)}:{node.lineno} {node.name} has "
            f"{code} lines of code (at most {FUNCTION_LINES})"
        )


TYPED = PACKAGE / "case" / "pipeline"


def _unannotated(tree: ast.AST) -> list[str]:
    """``line name(parameter)`` for each parameter without an annotation, and
    ``line name -> ?`` for each function without a return annotation.

    ``self`` and ``cls`` need none, nor ``*args`` and ``**kwargs``.
    """
    missing: list[tuple[int, str]] = []
    for node in ast.walk(tree):
        if not isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            continue
        a = node.args
        for arg in a.posonlyargs + a.args + a.kwonlyargs:
            if arg.annotation is None and arg.arg not in {"self", "cls"}:
                missing.append((node.lineno, f"{node.name}({arg.arg})"))
        if node.returns is None:
            missing.append((node.lineno, f"{node.name} -> ?"))
    return [f"{line} {what}" for line, what in sorted(missing, key=lambda m: m[0])]


def test_unannotated_finds_a_missing_annotation():
    source = """class C:
    def m(self, a: int, b, *args, c=1, **kw) -> None: ...
def f(x: int):
    def g(y) -> int: ...
"""
    assert _unannotated(ast.parse(source)) == [
        "2 m(b)",
        "2 m(c)",
        "3 f -> ?",
        "4 g(y)",
    ]


@pytest.mark.parametrize(
    "path",
    [p for p in _modules() if TYPED in p.parents],
    ids=lambda p: str(p.relative_to(PACKAGE)),
)
def test_the_pipeline_is_annotated(path):
    """Every parameter and return of ``case/pipeline`` has a type: mypy checks
    the bodies of untyped functions, but not what their callers pass them."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    missing = _unannotated(tree)
    assert not missing, f"{path.relative_to(ROOT)}: no annotation at {missing}"


@pytest.mark.parametrize("path", _modules(), ids=lambda p: str(p.relative_to(PACKAGE)))
def test_nothing_imports_upward_from_the_package_root(path):
    """The root ``coastmesh/__init__.py`` is the API over every layer: a module
    in a layer that takes a name from it imports upward. Subpackages by name
    (``from coastmesh import plot``) are imports of those."""
    if path == PACKAGE / "__init__.py":
        return
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom) and node.module == "coastmesh":
            for alias in node.names:
                assert (PACKAGE / alias.name).is_dir() or (
                    PACKAGE / f"{alias.name}.py"
                ).is_file(), (
                    f"{path.relative_to(ROOT)}:{node.lineno} imports {alias.name} "
                    "from the package root"
                )


def test_no_loose_modules_beside_the_stage_packages():
    loose = sorted(
        p.name
        for p in PACKAGE.glob("*.py")
        if p.name not in {"__init__.py", "__main__.py", "errors.py", "version.py"}
    )
    assert loose == [], loose


WRITERS = {"write_text", "write_bytes", "savefig", "to_netcdf", "mkdir", "replace"}


@pytest.mark.parametrize(
    "stage", ["pca", "geometry", "depth", "sizing", "meshing", "types"]
)
def test_the_core_stages_write_no_files(stage):
    """Computation never writes: files are written in io (and by its callers)."""
    for path in sorted((PACKAGE / stage).rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if not isinstance(node, ast.Call):
                continue
            name = getattr(node.func, "attr", getattr(node.func, "id", ""))
            assert name not in WRITERS and name != "open", (
                f"{path.relative_to(ROOT)}:{node.lineno} calls {name}()"
            )


UNIX_ONLY = {"resource", "fcntl", "termios", "pwd", "grp", "posix"}


@pytest.mark.parametrize("path", _modules(), ids=lambda p: str(p.relative_to(PACKAGE)))
def test_no_unix_only_module_at_import_time(path):
    """coastmesh imports on Windows: Unix-only modules only inside functions."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    for node in tree.body:
        names = []
        if isinstance(node, ast.Import):
            names = [a.name.split(".")[0] for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module:
            names = [node.module.split(".")[0]]
        assert not set(names) & UNIX_ONLY, f"{path.name}:{node.lineno} {names}"
