"""The command line asks numpy for ordinary pages unless the user chose."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

_PROBE = (
    "import os, sys\n"
    "from coastmesh.cli.main import small_pages\n"
    "small_pages()\n"
    "import numpy\n"
    "from numpy._core import multiarray\n"
    "print(os.environ.get('NUMPY_MADVISE_HUGEPAGE'),"
    " multiarray._get_madvise_hugepage())\n"
)


@pytest.mark.parametrize(
    ("given", "expected"),
    [(None, "0 False"), ("1", "1 True"), ("0", "0 False")],
)
def test_the_command_line_leaves_huge_pages_off_unless_asked(given, expected):
    env = {k: v for k, v in os.environ.items() if k != "NUMPY_MADVISE_HUGEPAGE"}
    if given is not None:
        env["NUMPY_MADVISE_HUGEPAGE"] = given
    out = subprocess.run(
        [sys.executable, "-c", _PROBE],
        check=False,
        env=env,
        capture_output=True,
        text=True,
    )
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == expected


def test_a_process_that_has_numpy_already_keeps_its_environment(monkeypatch):
    # main() called from Python after numpy was imported: nothing is changed
    from coastmesh.cli.main import small_pages

    monkeypatch.delenv("NUMPY_MADVISE_HUGEPAGE", raising=False)
    small_pages()
    assert "NUMPY_MADVISE_HUGEPAGE" not in os.environ
