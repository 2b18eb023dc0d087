"""The progress bar the commands hand to the pipeline."""

from __future__ import annotations

import io
import sys

from coastmesh.cli._common import ProgressBar


class Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_bar_on_a_terminal(monkeypatch):
    screen = Terminal()
    monkeypatch.setattr(sys, "stderr", screen)
    with ProgressBar("points") as progress:
        progress(5, 10)
        progress(10, 10)
    assert "points" in screen.getvalue()
    assert "100%" in screen.getvalue()


def test_no_bar_off_a_terminal_or_when_quiet(monkeypatch):
    screen = io.StringIO()
    monkeypatch.setattr(sys, "stderr", screen)
    with ProgressBar("points") as progress:
        progress(5, 10)
    with ProgressBar("points", enabled=False) as progress:
        progress(5, 10)
    assert screen.getvalue() == ""
