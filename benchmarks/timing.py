"""Timing shared by the benchmark scripts (run them from the repository root)."""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

import numpy as np


def best_time(func: Callable[[], Any], repeat: int = 3) -> tuple[float, Any]:
    """Run ``func`` ``repeat`` times; return the shortest wall time and a result."""
    best, result = np.inf, None
    for _ in range(repeat):
        start = time.perf_counter()
        result = func()
        best = min(best, time.perf_counter() - start)
    return best, result
