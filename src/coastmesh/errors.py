"""Exception and warning classes of coastmesh.

Every error coastmesh raises derives from :class:`CoastmeshError` and also from the
matching builtin, so ``except ValueError`` keeps working for callers who do not know
about coastmesh.
"""

from __future__ import annotations

__all__ = [
    "CoastmeshError",
    "CoastmeshWarning",
    "ConfigError",
    "FormatError",
    "InputDataError",
    "MeshingError",
    "OutputExistsError",
    "RepairedBoundaryWarning",
    "RepairedGeometryWarning",
]


class CoastmeshError(Exception):
    """Root of every coastmesh exception."""


class ConfigError(CoastmeshError, ValueError):
    """A configuration value or command-line option is invalid."""


class InputDataError(CoastmeshError, ValueError):
    """An input file, layer or feature cannot be used.

    Parameters
    ----------
    message : str
        What is wrong, with the bad value.
    path : str, optional
        The file.
    layer : str, optional
        The layer inside the file.
    feature : int, optional
        The feature id inside the layer.

    Attributes
    ----------
    message : str
        The message without the location, to re-raise with a better one.
    """

    def __init__(
        self,
        message: str,
        *,
        path: str | None = None,
        layer: str | None = None,
        feature: int | None = None,
    ) -> None:
        self.message = message
        self.path = path
        self.layer = layer
        self.feature = feature
        where = []
        if path is not None:
            where.append(str(path))
        if layer is not None:
            where.append(f"layer {layer!r}")
        if feature is not None:
            where.append(f"feature {feature}")
        prefix = ", ".join(where)
        super().__init__(f"{prefix}: {message}" if prefix else message)


class FormatError(CoastmeshError, ValueError):
    """A file format is unknown or cannot hold what is asked of it."""


class MeshingError(CoastmeshError, RuntimeError):
    """The mesh generator failed."""


class OutputExistsError(CoastmeshError, FileExistsError):
    """An output exists and overwriting was not asked for."""


class CoastmeshWarning(UserWarning):
    """Root of coastmesh warnings: recoverable data problems."""


class RepairedGeometryWarning(CoastmeshWarning):
    """Geometries made invalid by smoothing were repaired."""


class RepairedBoundaryWarning(CoastmeshWarning):
    """A mesh file's boundary lists broke its model's rules and were repaired."""
