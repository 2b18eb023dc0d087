"""Text tables of numbers: fixed-width writing, line-by-line reading.

The ADCIRC/SCHISM grid files and MIKE ``.mesh`` files are text tables: a header
line with counts, then one row of numbers per node or element. Writing formats
the rows with numpy in blocks (no Python loop per row), so meshes of millions of
triangles write in seconds. Reading goes line by line through :class:`TextLines`,
whose errors name the file, the line number and what the line should hold.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import IO, Any

import numpy as np
from numpy.typing import NDArray

from coastmesh.errors import InputDataError

__all__ = ["TextLines", "put_lines", "write_table"]

_CHUNK = 1 << 19  # rows formatted per block: bounds the memory of the text
_POW10 = 10 ** np.arange(19, dtype=np.int64)
# "0000" ... "9999" as uint32 words: four ASCII digits per table lookup
_QUADS = np.frombuffer("".join(f"{i:04d}" for i in range(10000)).encode(), np.uint32)


def put_lines(handle: IO[bytes], *lines: str) -> None:
    r"""Write lines of text, each ended by a newline, as UTF-8.

    Parameters
    ----------
    handle : binary file
        Open for writing.
    *lines : str
        The lines, without their newlines.

    Examples
    --------
    >>> import io
    >>> out = io.BytesIO()
    >>> put_lines(out, "title", "2 3")
    >>> out.getvalue()
    b'title\n2 3\n'
    """
    handle.write("".join(f"{line}\n" for line in lines).encode("utf-8"))


def write_table(
    handle: IO[bytes], columns: Sequence[tuple[NDArray[Any], int | None]]
) -> None:
    """Write rows of numbers, right-aligned in columns, one row per line.

    Parameters
    ----------
    handle : binary file
        Open for writing.
    columns : sequence of (array of shape (R,), int or None)
        The values of each column and how to write them: ``None`` for integers,
        else the number of significant digits of floats, written in fixed point
        with the same decimals down the column (so that its largest value keeps
        that many digits).

    Raises
    ------
    ValueError
        If the columns differ in length or a float is not finite or >= 1e18.

    Notes
    -----
    Each block of rows becomes one ``uint8`` array of characters: digits come
    four at a time from a lookup table, so there is no Python loop per row.

    Examples
    --------
    >>> import io
    >>> out = io.BytesIO()
    >>> write_table(out, [(np.array([1, 20]), None), (np.array([-1.5, 2.25]), 4)])
    >>> print(out.getvalue().decode(), end="")
     1 -1.500
    20  2.250
    """
    specs = [_column(np.asarray(values), digits) for values, digits in columns]
    rows = {len(spec[0]) for spec in specs}
    if len(rows) != 1:
        raise ValueError(f"columns have different lengths: {sorted(rows)}")
    (n,) = rows
    for start in range(0, n, _CHUNK):
        stop = min(start + _CHUNK, n)
        parts = []
        for k, spec in enumerate(specs):
            if k:
                parts.append(np.full((stop - start, 1), ord(" "), np.uint8))
            parts.append(_render(spec, start, stop))
        parts.append(np.full((stop - start, 1), ord("\n"), np.uint8))
        handle.write(np.hstack(parts).tobytes())


def _column(
    values: NDArray[Any], digits: int | None
) -> tuple[NDArray[Any], int | None, int]:
    """(values, decimals or None for integers, width of the integer part)."""
    if values.ndim != 1:
        raise ValueError(f"a column has shape {values.shape}, expected (R,)")
    if digits is None:
        values = values.astype(np.int64)
        top = int(np.abs(values).max(initial=0))
        return values, None, _ndigits(top) + int((values < 0).any())
    values = values.astype(np.float64)
    if not np.isfinite(values).all():
        raise ValueError("a column has non-finite values")
    largest = float(np.abs(values).max(initial=0.0))
    if largest >= 1e18:
        raise ValueError(f"a column has |values| up to {largest:g}; expected < 1e18")
    decimals = max(0, digits - _ndigits(int(largest)))
    unit = 10.0**-decimals
    widest = int(np.rint(largest / unit)) // 10**decimals
    negative = bool((values <= -0.5 * unit).any())
    return values, decimals, _ndigits(widest) + int(negative)


def _render(
    spec: tuple[NDArray[Any], int | None, int], start: int, stop: int
) -> NDArray[np.uint8]:
    values, decimals, width = spec
    chunk = values[start:stop]
    if decimals is None:
        return _signed(np.abs(chunk), chunk < 0, width)
    scaled = np.rint(np.abs(chunk) * 10.0**decimals).astype(np.int64)
    whole, fraction = np.divmod(scaled, np.int64(10) ** decimals)
    head = _signed(whole, (chunk < 0) & (scaled != 0), width)
    if decimals == 0:
        return head
    dot = np.full((len(chunk), 1), ord("."), np.uint8)
    return np.hstack([head, dot, _digits(fraction, decimals)])


def _signed(
    magnitude: NDArray[np.int64], negative: NDArray[np.bool_], width: int
) -> NDArray[np.uint8]:
    """Right-aligned decimal text of ``magnitude``, a minus sign where negative."""
    text = _digits(magnitude, width)
    lead = width - np.maximum(np.searchsorted(_POW10, magnitude, side="right"), 1)
    blank = np.arange(width)[None, :] < lead[:, None]
    text[blank] = ord(" ")
    rows = np.flatnonzero(negative)
    text[rows, lead[rows] - 1] = ord("-")
    return text


def _digits(values: NDArray[np.int64], width: int) -> NDArray[np.uint8]:
    """Zero-padded decimal digits of non-negative ``values``, shape (R, width)."""
    words = -(-width // 4)
    out = np.empty((len(values), words), np.uint32)
    rest = values
    for k in range(words - 1, -1, -1):
        rest, quad = np.divmod(rest, 10000)
        out[:, k] = _QUADS[quad]
    return np.ascontiguousarray(out.view(np.uint8)[:, 4 * words - width :])


def _ndigits(value: int) -> int:
    return max(len(str(abs(int(value)))), 1)


class TextLines:
    """The lines of a text file, read in order; errors name the file and line.

    Parameters
    ----------
    path : str or path-like
        The file, for messages.
    lines : list of str
        Its lines.

    Examples
    --------
    >>> lines = TextLines("fort.14", ["2 3", "1 0.5 x"])
    >>> lines.ints(2, "NE NP")
    [2, 3]
    >>> lines.table(1, 3, float, "JN X Y")
    Traceback (most recent call last):
    ...
    coastmesh.errors.InputDataError: fort.14: line 2 (JN X Y): a value is not a ...
    """

    def __init__(self, path: str | os.PathLike[str], lines: list[str]) -> None:
        self.path = os.fspath(path)
        self.lines = lines
        self.at = 0

    @classmethod
    def read(cls, path: str | os.PathLike[str]) -> TextLines:
        """Read the lines of the text file ``path`` (UTF-8, bad bytes replaced).

        Parameters
        ----------
        path : str or path-like
            The file.

        Returns
        -------
        TextLines
        """
        with open(path, encoding="utf-8", errors="replace") as handle:
            return cls(path, handle.read().splitlines())

    def error(self, what: str, problem: str) -> InputDataError:
        """Return the error for the line last read: what it should hold, and why."""
        text = self.lines[self.at - 1] if 0 < self.at <= len(self.lines) else ""
        return InputDataError(
            f"line {self.at} ({what}): {problem}; found {text.strip()[:60]!r}",
            path=self.path,
        )

    def next_line(self) -> str:
        """Return the next line; raise if the file has ended."""
        if self.at >= len(self.lines):
            self.at += 1
            raise InputDataError(
                f"the file ends at line {len(self.lines)}; more lines expected",
                path=self.path,
            )
        self.at += 1
        return self.lines[self.at - 1]

    def fields(self, k: int, what: str) -> list[str]:
        """Return the first ``k`` words of the next line; raise if it has fewer."""
        found = self.next_line().split()
        if len(found) < k:
            raise self.error(what, f"expected {k} values")
        return found[:k]

    def ints(self, k: int, what: str) -> list[int]:
        """Return the first ``k`` words of the next line as integers."""
        fields = self.fields(k, what)
        try:
            return [int(f) for f in fields]
        except ValueError:
            raise self.error(what, f"expected {k} integers") from None

    def table(self, count: int, k: int, kind: type, what: str) -> NDArray[Any]:
        """Return the first ``k`` numbers of each of the next ``count`` lines.

        Parameters
        ----------
        count : int
            The number of lines.
        k : int
            The numbers taken from each line; more words are ignored.
        kind : type
            ``int`` or ``float``.
        what : str
            What the lines hold, for messages (``"JN X Y DP"``).

        Returns
        -------
        ndarray of shape (count, k)
        """
        rows = [self.fields(k, what) for _ in range(count)]
        try:
            return np.array(rows, dtype=kind).reshape(count, k)
        except ValueError:
            first = self.at - count
            for offset, row in enumerate(rows):
                try:
                    [kind(f) for f in row]
                except ValueError:
                    self.at = first + offset + 1
                    raise self.error(what, "a value is not a number") from None
            raise

    def count_and_rest(self, what: str) -> tuple[int, str]:
        """Return the leading integer of the next line and the text after it."""
        found = self.next_line().split(maxsplit=1)
        try:
            count = int(found[0])
        except (IndexError, ValueError):
            raise self.error(what, "expected an integer count") from None
        return count, found[1] if len(found) > 1 else ""

    def remaining(self) -> int:
        """Return the number of non-blank lines not read yet."""
        return sum(1 for line in self.lines[self.at :] if line.strip())
