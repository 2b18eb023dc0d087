"""Checks shared by the core types."""

from __future__ import annotations

import numpy as np

__all__ = ["check_positive_int"]


def check_positive_int(value: object, name: str) -> None:
    if isinstance(value, bool) or not isinstance(value, int | np.integer):
        raise ValueError(f"{name} is {value!r}, expected an integer > 0")
    if value <= 0:
        raise ValueError(f"{name} is {value}, expected an integer > 0")
