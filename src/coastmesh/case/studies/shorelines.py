"""The paper's shoreline study (section III.A, figure 2): PCA reconstructions.

A shoreline layer (GSHHG full resolution, say) is approximated by
:func:`~coastmesh.geometry.simplify_shorelines` once per ``[[study.reconstructions]]``
(window, modes). For each one the study writes the reconstruction as a GeoPackage
and a row of a table: rings in and dropped (shorter than the window, the paper's
small-island filter), points in and out, and how far the reconstruction departs from
the original in metres. Two figures lay every reconstruction over the original: the
whole layer and a detail box.

A layer clipped to a data box (Eurasia in the bundled West Norway file) has cut
edges hundreds of kilometres long between two vertices, and a PCA window spanning
one pulls the reconstruction across land. With ``densify_long_edges`` (the default)
such edges get vertices at the layer's median spacing before PCA, as mesh cases do
(:mod:`coastmesh.case`); the table counts them as ``points added``, apart from the
``points in`` of the file.

Distances are measured in a local metric CRS (the UTM zone of the layer's centre
for longitude/latitude data) between the original rings that are kept and the
reconstructed rings. The Hausdorff distance is symmetric and discrete: each side is
densified to ``hausdorff_spacing`` and the exact distance from every one of its
points to the other side's segments is found with an STR-tree, so it is GEOS's
densified Hausdorff distance (:func:`shapely.hausdorff_distance` with ``densify``)
at the cost of a tree query rather than all pairs of vertices. It is exact to
within half the spacing.
"""

from __future__ import annotations

import csv
import json
import logging
import math
import re
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TypedDict

import numpy as np
import shapely
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.case import schema
from coastmesh.case.schema import Table
from coastmesh.errors import ConfigError, InputDataError
from coastmesh.geometry import (
    ShorelineReport,
    densify_long_edges,
    land_polygons,
    simplify_shorelines,
)
from coastmesh.geometry.earth import metres_per_unit, reproject, reproject_points
from coastmesh.io import read_features, write_features
from coastmesh.plot.base import detail_bounds, save_figure
from coastmesh.plot.studies import overlay_figure
from coastmesh.types import Features, Report, StageFactory
from coastmesh.version import __version__

__all__ = [
    "ReconstructionConfig",
    "ShorelineStudyConfig",
    "ShorelineStudyResult",
    "parse_study",
    "run_study",
]

logger = logging.getLogger(__name__)

_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]*$")
#: line colours of the reconstructions, in order (figure 2 and the NW shelf cases)
_COLUMNS = (
    ("label", "reconstruction"),
    ("rings_in", "rings in"),
    ("rings_dropped", "rings dropped"),
    ("features_dropped", "features dropped"),
    ("points_in", "points in"),
    ("points_added", "points added"),
    ("points_out", "points out"),
    ("repaired", "repaired"),
    ("hausdorff_m", "Hausdorff (m)"),
    ("mean_distance_m", "mean distance (m)"),
    ("seconds", "PCA time (s)"),
)


@dataclass(frozen=True, slots=True)
class ReconstructionConfig:
    """``[[study.reconstructions]]``: one PCA reconstruction.

    Examples
    --------
    >>> ReconstructionConfig("pca_1_500", 500, 1).label
    'PCA 1 mode / 500 points'
    """

    name: str
    window: int
    modes: int

    @property
    def label(self) -> str:
        """Describe it, e.g. ``"PCA 5 modes / 100 points"``."""
        modes = "1 mode" if self.modes == 1 else f"{self.modes} modes"
        return f"PCA {modes} / {self.window} points"


@dataclass(frozen=True, slots=True)
class ShorelineStudyConfig:
    """``[study]`` of a ``kind = "shorelines"`` case; paths are resolved.

    ``bbox`` and ``detail`` are ``(minx, miny, maxx, maxy)`` in the layer's CRS;
    ``hausdorff_spacing`` is in metres.
    """

    path: Path
    reconstructions: tuple[ReconstructionConfig, ...]
    layer: str | None = None
    bbox: tuple[float, float, float, float] | None = None
    detail: tuple[float, float, float, float] | None = None
    densify_long_edges: bool = True
    hausdorff_spacing: float = 25.0


class Distances(TypedDict):
    """How far a reconstruction is from the original, metres; where it is farthest."""

    hausdorff_m: float
    hausdorff_lon: float
    hausdorff_lat: float
    mean_distance_m: float


class StudyRow(Distances):
    """One row of the study's table: a reconstruction, its counts and distances."""

    name: str
    label: str
    window: int
    modes: int
    rings_in: int
    rings_dropped: int
    features_in: int
    features_dropped: int
    points_in: int
    points_added: int
    points_out: int
    repaired: int
    seconds: float


@dataclass(frozen=True, slots=True)
class ShorelineStudyResult(Report):
    """What :func:`run_study` wrote: file names (relative to the folder), the rows."""

    files: tuple[str, ...]
    rows: tuple[StudyRow, ...]
    seconds: float

    def summary(self) -> str:
        """Return a one-line summary."""
        parts = ", ".join(
            f"{r['name']} {r['points_out']:,} points, {r['rings_dropped']} rings "
            f"dropped, Hausdorff {r['hausdorff_m'] / 1000:.2f} km"
            for r in self.rows
        )
        points = self.rows[0]["points_in"] if self.rows else 0
        return (
            f"shorelines: {points:,} points in; {parts}; {len(self.files)} files "
            f"in {self.seconds:.1f} s"
        )


def parse_study(
    table: Table, path_of: Callable[[object, str], Path]
) -> ShorelineStudyConfig:
    """Read the ``[study]`` table of a shoreline study case.

    Parameters
    ----------
    table : coastmesh.case.schema.Table
        The ``[study]`` table.
    path_of : callable
        ``path_of(value, key)`` resolves a path relative to the case file.

    Returns
    -------
    ShorelineStudyConfig

    Raises
    ------
    ConfigError
        For an unknown or missing key or a bad value, naming the file and the key.

    Examples
    --------
    >>> from pathlib import Path
    >>> t = Table({"path": "c.gpkg", "reconstructions": [{"window": 100, "modes": 5}]},
    ...            "study", "case.toml")
    >>> study = parse_study(t, lambda value, key: Path("/cases") / value)
    >>> study.path.as_posix(), study.reconstructions[0].name
    ('/cases/c.gpkg', 'pca_5_100')
    """
    path = table.get("path", path_of)
    layer = table.get("layer", schema.string, None)
    bbox = table.get("bbox", schema.box, None)
    detail = table.get("detail", schema.box, None)
    densify = table.get("densify_long_edges", schema.boolean, True)
    spacing = table.get("hausdorff_spacing", _positive_length, 25.0)
    reconstructions: list[ReconstructionConfig] = []
    for r in table.tables("reconstructions"):
        window = r.get("window", schema.integer(2))
        modes = r.get("modes", schema.integer(1))
        if modes > window:
            raise r.error("modes", f"= {modes} is more than window = {window}")
        name = r.get("name", schema.string, f"pca_{modes}_{window}")
        if not _NAME.match(name):
            raise r.error(
                "name", f"= {name!r}: use letters, digits, '_', '.' and '-' only"
            )
        if name in {c.name for c in reconstructions}:
            raise r.error("name", f"= {name!r} is used twice; give each a name")
        reconstructions.append(ReconstructionConfig(name, window, modes))
        r.done()
    if not reconstructions:
        raise table.error(
            "reconstructions", "give at least one [[study.reconstructions]]"
        )
    table.done()
    return ShorelineStudyConfig(
        path, tuple(reconstructions), layer, bbox, detail, densify, spacing
    )


def run_study(
    config: ShorelineStudyConfig, folder: Path, stage: StageFactory
) -> ShorelineStudyResult:
    """Reconstruct the shoreline by PCA and write the study into ``folder``.

    Parameters
    ----------
    config : ShorelineStudyConfig
        The study.
    folder : pathlib.Path
        An existing, empty folder.
    stage : callable
        ``stage(label)`` returns a context manager yielding ``progress(done, total)``.

    Returns
    -------
    ShorelineStudyResult
        One row per reconstruction (also in ``table.md``, ``table.csv`` and
        ``study.json``); ``<name>.gpkg`` per reconstruction; ``figures/``.

    Raises
    ------
    InputDataError
        If the file is missing, declares no CRS, or holds no land polygons.
    ConfigError
        If the ``detail`` box holds no shoreline.
    """
    started = time.perf_counter()
    with stage("reading shorelines"):
        features, crs = _read(config)
    bounds = tuple(float(v) for v in shapely.total_bounds(features.geometry))
    detail = config.detail or detail_bounds(features.geometry, crs)
    assert detail is not None  # _read keeps land polygons only, and some
    if not shapely.intersects(shapely.box(*detail), features.geometry).any():
        raise ConfigError(
            f"study.detail = {list(detail)}: the box holds no shoreline of "
            f"{config.path} (extent {[round(b, 4) for b in bounds]})"
        )
    metric, to_metric = _metric(crs, bounds)
    land = features.geometry
    if config.densify_long_edges:
        land = densify_long_edges(land)
    points = (_distinct_points(features.geometry), _distinct_points(land))
    rings, ring_part = shapely.get_rings(shapely.get_parts(land), return_index=True)
    original = to_metric(rings)
    rows: list[StudyRow] = []
    results: list[NDArray[np.object_]] = []
    for rec in config.reconstructions:
        with stage(f"{rec.name}: {rec.label}") as progress:
            t0 = time.perf_counter()
            out, report = simplify_shorelines(
                land, rec.window, rec.modes, progress=progress
            )
            seconds = time.perf_counter() - t0
        with stage(f"{rec.name}: distances"):
            kept = _kept_rings(rings, ring_part, rec.window)
            rebuilt = to_metric(shapely.get_rings(shapely.get_parts(out)))
            distances = _distances(
                original[kept], rebuilt, config.hausdorff_spacing, metric, crs
            )
        rows.append(_row(rec, report, points, distances, seconds))
        results.append(out)
        logger.info("%s: %s; %s", rec.name, report.summary(), distances)
    files: list[str] = []
    with stage("writing GeoPackages") as progress:
        for k, (rec, out) in enumerate(
            zip(config.reconstructions, results, strict=True)
        ):
            files.append(_write_gpkg(folder, rec, features, out))
            progress(k + 1, len(results))
    with stage("figures"):
        files += _figures(folder, config, features.geometry, results, detail, crs)
    with stage("tables"):
        setup: dict[str, object] = {
            "path": str(config.path),
            "layer": features.layer,
            "bbox": config.bbox,
            "crs": crs.to_string(),
            "metric_crs": metric.to_string(),
            "densify_long_edges": config.densify_long_edges,
            "hausdorff_spacing_m": config.hausdorff_spacing,
            "detail": list(detail),
            "features": len(features),
        }
        files += _tables(folder, rows, setup)
    seconds = time.perf_counter() - started
    return ShorelineStudyResult(tuple(files), tuple(rows), seconds)


def _read(config: ShorelineStudyConfig) -> tuple[Features, CRS]:
    """Read the layer's land polygons, and its CRS."""
    features = read_features(config.path, layer=config.layer, bbox=config.bbox)
    if features.crs is None:
        raise InputDataError(
            "the file declares no CRS; distances need one", path=str(config.path)
        )
    return land_polygons(features, purpose="a shoreline study"), features.crs


def _row(
    rec: ReconstructionConfig,
    report: ShorelineReport,
    points: tuple[int, int],
    distances: Distances,
    seconds: float,
) -> StudyRow:
    """One row of the table: the reconstruction, its counts and distances."""
    return {
        "name": rec.name,
        "label": rec.label,
        "window": rec.window,
        "modes": rec.modes,
        "rings_in": report.contours_in,
        "rings_dropped": report.contours_dropped,
        "features_in": report.features_in,
        "features_dropped": report.features_dropped,
        "points_in": points[0],
        "points_added": points[1] - points[0],
        "points_out": report.points_out,
        "repaired": report.repaired,
        **distances,
        "seconds": round(seconds, 3),
    }


def _positive_length(value: object, key: str) -> float:
    """Convert a length with its unit to metres, > 0."""
    return schema.length()(schema.length_with_unit(value, key), key)


def _distinct_points(geometry: NDArray[np.object_]) -> int:
    """Vertices of polygon rings, a ring's closing vertex not counted."""
    rings = shapely.get_rings(shapely.get_parts(geometry))
    return int(shapely.get_num_coordinates(rings).sum() - len(rings))


def _kept_rings(
    rings: NDArray[np.object_], ring_part: NDArray[np.int64], window: int
) -> NDArray[np.bool_]:
    """Rings that PCA keeps: long enough, and (holes) in a shell that is kept."""
    long_enough: NDArray[np.bool_] = shapely.get_num_coordinates(rings) - 1 >= window
    shell = np.r_[True, ring_part[1:] != ring_part[:-1]]
    shell_kept = np.zeros(int(ring_part.max()) + 1 if len(rings) else 0, dtype=bool)
    shell_kept[ring_part[shell & long_enough]] = True
    return long_enough & shell_kept[ring_part]


def _metric(
    crs: CRS, bounds: tuple[float, ...]
) -> tuple[CRS, Callable[[NDArray[np.object_]], NDArray[np.object_]]]:
    """Pick a metric CRS for the layer; return it and a function into it.

    Examples
    --------
    >>> crs, _ = _metric(CRS.from_epsg(4326), (4.5, 60.0, 8.2, 62.5))
    >>> crs.to_epsg()
    32632
    """
    if crs.is_geographic:
        lon, lat = (bounds[0] + bounds[2]) / 2, (bounds[1] + bounds[3]) / 2
        zone = min(max(math.floor((lon + 180) / 6) + 1, 1), 60)
        metric = CRS.from_epsg((32600 if lat >= 0 else 32700) + zone)
        return metric, lambda g: reproject(g, crs, metric)
    if not crs.is_projected:
        raise InputDataError(f"CRS {crs.name!r} is neither geographic nor projected")
    factor = metres_per_unit(crs)
    return crs, lambda g: shapely.transform(g, lambda xy: xy * factor)


def _distances(
    original: NDArray[np.object_],
    rebuilt: NDArray[np.object_],
    spacing: float,
    metric: CRS,
    crs: CRS,
) -> Distances:
    """Symmetric Hausdorff distance, where it is reached, and the mean distance.

    All lengths in metres; ``original`` and ``rebuilt`` are rings in ``metric``.
    """
    if len(original) == 0 or len(rebuilt) == 0:
        return {
            "hausdorff_m": math.nan,
            "hausdorff_lon": math.nan,
            "hausdorff_lat": math.nan,
            "mean_distance_m": math.nan,
        }
    to_rebuilt, to_original = _segment_tree(rebuilt), _segment_tree(original)
    a = shapely.get_coordinates(shapely.segmentize(original, spacing))
    b = shapely.get_coordinates(shapely.segmentize(rebuilt, spacing))
    da = _nearest(to_rebuilt, a)
    db = _nearest(to_original, b)
    far = a[np.argmax(da)] if da.max() >= db.max() else b[np.argmax(db)]
    ((lon, lat),) = reproject_points([far], metric, crs)
    coords, ring = shapely.get_coordinates(rebuilt, return_index=True)
    vertices = coords[np.r_[ring[1:] == ring[:-1], False]]  # closing ones left out
    return {
        "hausdorff_m": round(float(max(da.max(), db.max())), 1),
        "hausdorff_lon": round(float(lon), 5),
        "hausdorff_lat": round(float(lat), 5),
        "mean_distance_m": round(float(_nearest(to_original, vertices).mean()), 1),
    }


def _segment_tree(rings: NDArray[np.object_]) -> shapely.STRtree:
    """Build an STR-tree of every segment of the rings."""
    coords, index = shapely.get_coordinates(rings, return_index=True)
    same = index[1:] == index[:-1]
    pairs = np.stack([coords[:-1][same], coords[1:][same]], axis=1)
    return shapely.STRtree(shapely.linestrings(pairs))


def _nearest(tree: shapely.STRtree, xy: NDArray[np.float64]) -> NDArray[np.float64]:
    """Distance from each point to the nearest segment in ``tree``."""
    _, distance = tree.query_nearest(
        shapely.points(xy), return_distance=True, all_matches=False
    )
    return np.asarray(distance, dtype=np.float64)


def _write_gpkg(
    folder: Path,
    rec: ReconstructionConfig,
    features: Features,
    out: NDArray[np.object_],
) -> str:

    name = f"{rec.name}.gpkg"
    alive = ~shapely.is_missing(out)
    write_features(
        folder / name,
        features.take(alive).with_geometry(out[alive]),
        metadata={
            "window": str(rec.window),
            "modes": str(rec.modes),
            "source": features.path,
            "coastmesh": __version__,
        },
    )
    return name


def _figures(
    folder: Path,
    config: ShorelineStudyConfig,
    original: NDArray[np.object_],
    results: list[NDArray[np.object_]],
    detail: tuple[float, float, float, float],
    crs: CRS,
) -> list[str]:

    (folder / "figures").mkdir(exist_ok=True)
    layers = [
        (f"{rec.label} ({rec.name})", out)
        for rec, out in zip(config.reconstructions, results, strict=True)
    ]
    label = f"original ({_distinct_points(original):,} points)"
    names = []
    for view in ("whole", "detail"):
        figure = overlay_figure(
            original, layers, crs=crs, detail=detail, view=view, label=label
        )
        name = f"figures/overlay_{view}.png"
        save_figure(figure, folder / name)
        names.append(name)
    return names


def _tables(
    folder: Path, rows: Sequence[Mapping[str, object]], setup: dict[str, object]
) -> list[str]:

    def cell(key: str, value: object) -> str:
        if isinstance(value, float):
            digits = 2 if key == "seconds" else 1
            return "n/a" if math.isnan(value) else f"{value:,.{digits}f}"
        return f"{value:,}" if isinstance(value, int) else str(value)

    head = [title for _, title in _COLUMNS]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    lines += [
        "| " + " | ".join(cell(k, r[k]) for k, _ in _COLUMNS) + " |" for r in rows
    ]
    (folder / "table.md").write_text("\n".join(lines) + "\n", encoding="utf-8")
    with (folder / "table.csv").open("w", newline="", encoding="utf-8") as stream:
        writer = csv.DictWriter(stream, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    study = {"coastmesh": __version__, "study": "shorelines"} | setup
    study["rows"] = [
        {
            k: (None if isinstance(v, float) and math.isnan(v) else v)
            for k, v in r.items()
        }
        for r in rows
    ]
    (folder / "study.json").write_text(json.dumps(study, indent=2) + "\n")
    return ["table.md", "table.csv", "study.json"]
