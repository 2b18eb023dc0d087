"""Helpers of the subcommands: error translation and the progress bar."""

from __future__ import annotations

import functools
import sys
import time
from collections.abc import Callable
from typing import Any, TypeVar

import click

__all__ = ["ProgressBar", "translate_errors"]

F = TypeVar("F", bound=Callable[..., Any])

_REFRESH_SECONDS = 0.1


def translate_errors(command: F) -> F:
    """Turn coastmesh errors into click errors: usage errors exit 2, others 1."""

    @functools.wraps(command)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        from coastmesh.errors import CoastmeshError, ConfigError

        try:
            return command(*args, **kwargs)
        except ConfigError as exc:
            raise click.UsageError(str(exc), ctx=click.get_current_context()) from None
        except CoastmeshError as exc:
            raise click.ClickException(str(exc)) from None
        except OSError as exc:
            raise click.ClickException(_describe_os_error(exc)) from None

    return wrapper  # type: ignore[return-value]


def _describe_os_error(exc: OSError) -> str:
    if exc.filename is not None and exc.strerror:
        return f"{exc.filename}: {exc.strerror}"
    return str(exc)


class ProgressBar:
    """A ``progress(done, total)`` callback drawing a click progress bar to stderr.

    The bar starts on the first call and is redrawn at most every 0.1 s. Use as
    a context manager so the bar is finished (or never drawn when quiet).

    Parameters
    ----------
    label : str
        Shown before the bar.
    enabled : bool
        False draws nothing; nothing is drawn either when stderr is not a
        terminal.
    """

    def __init__(self, label: str, *, enabled: bool = True) -> None:
        self.label = label
        self.enabled = enabled
        self._bar: Any = None
        self._shown = 0
        self._last = 0.0

    def __call__(self, done: int, total: int) -> None:
        if not self.enabled:
            return
        if self._bar is None:
            stream = sys.stderr
            if not stream.isatty():
                self.enabled = False
                return
            self._bar = click.progressbar(
                length=max(int(total), 1), label=self.label, file=stream
            )
            self._bar.__enter__()
        now = time.monotonic()
        if done >= total or now - self._last >= _REFRESH_SECONDS:
            self._bar.update(int(done) - self._shown)
            self._shown = int(done)
            self._last = now

    def __enter__(self) -> ProgressBar:
        return self

    def __exit__(self, *exc: object) -> None:
        if self._bar is not None:
            self._bar.__exit__(None, None, None)
            self._bar = None
