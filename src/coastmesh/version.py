"""The package's version, in the lowest layer: any module may import it.

It is the version of the installed distribution (``pyproject.toml`` holds it,
once); a source tree that is not installed says ``0+unknown``.
"""

from importlib.metadata import PackageNotFoundError, version

__all__ = ["__version__"]

try:
    __version__ = version("coastmesh")
except PackageNotFoundError:  # pragma: no cover - run from a bare source tree
    __version__ = "0+unknown"
