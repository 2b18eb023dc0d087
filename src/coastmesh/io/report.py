"""Write a report as JSON, and its summary as text, together or not at all.

A report is any object with ``to_dict()`` (JSON-ready data) and ``summary()``
(text for people), such as every :class:`coastmesh.types.Report`. The JSON is
written from ``to_dict()`` as it is, never re-mapped by hand.
"""

from __future__ import annotations

import json
import logging
import os
from typing import Any, Protocol

from coastmesh.errors import FormatError
from coastmesh.io._atomic import AtomicOutputs

__all__ = ["write_report"]

logger = logging.getLogger(__name__)


class _Reporting(Protocol):
    def to_dict(self) -> dict[str, Any]: ...

    def summary(self) -> str: ...


def write_report(
    path: str | os.PathLike[str],
    report: _Reporting,
    *,
    summary: str | os.PathLike[str] | None = None,
    overwrite: bool = False,
) -> None:
    r"""Write ``report.to_dict()`` as indented JSON, and ``report.summary()`` as text.

    Parameters
    ----------
    path : str or path-like
        The JSON file, such as ``quality.json``.
    report : object with ``to_dict()`` and ``summary()``
        Such as a :class:`coastmesh.types.Report`; it is not changed.
    summary : str or path-like, optional
        A text file for ``report.summary()``, such as ``quality.txt``.
    overwrite : bool, default False
        Whether existing files may be replaced.

    Raises
    ------
    TypeError
        If ``report`` has no ``to_dict()`` or ``summary()`` method.
    FormatError
        If ``to_dict()`` returns data JSON cannot hold (such as NaN, or an
        object); the message names ``path``.
    OutputExistsError
        If ``path`` or ``summary`` exists and ``overwrite`` is false.
    ConfigError
        If ``summary`` is ``path``.

    Notes
    -----
    Both files are staged and published together (:class:`AtomicOutputs
    <coastmesh.io.AtomicOutputs>`): if either cannot be written, neither is,
    and existing files stay as they were. The JSON is UTF-8 with an indent of 2
    and a final newline; the summary text ends with a newline too.

    Examples
    --------
    >>> import json, tempfile, pathlib
    >>> from dataclasses import dataclass
    >>> from coastmesh.types import Report
    >>> @dataclass(frozen=True, slots=True)
    ... class Counted(Report):
    ...     items: int
    ...     def summary(self) -> str:
    ...         return f"{self.items} items"
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> write_report(folder / "r.json", Counted(3), summary=folder / "r.txt")
    >>> json.loads((folder / "r.json").read_text()), (folder / "r.txt").read_text()
    ({'items': 3}, '3 items\n')
    """
    for method in ("to_dict", "summary"):
        if not callable(getattr(report, method, None)):
            raise TypeError(
                f"report is a {type(report).__name__}, which has no {method}() "
                "method; expected a report such as coastmesh.types.Report"
            )
    try:
        data = json.dumps(report.to_dict(), indent=2, allow_nan=False) + "\n"
    except (TypeError, ValueError) as exc:
        raise FormatError(
            f"{os.fspath(path)}: the report's to_dict() is not JSON data ({exc})"
        ) from None
    text = None if summary is None else report.summary().rstrip("\n") + "\n"
    with AtomicOutputs(overwrite=overwrite) as outputs:
        staged = outputs.stage(path)
        staged_summary = None if summary is None else outputs.stage(summary)
        staged.write_text(data, encoding="utf-8")
        if staged_summary is not None and text is not None:
            staged_summary.write_text(text, encoding="utf-8")
    logger.debug("wrote %s%s", path, "" if summary is None else f" and {summary}")
