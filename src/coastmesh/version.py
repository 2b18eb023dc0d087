"""The package's version, in the lowest layer: any module may import it.

A constant, not read from the installed metadata: ``importlib.metadata`` would
add 60 ms to ``import coastmesh`` (the command line's start). A test checks it
is ``pyproject.toml``'s.
"""

__all__ = ["__version__"]

__version__ = "0.1.0"
