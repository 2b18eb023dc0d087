"""BLAS threading for the small matrices of the contour kernel."""

from __future__ import annotations

import functools
from contextlib import AbstractContextManager

from threadpoolctl import ThreadpoolController

__all__ = ["single_threaded_blas"]


@functools.cache
def _controller() -> ThreadpoolController:
    return ThreadpoolController()


def single_threaded_blas() -> AbstractContextManager:
    """Limit BLAS to one thread inside a ``with`` block.

    The contour kernel works on matrices of at most a few hundred rows, where
    OpenBLAS threads cost more than they give (measured: an L = 100 eigenproblem
    takes 2 ms with two threads and 0.3 ms with one). Entering costs ~15 us.
    """
    return _controller().limit(limits=1, user_api="blas")
