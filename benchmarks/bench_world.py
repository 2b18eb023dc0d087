"""A world ocean mesh end to end, from the bundled GSHHG world layers.

Reads a world shoreline layer, builds the world ocean in the stereographic
plane (:func:`coastmesh.geometry.world.world_ocean`), grades the size from the
coast on a longitude/latitude grid with the tidal-wavelength term from ETOPO1
at 0.5 degrees (:class:`coastmesh.sizing.SphereGrid`), meshes it
through the plane (:class:`coastmesh.meshing.gmsh.sphere_sizes.SphereSizeGrid`)
and prints one JSON line: each stage's time, the triangles, the quality measured on the
sphere (flat triangles between the nodes' unit vectors), the area against the
ocean's on the sphere, and the peak memory::

    python benchmarks/bench_world.py --layer world_gshhg_i.zip
"""

from __future__ import annotations

import argparse
import json
import math
import resource
import time

import numpy as np
import shapely
from pyproj import Geod

from coastmesh.data import path as data_path
from coastmesh.geometry.domain import smaller_than
from coastmesh.geometry.earth import EARTH_RADIUS, reproject
from coastmesh.geometry.world import world_ocean
from coastmesh.io import read_raster
from coastmesh.io.vectors.vector import read_features
from coastmesh.meshing import generate_mesh
from coastmesh.meshing.gmsh.sphere_sizes import SphereSizeGrid
from coastmesh.sizing import SphereGrid, TermSizes, combine, wavelength_size
from coastmesh.sizing.gradation import Gradation
from coastmesh.types import BoundarySegment, Domain, SizeGrid


def sphere_quality(mesh) -> dict:
    lon, lat = np.radians(mesh.points).T
    p = np.column_stack(
        [np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon), np.sin(lat)]
    )
    t = mesh.triangles
    a, b, c = p[t[:, 0]], p[t[:, 1]], p[t[:, 2]]
    normal = np.cross(b - a, c - a)
    outward = ((normal * (a + b + c)).sum(axis=1) > 0).mean()
    angles = []
    for x, y, z in ((a, b, c), (b, c, a), (c, a, b)):
        u, v = y - x, z - x
        cos = (u * v).sum(1) / np.linalg.norm(u, axis=1) / np.linalg.norm(v, axis=1)
        angles.append(np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))))
    smallest = np.min(angles, axis=0)
    area = 0.5 * np.linalg.norm(normal, axis=1).sum() * EARTH_RADIUS**2
    return {
        "outward_fraction": float(outward),
        "min_angle_p1": round(float(np.percentile(smallest, 1)), 2),
        "min_angle_min": round(float(smallest.min()), 2),
        "area_km2": round(area / 1e6),
        "crossing_antimeridian": int((np.ptp(mesh.points[t, 0], axis=1) > 180).sum()),
    }


def ocean_area(ocean) -> float:
    """The ocean polygon's area on the sphere, through its rings in lon/lat."""
    geod = Geod(a=EARTH_RADIUS, b=EARTH_RADIUS)

    def ring_area(ring) -> float:
        xy = shapely.get_coordinates(reproject(ring, ocean.crs, "EPSG:4326"))
        return abs(geod.polygon_area_perimeter(xy[:, 0], xy[:, 1])[0])

    outer = ring_area(ocean.polygon.exterior)
    outer = max(outer, 4 * math.pi * EARTH_RADIUS**2 - outer)
    return outer - sum(ring_area(r) for r in ocean.polygon.interiors)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--layer", default="world_gshhg_i.zip")
    parser.add_argument("--coast", type=float, default=10e3, help="metres")
    parser.add_argument("--ocean", type=float, default=50e3, help="metres")
    parser.add_argument("--grade", type=float, default=1000e3, help="metres")
    parser.add_argument("--cell", type=float, default=0.25, help="degrees")
    parser.add_argument("--min-area", type=float, default=500.0, help="km2")
    parser.add_argument("--per-wavelength", type=float, default=100.0)
    parser.add_argument("--rate", type=float, default=0.3)
    parser.add_argument("--close", type=float, default=None, help="metres")
    args = parser.parse_args()
    seconds = {}
    t0 = time.perf_counter()
    land = read_features(data_path(args.layer))
    seconds["read"] = time.perf_counter() - t0

    t = time.perf_counter()
    ocean = world_ocean(land.geometry, land.crs, close=args.close)
    holes = np.array([shapely.Polygon(r) for r in ocean.polygon.interiors])
    keep = ~smaller_than(holes, ocean.crs, args.min_area * 1e6)
    polygon = shapely.Polygon(ocean.polygon.exterior, [h.exterior for h in holes[keep]])
    rings = [polygon.exterior, *polygon.interiors]
    domain = Domain(
        polygon,
        tuple(
            BoundarySegment(np.asarray(r.coords), "shoreline", f"coast {i}", 1)
            for i, r in enumerate(rings)
        ),
        crs=ocean.crs,
    )
    seconds["ocean"] = time.perf_counter() - t

    t = time.perf_counter()
    south = float(reproject(polygon, ocean.crs, "EPSG:4326").bounds[1])
    coast = Gradation(
        np.array([polygon]), h_min=args.coast, d_hold=0.0, d_grade=args.grade
    )
    raster = read_raster(data_path("etopo1_0.5deg_world.tif"))
    grid = SphereGrid(args.cell, south=math.floor(south) - 1.0)
    graded = grid.graded([coast], lines_crs=ocean.crs, h_max=args.ocean)
    wave = wavelength_size(
        grid.depth(raster), per_wavelength=args.per_wavelength, min_depth=10.0
    )
    terms = [("coast", TermSizes(graded)), ("wavelength", TermSizes(wave))]
    field = combine(
        grid, terms, h_min=args.coast, h_max=args.ocean, rate=args.rate
    ).field
    size = SphereSizeGrid(SizeGrid.from_dataarray(field))
    seconds["size field"] = time.perf_counter() - t

    t = time.perf_counter()
    try:
        mesh = generate_mesh(domain, size, mesh_crs=ocean.crs, output_crs="EPSG:4326")
    except Exception as exc:
        import re

        xy = [float(v) for v in re.findall(r"[-0-9.]+", str(exc).split("[")[1])[:2]]
        where = reproject(shapely.Point(xy), ocean.crs, "EPSG:4326")
        raise SystemExit(f"{exc} at lon/lat {where.x:.3f}, {where.y:.3f}") from exc
    seconds["meshing"] = time.perf_counter() - t
    seconds["total"] = time.perf_counter() - t0
    quality = sphere_quality(mesh)
    want = ocean_area(type(ocean)(polygon, ocean.crs, ocean.pole, 0, 0, 0))
    quality["closed"] = ocean.closed
    print(
        json.dumps(
            {
                "layer": args.layer,
                "islands": len(polygon.interiors),
                "islands_below_min_area": int((~keep).sum()),
                "nodes": len(mesh.points),
                "triangles": len(mesh.triangles),
                "seconds": {k: round(v, 2) for k, v in seconds.items()},
                **quality,
                "ocean_km2": round(want / 1e6),
                "area_error": round(quality["area_km2"] * 1e6 / want - 1, 5),
                "peak_rss_mb": round(
                    resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
                ),
            }
        )
    )


if __name__ == "__main__":
    main()
