"""Make the hard-coast test data: three GSHHG shorelines and ETOPO1 windows.

Run it from anywhere with the venv's python (numpy, shapely, pyogrio,
rasterio)::

    python tests/data/coasts/make_coasts.py               # ../shared/data
    python tests/data/coasts/make_coasts.py SRC [OUT]     # another source folder

``SRC`` is the coastmesh developer data set (default: ``shared/data`` beside
the repository); ``OUT`` defaults to this folder. For each coast it writes

- ``NAME_gshhg_f.geojson``: the GSHHG level-1 polygons of
  ``uk_northsea_gshhg_f.gpkg`` that intersect the box, whole, except those of
  at least 10,000 km2 that stick out of it, which are clipped to it (the rule of
  the bundled files, ``src/coastmesh/data/README.md``); counter-clockwise
  exteriors, RFC 7946 GeoJSON with 6 decimals;
- ``etopo1_0.1deg_NAME.tif``: the cells of ``etopo1_0.1deg_nwshelf.tif`` whose
  centres lie within the box widened by :data:`MARGIN`, with the source's
  profile (float32, deflate, predictor 3, ``AREA_OR_POINT=Area``);

and prints the counts, sizes and the share of each box's sea (GSHHG) that the
raster sees as water: bilinear elevation below 0 m, as coastmesh interpolates
it, on a lattice of :data:`LATTICE` degrees. Running it again gives the same
files.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pyogrio.raw
import rasterio
import shapely
from rasterio.windows import Window

HERE = Path(__file__).resolve().parent
SOURCE = HERE.parents[3] / "shared" / "data"
SHORELINES = "uk_northsea_gshhg_f.gpkg"
RASTER = "etopo1_0.1deg_nwshelf.tif"

#: name: (lon_min, lat_min, lon_max, lat_max)
BOXES = {
    "vestfjorden": (14.5, 67.85, 15.7, 68.25),
    "shetland": (-1.9, 59.8, -0.6, 60.9),
    "oresund": (12.2, 55.25, 13.2, 56.25),
}
#: polygons at least this large (GSHHG area, km2) that stick out are clipped
CLIP_AREA_KM2 = 10_000.0
#: the raster window reaches this far beyond the box, degrees
MARGIN = 0.3
#: the lattice spacing of the sea-share measure, degrees
LATTICE = 0.005
FIELDS = ("id", "part", "level", "npoints", "clipped", "area_km2", "riverlake")


def shoreline(source: Path, box: tuple[float, ...]) -> dict[str, np.ndarray]:
    """Return the polygons of ``box`` and their fields, by the clipping rule."""
    meta, _, wkb, values = pyogrio.raw.read(source / SHORELINES, bbox=box)
    fields = dict(zip(meta["fields"], values, strict=True))
    geoms = shapely.from_wkb(wkb)
    keep = shapely.intersects(geoms, shapely.box(*box))
    geoms, fields = geoms[keep], {k: v[keep] for k, v in fields.items()}
    bounds = shapely.bounds(geoms)
    inside = (bounds[:, :2] >= box[:2]).all(1) & (bounds[:, 2:] <= box[2:]).all(1)
    clip = ~inside & (fields["area_km2"] >= CLIP_AREA_KM2)
    geoms[clip] = [shapely.clip_by_rect(g, *box) for g in geoms[clip]]
    geoms = np.array([_single(g) for g in geoms], dtype=object)
    geoms = shapely.orient_polygons(geoms, exterior_cw=False)
    fields["clipped"] = fields["clipped"] | clip
    fields["npoints"] = shapely.get_num_coordinates(geoms).astype(np.int32)
    order = np.lexsort((-fields["npoints"], fields["level"]))
    return {"geometry": geoms[order]} | {k: v[order] for k, v in fields.items()}


def _single(geom: shapely.Geometry) -> shapely.Geometry:
    """A MultiPolygon of one part as its Polygon (as the bundled GeoJSON)."""
    parts = shapely.get_parts(geom)
    return parts[0] if len(parts) == 1 else geom


def write_shoreline(path: Path, data: dict[str, np.ndarray]) -> None:
    """Write the polygons as RFC 7946 GeoJSON with 6 decimals."""
    path.unlink(missing_ok=True)
    names = [*FIELDS, "npoints_orig"]
    pyogrio.raw.write(
        path,
        shapely.to_wkb(data["geometry"]),
        [data[k] for k in names],
        names,
        driver="GeoJSON",
        geometry_type="Unknown",
        crs="EPSG:4326",
        layer_options={
            "RFC7946": "YES",
            "COORDINATE_PRECISION": "6",
            "WRITE_NAME": "NO",
        },
    )


def write_raster(source: Path, path: Path, box: tuple[float, ...]) -> np.ndarray:
    """Write the window of cell centres within ``box`` + :data:`MARGIN`."""
    with rasterio.open(source / RASTER) as src:
        inv = ~src.transform
        col0, row0 = inv * (box[0] - MARGIN, box[3] + MARGIN)
        col1, row1 = inv * (box[2] + MARGIN, box[1] - MARGIN)
        c0, r0 = round(col0 - 0.5), round(row0 - 0.5)  # the cells' indices
        window = Window(c0, r0, round(col1 - 0.5) - c0 + 1, round(row1 - 0.5) - r0 + 1)
        data = src.read(1, window=window)
        profile = src.profile | {
            "height": data.shape[0],
            "width": data.shape[1],
            "transform": _rounded(src.window_transform(window)),
            "predictor": 3,
        }
        tags = src.tags() | {"description": f"ETOPO1 0.1 deg, window of {RASTER}"}
        band_tags = src.tags(1)
    path.unlink(missing_ok=True)
    with rasterio.open(path, "w", **profile) as dst:
        dst.write(data, 1)
        dst.update_tags(**tags)
        dst.update_tags(1, **band_tags)
        dst.set_band_description(1, "elevation")
    return data


def _rounded(transform: rasterio.Affine) -> rasterio.Affine:
    """The transform with its origin rounded to 1e-9 degrees (no float noise)."""
    a, b, c, d, e, f = transform[:6]
    return rasterio.Affine(a, b, round(c, 9), d, e, round(f, 9))


def sea_seen(path: Path, land: np.ndarray, box: tuple[float, ...]) -> float:
    """The share of the box's sea where the raster's bilinear elevation is < 0."""
    from scipy.interpolate import RegularGridInterpolator

    with rasterio.open(path) as ds:
        z = ds.read(1).astype(np.float64)
        t = ds.transform
    x = t.c + t.a * (np.arange(z.shape[1]) + 0.5)
    y = t.f + t.e * (np.arange(z.shape[0]) + 0.5)
    bilinear = RegularGridInterpolator((y[::-1], x), z[::-1])
    lon = np.arange(box[0] + LATTICE / 2, box[2], LATTICE)
    lat = np.arange(box[1] + LATTICE / 2, box[3], LATTICE)
    lon, lat = (a.ravel() for a in np.meshgrid(lon, lat))
    sea = shapely.box(*box).difference(shapely.union_all(land))
    wet = shapely.contains_xy(sea, lon, lat)
    return float((bilinear(np.column_stack([lat[wet], lon[wet]])) < 0).mean())


def main(source: Path = SOURCE, out: Path = HERE) -> None:
    """Write every coast's files into ``out`` and print what they hold."""
    print(
        "| coast | box | polygons (clipped) | points | GeoJSON bytes | raster | "
        "tif bytes | sea seen |"
    )
    print("|---|---|---:|---:|---:|---|---:|---:|")
    for name, box in BOXES.items():
        data = shoreline(source, box)
        geojson = out / f"{name}_gshhg_f.geojson"
        write_shoreline(geojson, data)
        tif = out / f"etopo1_0.1deg_{name}.tif"
        cells = write_raster(source, tif, box)
        seen = sea_seen(tif, data["geometry"], box)
        print(
            f"| {name} | {box} | {len(data['geometry']):,} "
            f"({int(data['clipped'].sum())}) | {int(data['npoints'].sum()):,} | "
            f"{geojson.stat().st_size:,} | {cells.shape[0]} x {cells.shape[1]}, "
            f"{cells.min():.0f}..{cells.max():.0f} m | {tif.stat().st_size:,} | "
            f"{100 * seen:.1f} % |"
        )


if __name__ == "__main__":
    args = [Path(a) for a in sys.argv[1:3]]
    main(*args)
