"""Read and write vector files (GeoPackage, shapefile, GeoJSON, FlatGeobuf, ...).

Reading accepts anything GDAL reads; writing picks the driver from the extension
(:mod:`coastmesh.io._drivers`). Both are vectorised: pyogrio's raw interface moves
all features as WKB arrays and shapely 2 converts them in one call.
"""

from __future__ import annotations

import logging
import os
import warnings
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
import pyogrio
import pyogrio.raw
import shapely
from numpy.typing import NDArray
from pyogrio.errors import DataLayerError, DataSourceError, FeatureError, GeometryError
from pyproj import CRS
from pyproj.exceptions import CRSError

from coastmesh.errors import FormatError, InputDataError
from coastmesh.io._atomic import atomic_write
from coastmesh.io._drivers import vector_driver
from coastmesh.io._inputs import check_bbox, check_input
from coastmesh.types import Features

__all__ = ["read_features", "write_features"]

logger = logging.getLogger(__name__)

_GEOMETRY_NAMES = {
    0: "Point",
    1: "LineString",
    2: "LineString",
    3: "Polygon",
    4: "MultiPoint",
    5: "MultiLineString",
    6: "MultiPolygon",
    7: "GeometryCollection",
}
_MULTI_OF = {
    frozenset({3, 6}): "MultiPolygon",
    frozenset({1, 2, 5}): "MultiLineString",
    frozenset({1, 5}): "MultiLineString",
    frozenset({1, 2}): "LineString",
    frozenset({0, 4}): "MultiPoint",
}


def read_features(
    path: str | os.PathLike[str],
    *,
    layer: str | None = None,
    bbox: Sequence[float] | None = None,
) -> Features:
    """Read a vector layer into :class:`~coastmesh.types.Features`.

    Parameters
    ----------
    path : str or path-like
        Any vector file GDAL reads (GeoPackage, shapefile, GeoJSON, ...).
    layer : str, optional
        The layer to read. Needed only when the file holds more than one.
    bbox : sequence of 4 floats, optional
        ``(minx, miny, maxx, maxy)`` in the file's CRS units. Features outside
        are skipped and the others are clipped to the box.

    Returns
    -------
    Features
        Geometries (2-D; a Z coordinate is dropped), CRS (None if the file has
        none), attribute fields, and the feature ids of the layer.

    Raises
    ------
    InputDataError
        If the file is missing, the layer is unknown or has no features (in
        ``bbox``), or the file's CRS is not understood.
    FormatError
        If GDAL cannot read the file as vector data.
    ConfigError
        If ``bbox`` is malformed.

    Examples
    --------
    >>> from coastmesh.data import path as data_path
    >>> coast = read_features(data_path("orkney_gshhg_f.geojson"))
    >>> len(coast), coast.crs.to_epsg()
    (84, 4326)
    """
    source = check_input(path)
    box = None if bbox is None else check_bbox(bbox)
    layer_name = pick_layer(source, layer)
    try:
        with np.errstate(invalid="ignore"):
            meta, fids, wkb, columns = pyogrio.raw.read(
                source,
                layer=layer_name,
                bbox=box,
                return_fids=True,
                force_2d=True,
            )
    except (DataSourceError, DataLayerError, FeatureError, GeometryError) as exc:
        raise InputDataError(
            f"cannot be read: {exc}", path=source, layer=layer_name
        ) from None
    if "Z" in str(meta.get("geometry_type", "")):
        logger.info("%s: Z coordinates dropped (2-D geometries kept)", source)
    if wkb is None:
        raise InputDataError(
            "the layer has no geometry column", path=source, layer=layer_name
        )
    if len(fids) == 0:
        where = f" in bbox {box}" if box is not None else ""
        raise InputDataError(
            f"no features{where}; nothing to do", path=source, layer=layer_name
        )
    with np.errstate(invalid="ignore"):
        geometry = shapely.from_wkb(wkb)
    fields = dict(zip(meta["fields"], columns, strict=True))
    if box is not None:
        geometry = _clip(geometry, box)
        keep = ~shapely.is_empty(geometry) & ~shapely.is_missing(geometry)
        if not keep.any():
            raise InputDataError(
                f"no features in bbox {box}; nothing to do",
                path=source,
                layer=layer_name,
            )
        geometry, fids = geometry[keep], fids[keep]
        fields = {name: values[keep] for name, values in fields.items()}
    crs = _parse_crs(meta.get("crs"), source, layer_name)
    features = Features(
        geometry=geometry,
        crs=crs,
        fields=fields,
        fids=fids,
        path=source,
        layer=layer_name,
    )
    logger.info("read %s, layer %r: %d features", source, layer_name, len(features))
    return features


def write_features(
    path: str | os.PathLike[str],
    features: Features,
    *,
    layer: str | None = None,
    overwrite: bool = False,
    metadata: Mapping[str, str] | None = None,
) -> None:
    """Write features to a vector file, atomically.

    Parameters
    ----------
    path : str or path-like
        The output file; its extension picks the format (``.gpkg``, ``.shp``,
        ``.geojson``/``.json``, ``.fgb``).
    features : Features
        What to write. Polygons and multipolygons mixed are written as
        multipolygons where the format needs one type (likewise for lines).
    layer : str, optional
        The layer name; the file name without extension by default.
    overwrite : bool, default False
        Whether an existing file may be replaced.
    metadata : mapping of str to str, optional
        Key/value notes stored with the data (GeoPackage metadata, or the
        GeoJSON/FlatGeobuf description); shapefiles cannot hold them.

    Raises
    ------
    FormatError
        If the extension is unknown or the driver cannot hold these features.
    OutputExistsError
        If ``path`` exists and ``overwrite`` is false.

    Notes
    -----
    Features keep their order. Shapefiles cut field names to 10 characters
    (GDAL warns).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> points = Features([shapely.Point(0, 0)], "EPSG:4326", {}, [0], "<memory>")
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "points.geojson"
    >>> write_features(path, points)
    >>> len(read_features(path))
    1
    """
    target = Path(path)
    driver = vector_driver(target)
    layer_options = {}
    notes = dict(metadata or {})
    if notes and driver in {"GeoJSON", "FlatGeobuf"}:
        layer_options["DESCRIPTION"] = "; ".join(f"{k}={v}" for k, v in notes.items())
    if driver == "FlatGeobuf":  # its spatial index would reorder the features
        layer_options["SPATIAL_INDEX"] = "NO"
    with atomic_write(target, overwrite=overwrite) as staged:
        write_layer(
            staged,
            features,
            layer=layer if layer is not None else target.stem,
            driver=driver,
            metadata=notes,
            layer_options=layer_options,
            target=target,
        )
    logger.debug("wrote %s: %d features", target, len(features))


def write_layer(
    staged: str | os.PathLike[str],
    features: Features,
    *,
    layer: str,
    driver: str,
    target: str | os.PathLike[str],
    metadata: Mapping[str, str] | None = None,
    layer_options: Mapping[str, str] | None = None,
) -> None:
    """Write features as one layer of a (staged) vector file, with GDAL.

    Parameters
    ----------
    staged : str or path-like
        The file to write to: a staging path from :mod:`coastmesh.io._atomic`.
        A GeoPackage that exists gets one more layer.
    features : Features
        What to write, in order.
    layer : str
        The layer name.
    driver : str
        The GDAL driver (:data:`coastmesh.io._drivers.VECTOR_DRIVERS`).
    target : str or path-like
        The output the staged file becomes, for messages.
    metadata : mapping of str to str, optional
        Dataset metadata (GeoPackage); left out if empty.
    layer_options : mapping of str to str, optional
        GDAL layer creation options.

    Raises
    ------
    FormatError
        If the driver cannot hold these features; the message names ``target``,
        the layer and the driver.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> points = Features([shapely.Point(0, 0)], "EPSG:4326", {}, [0], "<memory>")
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "p.gpkg"
    >>> write_layer(path, points, layer="p", driver="GPKG", target=path)
    >>> pyogrio.list_layers(path)[:, 0].tolist()
    ['p']
    """
    crs = None if features.crs is None else _crs_string(features.crs)
    try:
        with warnings.catch_warnings(), np.errstate(invalid="ignore"):
            warnings.filterwarnings("ignore", message="'crs' was not provided")
            pyogrio.raw.write(
                staged,
                shapely.to_wkb(features.geometry),
                [_writable(values) for values in features.fields.values()],
                list(features.fields),
                layer=layer,
                driver=driver,
                geometry_type=_geometry_type(features.geometry),
                crs=crs,
                encoding="UTF-8" if driver == "ESRI Shapefile" else None,
                dataset_metadata=dict(metadata or {}) or None,
                layer_options=dict(layer_options or {}) or None,
            )
    except (DataSourceError, DataLayerError, FeatureError, GeometryError) as exc:
        raise FormatError(
            f"{os.fspath(target)}, layer {layer!r}: the {driver} driver cannot write "
            f"these features: {exc}"
        ) from None


def pick_layer(source: str, layer: str | None) -> str:
    """Return the layer of ``source`` to read: ``layer``, or the only one.

    Parameters
    ----------
    source : str
        A vector file.
    layer : str, optional
        The layer asked for; None for the only layer of the file.

    Returns
    -------
    str

    Raises
    ------
    FormatError
        If GDAL cannot read ``source`` as vector data.
    InputDataError
        If the file has no layers, several and none is named, or not ``layer``;
        the message lists the layers.

    Examples
    --------
    >>> from coastmesh.data import path as data_path
    >>> pick_layer(str(data_path("orkney_gshhg_f.geojson")), None)
    'orkney_gshhg_f'
    """
    try:
        layers = pyogrio.list_layers(source)
    except DataSourceError as exc:
        reason = str(exc).split(";", 1)[0].strip()
        detail = "" if "not recognized" in reason else f" ({reason})"
        raise FormatError(
            f"{source}: not a vector file GDAL can read{detail}"
        ) from None
    names = [str(name) for name in layers[:, 0]] if len(layers) else []
    if not names:
        raise InputDataError("the file has no layers", path=source)
    if layer is None:
        if len(names) > 1:
            raise InputDataError(
                f"the file has {len(names)} layers ({', '.join(map(repr, names))}); "
                "pick one with --layer",
                path=source,
            )
        return names[0]
    if layer not in names:
        raise InputDataError(
            f"no layer {layer!r}; the layers are {', '.join(map(repr, names))}",
            path=source,
        )
    return layer


def _parse_crs(value: str | None, source: str, layer: str) -> CRS | None:
    if not value:
        return None
    try:
        return CRS.from_user_input(value)
    except CRSError as exc:
        raise InputDataError(
            f"unknown CRS {value!r}: {exc}", path=source, layer=layer
        ) from None


def _clip(
    geometry: NDArray[np.object_], box: tuple[float, float, float, float]
) -> NDArray[np.object_]:
    """Clip to the box; keep only the parts of the input's dimension."""
    clipped = shapely.clip_by_rect(geometry, *box)
    mixed = np.flatnonzero(
        (shapely.get_type_id(clipped) == 7) & ~shapely.is_empty(clipped)
    )
    for i in mixed:
        dimension = shapely.get_dimensions(geometry[i])
        parts = shapely.get_parts(clipped[i])
        parts = parts[shapely.get_dimensions(parts) == dimension]
        clipped[i] = shapely.union_all(parts) if len(parts) else None
    return clipped


def _geometry_type(geometry: NDArray[np.object_]) -> str:
    present = frozenset(int(t) for t in np.unique(shapely.get_type_id(geometry)))
    present = present - {-1}
    if len(present) == 1:
        return _GEOMETRY_NAMES[next(iter(present))]
    return _MULTI_OF.get(present, "Unknown")


def _writable(values: NDArray) -> NDArray:
    if values.dtype.kind == "U":
        return values.astype(object)
    return values


def _crs_string(crs: CRS) -> str:
    authority = crs.to_authority()
    if authority is not None and crs == CRS.from_authority(*authority):
        return ":".join(authority)
    return crs.to_wkt()
