"""Work on a side thread, or at once: one call for both (``threads`` 1 or more)."""

from __future__ import annotations

from concurrent.futures import Future
from typing import Any

__all__ = ["done_now"]


def done_now(fn: Any, *args: Any) -> Future[Any]:
    """Call ``fn(*args)`` now; return its result (or error) as a done Future.

    Stands in for ``executor.submit`` on one thread, so that the caller reads
    ``.result()`` either way (and an error is raised there, as a thread's is).

    Examples
    --------
    >>> done_now(max, 2, 3).result()
    3
    """
    future: Future[Any] = Future()
    try:
        future.set_result(fn(*args))
    except Exception as exc:  # raised by .result(), as a thread's would be
        future.set_exception(exc)
    return future
