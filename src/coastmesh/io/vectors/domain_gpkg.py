"""Write a meshing domain, and other layers with it, to one GeoPackage.

A GeoPackage holds several layers, so one file can carry the domain polygon, its
tagged boundary segments and any helper layers (untrimmed open-boundary lines,
region polygons) for a look in a GIS. All layers are written into one staged file
that is published only when every layer is written (:mod:`coastmesh.io._atomic`).
"""

from __future__ import annotations

import logging
import os
from collections.abc import Mapping
from pathlib import Path

import numpy as np
import shapely
from pyproj import CRS, Geod

from coastmesh.errors import ConfigError, FormatError
from coastmesh.io._atomic import atomic_write
from coastmesh.types import Domain, Features

__all__ = ["segment_lengths", "write_domain", "write_layers"]

logger = logging.getLogger(__name__)

DOMAIN_LAYERS = ("domain", "boundaries")


def write_domain(
    path: str | os.PathLike[str],
    domain: Domain,
    *,
    overwrite: bool = False,
    metadata: Mapping[str, str] | None = None,
    extra_layers: Mapping[str, Features] | None = None,
) -> None:
    """Write a domain to a GeoPackage, atomically.

    Parameters
    ----------
    path : str or path-like
        The output file; must end in ``.gpkg``.
    domain : Domain
        The domain to write.
    overwrite : bool, default False
        Whether an existing file may be replaced.
    metadata : mapping of str to str, optional
        Key/value notes stored as GeoPackage dataset metadata.
    extra_layers : mapping of str to Features, optional
        More layers to write into the same file, by layer name, each in its own
        CRS. The names ``domain`` and ``boundaries`` are taken.

    Raises
    ------
    FormatError
        If ``path`` does not end in ``.gpkg``, or GDAL cannot write a layer.
    ConfigError
        If an extra layer name is empty or clashes with another layer
        (GeoPackage layer names ignore case).
    OutputExistsError
        If ``path`` exists and ``overwrite`` is false.

    Notes
    -----
    Layer ``domain`` holds the polygon with field ``surface_id``. Layer
    ``boundaries`` holds one LineString per boundary segment, in order, with
    fields ``name``, ``kind``, ``physical_id`` and ``length_m``
    (:func:`segment_lengths`).

    Examples
    --------
    >>> import tempfile, pathlib, pyogrio
    >>> import shapely
    >>> from coastmesh.types import BoundarySegment
    >>> ring = [[0, 0], [1000, 0], [1000, 1000], [0, 1000], [0, 0]]
    >>> domain = Domain(
    ...     shapely.Polygon(ring),
    ...     (
    ...         BoundarySegment(ring[:3], "open", "sea", 2),
    ...         BoundarySegment(ring[2:], "shoreline", "coast", 1),
    ...     ),
    ...     crs="EPSG:32630",
    ... )
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "domain.gpkg"
    >>> write_domain(path, domain)
    >>> pyogrio.list_layers(path)[:, 0].tolist()
    ['domain', 'boundaries']
    """
    extras = dict(extra_layers or {})
    _check_layer_names([*DOMAIN_LAYERS, *extras], path)
    segments = domain.segments
    count = len(segments)
    layers = {
        "domain": Features(
            geometry=np.array([domain.polygon], dtype=object),
            crs=domain.crs,
            fields={"surface_id": np.array([domain.surface_id], dtype=np.int64)},
            fids=np.array([0], dtype=np.int64),
            path="<memory>",
            layer="domain",
        ),
        "boundaries": Features(
            geometry=_linestrings([s.coords for s in segments]),
            crs=domain.crs,
            fields={
                "name": np.array([s.name for s in segments], dtype=object),
                "kind": np.array([s.kind for s in segments], dtype=object),
                "physical_id": np.array(
                    [s.physical_id for s in segments], dtype=np.int64
                ),
                "length_m": segment_lengths(domain),
            },
            fids=np.arange(count),
            path="<memory>",
            layer="boundaries",
        ),
        **extras,
    }
    write_layers(path, layers, overwrite=overwrite, metadata=metadata)
    logger.debug(
        "wrote domain %s: %d boundary segments, %d extra layers",
        path,
        count,
        len(extras),
    )


def segment_lengths(domain: Domain) -> np.ndarray:
    """Return the length of each boundary segment of a domain, in metres.

    Parameters
    ----------
    domain : Domain
        The domain.

    Returns
    -------
    ndarray of shape (S,), float64
        One length per segment, in metres: geodesic on the WGS84 ellipsoid when
        the CRS is geographic (x = longitude, y = latitude, degrees), else the
        planar length times the CRS's linear unit in metres.

    Examples
    --------
    >>> import shapely
    >>> from coastmesh.types import BoundarySegment
    >>> ring = [[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]]
    >>> domain = Domain(
    ...     shapely.Polygon(ring),
    ...     (BoundarySegment(ring, "shoreline", "coast", 1),),
    ...     crs="EPSG:4326",
    ... )
    >>> segment_lengths(domain).round(-3).tolist()  # about 4 x 111 km
    [444000.0]
    """
    crs = domain.crs
    if crs.is_geographic:
        geod = Geod(ellps="WGS84")
        return np.array(
            [geod.line_length(s.coords[:, 0], s.coords[:, 1]) for s in domain.segments],
            dtype=np.float64,
        )
    planar = shapely.length(_linestrings([s.coords for s in domain.segments]))
    return np.asarray(planar, dtype=np.float64) * _metres_per_unit(crs)


def write_layers(
    path: str | os.PathLike[str],
    layers: Mapping[str, Features],
    *,
    overwrite: bool = False,
    metadata: Mapping[str, str] | None = None,
) -> None:
    """Write several layers into one GeoPackage, atomically as a whole.

    Parameters
    ----------
    path : str or path-like
        The output file; must end in ``.gpkg``.
    layers : mapping of str to Features
        The layers, by name, written in this order; at least one.
    overwrite : bool, default False
        Whether an existing file may be replaced.
    metadata : mapping of str to str, optional
        Key/value notes stored as GeoPackage dataset metadata.

    Raises
    ------
    FormatError
        If ``path`` does not end in ``.gpkg``, or GDAL cannot write a layer.
    ConfigError
        If ``layers`` is empty, or two names differ only in case.
    OutputExistsError
        If ``path`` exists and ``overwrite`` is false.

    Notes
    -----
    Every layer goes into the same staged file, which replaces ``path`` only
    after the last layer is written; a failure leaves ``path`` as it was.

    Examples
    --------
    >>> import tempfile, pathlib, pyogrio
    >>> import shapely
    >>> points = Features([shapely.Point(0, 0)], "EPSG:4326", {}, [0], "<memory>")
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "two.gpkg"
    >>> write_layers(path, {"a": points, "b": points})
    >>> pyogrio.list_layers(path)[:, 0].tolist()
    ['a', 'b']
    """
    from coastmesh.io.vectors.vector import write_layer

    target = Path(path)
    if target.suffix.lower() != ".gpkg":
        raise FormatError(
            f"{os.fspath(path)}: a multi-layer output must be a GeoPackage; "
            "use the extension .gpkg"
        )
    if not layers:
        raise ConfigError(f"{os.fspath(path)}: no layers to write")
    _check_layer_names(list(layers), path)
    notes = {str(k): str(v) for k, v in dict(metadata or {}).items()}
    with atomic_write(target, overwrite=overwrite) as staged:
        for i, (name, features) in enumerate(layers.items()):
            write_layer(
                staged,
                features,
                layer=name,
                driver="GPKG",
                target=target,
                metadata=notes if i == 0 else None,
            )
            logger.debug("%s: layer %r, %d features", target, name, len(features))


def _linestrings(parts: list[np.ndarray]) -> np.ndarray:
    """Build one LineString per ``(k, 2)`` array in one vectorised call."""
    if not parts:
        return np.empty(0, dtype=object)
    sizes = [len(part) for part in parts]
    indices = np.repeat(np.arange(len(parts)), sizes)
    return shapely.linestrings(np.concatenate(parts), indices=indices)


def _check_layer_names(names: list[str], path: str | os.PathLike[str]) -> None:
    seen: dict[str, str] = {}
    for name in names:
        if not isinstance(name, str) or not name.strip():
            raise ConfigError(
                f"{os.fspath(path)}: layer name {name!r} is not a non-empty string"
            )
        key = name.lower()
        if key in seen:
            raise ConfigError(
                f"{os.fspath(path)}: layer name {name!r} clashes with "
                f"{seen[key]!r} (GeoPackage layer names ignore case); "
                "pick another name"
            )
        seen[key] = name


def _metres_per_unit(crs: CRS) -> float:
    axes = crs.axis_info
    if not axes or axes[0].unit_conversion_factor is None:
        return 1.0
    return float(axes[0].unit_conversion_factor)
