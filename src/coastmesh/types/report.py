"""Reports: what a step did, as data (:meth:`Report.to_dict`) and as text.

Every report of coastmesh is a frozen dataclass deriving from :class:`Report`.
:meth:`Report.to_dict` turns it into JSON-ready data field by field, so files
such as ``report.json`` are written from it and never re-mapped by hand.
"""

from __future__ import annotations

import dataclasses
import math
import os
from collections.abc import Mapping
from typing import Any

import numpy as np

__all__ = ["Report", "json_ready"]


class Report:
    """Base of the report dataclasses: ``to_dict()`` and ``summary()``.

    Subclasses are ``@dataclass(frozen=True, slots=True)`` and implement
    :meth:`summary`. :meth:`to_dict` converts every field with
    :func:`json_ready`; a field declared with ``metadata={"to_dict": False}``
    is left out.

    Examples
    --------
    >>> from dataclasses import dataclass
    >>> @dataclass(frozen=True, slots=True)
    ... class Counted(Report):
    ...     items: int
    ...     def summary(self) -> str:
    ...         return f"{self.items} items"
    >>> Counted(3).to_dict(), Counted(3).summary()
    ({'items': 3}, '3 items')
    """

    __slots__ = ()

    def to_dict(self) -> dict[str, Any]:
        """Return the report as JSON-ready data (see :func:`json_ready`).

        Returns
        -------
        dict
            One entry per field, in field order.
        """
        return {
            f.name: json_ready(getattr(self, f.name))
            for f in dataclasses.fields(self)  # type: ignore[arg-type]
            if f.metadata.get("to_dict", True)
        }

    def summary(self) -> str:
        """Return the report as text for people, one line unless it says otherwise."""
        raise NotImplementedError(f"{type(self).__name__} has no summary()")


def json_ready(value: Any) -> Any:  # noqa: PLR0911 (one return per kind)
    """Return ``value`` as data :func:`json.dumps` takes as it is.

    Reports and objects with a ``to_dict()`` method become their dict; mappings
    become dicts with string keys; sequences and arrays become lists; numpy
    scalars become Python numbers; paths and CRSs become strings; non-finite
    floats become None.

    Parameters
    ----------
    value : object
        What to convert.

    Returns
    -------
    object
        None, bool, int, float, str, list or dict.

    Examples
    --------
    >>> import numpy as np
    >>> json_ready({1: np.float32(0.5), "ids": np.arange(2), "x": float("nan")})
    {'1': 0.5, 'ids': [0, 1], 'x': None}
    """
    if value is None or isinstance(value, bool | str):
        return value
    if hasattr(value, "to_dict"):
        return value.to_dict()
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, int):
        return value
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    if isinstance(value, Mapping):
        return {str(k): json_ready(v) for k, v in value.items()}
    if isinstance(value, np.ndarray | list | tuple | set | frozenset):
        items = sorted(value) if isinstance(value, set | frozenset) else value
        return [json_ready(v) for v in items]
    if hasattr(value, "to_string") and hasattr(value, "to_wkt"):  # pyproj.CRS
        return value.to_string()
    raise TypeError(f"cannot put a {type(value).__name__} into a report: {value!r}")
