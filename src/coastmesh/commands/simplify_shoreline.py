"""``coastmesh simplify-shoreline``: PCA of every ring and line of a vector file."""

from __future__ import annotations

import logging
import os
import warnings
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import shapely
from pyproj import CRS

from coastmesh.commands._common import (
    PathLike,
    check_outputs,
    listed,
    locate,
    modes_label,
    parse_crs,
    provenance,
    with_crs,
)
from coastmesh.errors import CoastmeshWarning, InputDataError
from coastmesh.geometry import (
    ShorelineReport,
    check_coordinates,
    simplify_shorelines,
)
from coastmesh.io import (
    AtomicOutputs,
    check_bbox,
    read_features,
    vector_driver,
    write_features,
)
from coastmesh.pca import check_modes, check_window
from coastmesh.types import Features, Progress

__all__ = ["simplify_shoreline_file"]

logger = logging.getLogger(__name__)

_SHORELINE_TYPES = (
    shapely.GeometryType.LINESTRING,
    shapely.GeometryType.LINEARRING,
    shapely.GeometryType.POLYGON,
    shapely.GeometryType.MULTILINESTRING,
    shapely.GeometryType.MULTIPOLYGON,
)


def simplify_shoreline_file(
    src: PathLike,
    dst: PathLike,
    *,
    window: int,
    modes: int,
    layer: str | None = None,
    bbox: Sequence[float] | None = None,
    crs: CRS | str | None = None,
    overwrite: bool = False,
    plot: PathLike | None = None,
    progress: Progress | None = None,
) -> ShorelineReport:
    """Approximate every ring and line of a vector layer by PCA and write it.

    Parameters
    ----------
    src : str or path-like
        Any vector file GDAL reads, with polygons and/or lines.
    dst : str or path-like
        The output file (``.gpkg``, ``.shp``, ``.geojson``, ``.fgb``). Attributes
        and CRS are kept; features whose every contour is shorter than the window
        are left out.
    window : int
        Partition size in points (vertices), ``>= 2``.
    modes : int
        Leading modes kept, ``1 <= modes <= window``.
    layer : str, optional
        The layer of ``src``; needed if it has several.
    bbox : sequence of 4 floats, optional
        ``(minx, miny, maxx, maxy)`` in the CRS units of ``src``: clip to it first.
    crs : pyproj.CRS or str, optional
        CRS of ``src`` if the file declares none.
    overwrite : bool, default False
        Whether existing outputs may be replaced.
    plot : str or path-like, optional
        Also draw the input and the result over each other to this image.
    progress : callable, optional
        Called as ``progress(points_done, points_total)``.

    Returns
    -------
    ShorelineReport

    Raises
    ------
    ConfigError
        If ``window``, ``modes``, ``bbox`` or ``crs`` is invalid.
    InputDataError
        If ``src`` is missing, empty (in ``bbox``), has no CRS, holds points, or
        has a non-finite coordinate; the message names file, layer and feature id.
    FormatError
        If ``src`` is not a vector file or an output extension is unknown.
    OutputExistsError
        If an output exists and ``overwrite`` is false.
    """
    window = check_window(window)
    modes = check_modes(modes, window)
    box = None if bbox is None else check_bbox(bbox)
    assigned = parse_crs(crs)
    vector_driver(dst)
    check_outputs(dst, plot, overwrite=overwrite)

    features = read_features(src, layer=layer, bbox=box)
    features = with_crs(features, assigned)
    try:
        _check_shoreline_types(features)
    except InputDataError:
        _check_coordinates(features)  # a bad coordinate is named first
        raise
    try:  # checks every coordinate as it flattens the layer; on every core
        geometry, report = simplify_shorelines(
            features.geometry, window, modes, progress=progress
        )
    except InputDataError as exc:
        raise locate(exc, features) from exc
    gone = shapely.is_missing(geometry) & ~shapely.is_missing(features.geometry)
    result = features.with_geometry(geometry).take(~gone)
    logger.info("shoreline: %s", report.summary())
    if len(result) == 0:
        warnings.warn(
            f"every feature of {features.path} was dropped: all its rings and lines "
            f"have fewer than window = {window} points; {os.fspath(dst)} is empty",
            CoastmeshWarning,
            stacklevel=2,
        )

    notes = provenance("simplify-shoreline", src, window=window, modes=modes)
    with AtomicOutputs(overwrite=overwrite) as outputs:
        write_features(outputs.stage(dst), result, layer=Path(dst).stem, metadata=notes)
        if plot is not None:
            from coastmesh import plot as plotting

            figure = plotting.shoreline_figure(
                features.geometry,
                result.geometry,
                crs=features.crs,
                title=f"{Path(src).name}: window {window} points, {modes_label(modes)}",
            )
            plotting.save_figure(figure, outputs.stage(plot))
    logger.info("wrote %s", listed(dst, plot))
    return report


def _check_coordinates(features: Features) -> None:
    try:
        check_coordinates(features.geometry)
    except InputDataError as exc:
        raise locate(exc, features) from exc


def _check_shoreline_types(features: Features) -> None:
    types = shapely.get_type_id(features.geometry)
    bad = np.flatnonzero((types >= 0) & ~np.isin(types, _SHORELINE_TYPES))
    if bad.size:
        first = int(bad[0])
        raise InputDataError(
            f"{features.geometry[first].geom_type} is not a polygon or a line "
            f"({bad.size} such features); shorelines must be polygons or lines",
            path=features.path,
            layer=features.layer,
            feature=int(features.fids[first]),
        )
