"""Helpers of the whole-run commands: output checks, CRS handling, provenance."""

from __future__ import annotations

import os
from dataclasses import replace
from datetime import UTC, datetime

from pyproj import CRS
from pyproj.exceptions import CRSError

from coastmesh.errors import ConfigError, InputDataError
from coastmesh.io import check_output, plot_format
from coastmesh.types import Features

__all__ = [
    "PathLike",
    "check_crs",
    "check_outputs",
    "listed",
    "locate",
    "modes_label",
    "parse_crs",
    "provenance",
    "with_crs",
]

PathLike = str | os.PathLike[str]


def listed(dst: PathLike, plot: PathLike | None) -> str:
    return os.fspath(dst) + ("" if plot is None else f" and {os.fspath(plot)}")


def modes_label(modes: int) -> str:
    return f"{modes} mode" if modes == 1 else f"{modes} modes"


def check_outputs(dst: PathLike, plot: PathLike | None, *, overwrite: bool) -> None:
    check_output(dst, overwrite=overwrite)
    if plot is not None:
        plot_format(plot)
        check_output(plot, overwrite=overwrite)
        if os.path.abspath(plot) == os.path.abspath(dst):
            raise ConfigError(f"plot = {os.fspath(plot)}: the same file as the output")


def parse_crs(crs: CRS | str | None) -> CRS | None:
    if crs is None or isinstance(crs, CRS):
        return crs
    try:
        return CRS.from_user_input(crs)
    except CRSError as exc:
        raise ConfigError(f"crs = {crs!r}: not a CRS pyproj knows ({exc})") from None


def check_crs(
    declared: CRS | None,
    given: CRS | None,
    what: str,
    path: PathLike,
    layer: str | None = None,
) -> None:
    """Check a file's CRS against ``--crs``: one is needed, and they must agree.

    Raises
    ------
    InputDataError
        If the file declares no CRS and none is given.
    ConfigError
        If the file declares one and ``given`` is another.
    """
    if declared is None and given is None:
        raise InputDataError(
            f"the {what} has no CRS; give one with --crs (e.g. --crs EPSG:4326)",
            path=os.fspath(path),
            layer=layer,
        )
    if declared is not None and given is not None and declared != given:
        raise ConfigError(
            f"crs = {given.to_string()!r}, but {os.fspath(path)} declares "
            f"{declared.to_string()!r}; --crs is only for files without one"
        )


def with_crs(features: Features, crs: CRS | None) -> Features:
    """Return ``features`` with a CRS: their own, else ``crs`` (:func:`check_crs`)."""
    check_crs(features.crs, crs, "layer", features.path, features.layer)
    return features if features.crs is not None else replace(features, crs=crs)


def locate(exc: InputDataError, features: Features) -> InputDataError:
    """Return ``exc`` again, naming the file, layer and feature id."""
    if exc.feature is None:
        return InputDataError(exc.message, path=features.path, layer=features.layer)
    return InputDataError(
        exc.message,
        path=features.path,
        layer=features.layer,
        feature=int(features.fids[exc.feature]),
    )


def provenance(command: str, src: PathLike, **parameters: object) -> dict[str, str]:
    from coastmesh.version import __version__

    settings = " ".join(f"--{k} {v}" for k, v in parameters.items())
    stamp = datetime.now(UTC).strftime("%Y-%m-%dT%H:%M:%SZ")
    notes = {
        "history": f"{stamp} coastmesh {__version__} {command} {os.fspath(src)} "
        f"{settings}",
        "coastmesh_version": __version__,
        "coastmesh_command": command,
        "coastmesh_source": os.fspath(src),
    }
    notes.update({f"coastmesh_{k}": str(v) for k, v in parameters.items()})
    return notes
