"""Closing narrow water on world layers: the raster closing against the buffers.

Issue 33's "fast closing at full resolution", measured. For each world layer
(GSHHG intermediate, bundled; and a full-resolution one, or its proxy made by
``scripts/world_layer.py proxy``), the background set of
``examples/global/world.toml`` is built as a global case builds it (the world
in the stereographic plane, islands under ``min_area`` dropped, the polar land
as a frame), then closed at ``close`` by both closings in the same run:

* ``new``: :func:`coastmesh.geometry.close_narrow_water`, on rasters;
* ``old``: the GEOS buffers it replaced, kept as the tests' reference
  (``tests/geometry/closing_reference.py``).

Prints a table: vertices, times and their ratio, polygons out, the land where
they differ (on the Earth, and over ``close`` x the coast's length), and the
islands of ``min_area`` or more that keep 90 % of their area. A layer
``NAME:europe`` is the set's land in a box round Europe, without the frame:
the buffers run out of memory on the whole world at full resolution. With
``--run``,
also times ``coastmesh run`` of world.toml on the largest layer (the case file
is written under ``--scratch``).

Run from the repository root::

    python benchmarks/bench_closing.py     # intermediate; proxy: Europe, the world
    python benchmarks/bench_closing.py --layers i --repeat 3
    python benchmarks/bench_closing.py --run                  # and a whole case
"""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import shapely

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "geometry"))  # the reference closing

from closing_reference import close_narrow_water_reference  # noqa: E402
from timing import best_time  # noqa: E402

from coastmesh.geometry.earth import EARTH_RADIUS  # noqa: E402

CASE = ROOT / "examples" / "global" / "world.toml"
PROXY = Path("/work/scratch/proxy/world_gshhg_proxy.zip")
#: pieces of the world (lon/lat boxes) small enough for the buffers at full
#: resolution: the NW European shelf, Norway's fjords and the Baltic
REGIONS = {"europe": (-16.0, 48.0, 32.0, 72.0)}
R2 = 2.0 * EARTH_RADIUS


def background_set(layer: Path, region: str | None = None):
    """Return the world set's land as the closing gets it, with min_area, reach.

    With ``region`` (a key of :data:`REGIONS`), only the land in its box, and
    no frame: a piece of the world small enough for the buffers.
    """
    import coastmesh
    from coastmesh.case.pipeline.shorelines import build_shoreline_set
    from coastmesh.case.pipeline.world import closing_width, kept_area
    from coastmesh.geometry import reproject, world_land
    from coastmesh.io import read_features
    from coastmesh.types import Features

    config = coastmesh.read_case(CASE)
    features = read_features(layer)
    world = world_land(features.geometry, features.crs, pole=config.domain.pole)
    n = len(world.islands)
    islands = Features(world.islands, world.crs, {}, np.arange(n), str(layer))
    s = config.background_set
    land, _ = build_shoreline_set(s, islands, world.crs, kept_area(config))
    if region is None:
        land = np.concatenate([[world.frame()], land])
    else:
        box = shapely.segmentize(shapely.box(*REGIONS[region]), 0.1)
        box = reproject(box, "EPSG:4326", world.crs)
        land = shapely.intersection(land[shapely.intersects(land, box)], box)
        land = shapely.get_parts(land)
        land = land[shapely.get_type_id(land) == shapely.GeometryType.POLYGON]
    return land, kept_area(config), closing_width(config), 1.05 * world.reach


def earth_length(geoms) -> float:
    """Return the length on the Earth of the rings of plane geometries (m)."""
    xy, ring = shapely.get_coordinates(shapely.get_rings(geoms), return_index=True)
    same = ring[1:] == ring[:-1]
    a, b = xy[:-1][same], xy[1:][same]
    k = 1.0 + (((a + b) / 2) ** 2).sum(axis=1) / R2**2
    return float((np.hypot(*(b - a).T) / k).sum())


def compare(land, min_area, close, reach, new, old, *, framed: bool) -> dict:
    """Return how the two closings differ, and the islands each keeps."""
    from coastmesh.geometry.closing import earth_areas, island_changes

    disc = shapely.Point(0, 0).buffer(reach, quad_segs=512)
    new_u, old_u = shapely.union_all(new), shapely.union_all(old)
    only_new = shapely.difference(new_u, old_u).intersection(disc)
    only_old = shapely.difference(old_u, new_u).intersection(disc)
    islands = land[1:] if framed else land
    coast = earth_length(islands)
    if framed:  # and the frame's coast: its hole
        coast += earth_length(np.array([shapely.Polygon(r) for r in land[0].interiors]))
    _, changed = island_changes(islands, new, min_area=min_area, framed=framed)
    islands = islands[earth_areas(islands) >= min_area]
    area = earth_areas(islands)
    kept = {}
    for name, union in (("new", new_u), ("old", old_u)):
        shapely.prepare(union)
        left = earth_areas(shapely.intersection(islands, union))
        kept[name] = int((left >= 0.9 * area).sum())
    # earth_areas takes each edge at its middle: the frame's slivers far out
    # have edges of 1e8 m over which k changes tenfold, cut them to 100 km
    km2_new = earth_areas(shapely.segmentize(shapely.get_parts(only_new), 1e5))
    km2_old = earth_areas(shapely.segmentize(shapely.get_parts(only_old), 1e5))
    km2_new, km2_old = km2_new.sum() / 1e6, km2_old.sum() / 1e6
    return {
        "islands": len(islands),
        "kept": kept,
        "only_new": float(km2_new),
        "only_old": float(km2_old),
        "share": float((km2_new + km2_old) * 1e6 / (close * coast)),
        "changed": len(changed),
    }


def bench(name: str, layer: Path, repeat: int, reference: bool) -> dict:
    """Close one layer's background set both ways; return the table's row.

    ``name`` is ``i``, ``proxy`` or a path, then ``:REGION`` for a piece.
    """
    from shapely.errors import GEOSException

    from coastmesh.geometry import close_narrow_water

    region = name.split(":")[1] if ":" in name else None
    land, min_area, close, reach = background_set(layer, region)
    kw = {"within": reach, "keep_area": min_area}
    new_s, (new, _) = best_time(lambda: close_narrow_water(land, close, **kw), repeat)
    row = {
        "layer": name,
        "vertices": int(shapely.get_num_coordinates(land).sum()),
        "polygons": len(land),
        "new_s": new_s,
        "new_out": len(new),
        "new_vertices": int(shapely.get_num_coordinates(new).sum()),
    }
    if reference:
        start = time.perf_counter()
        try:
            old_s, (old, _) = best_time(
                lambda: close_narrow_water_reference(land, close, **kw), 1
            )
        except (GEOSException, MemoryError) as exc:  # the buffers' memory
            row["old_failed"] = f"{exc} after {time.perf_counter() - start:.0f} s"
        else:
            row |= {"old_s": old_s, "old_out": len(old)}
            row |= compare(land, min_area, close, reach, new, old, framed=not region)
    print(row, flush=True)
    return row


def run_case(layer: Path, scratch: Path) -> tuple[float, str]:
    """Run world.toml on ``layer`` end to end; return its wall time and log."""
    scratch.mkdir(parents=True, exist_ok=True)
    text = CASE.read_text()
    data = ROOT / "src" / "coastmesh" / "data"
    text = text.replace("../../src/coastmesh/data/world_gshhg_i.zip", str(layer))
    text = text.replace("../../src/coastmesh/data/", f"{data}/")
    text = re.sub(r'output = ".*"', f'output = "{scratch / "out"}"', text, count=1)
    case = scratch / "world_full.toml"
    case.write_text(text)
    start = time.perf_counter()
    done = subprocess.run(
        ["coastmesh", "run", str(case), "--overwrite"],
        capture_output=True,
        text=True,
        check=False,
    )
    return time.perf_counter() - start, (done.stdout + done.stderr)[-3000:]


def table(rows: list[dict]) -> None:
    """Print the rows as a Markdown table."""
    print(
        "\n| layer | vertices | old (s) | new (s) | old / new | polygons out old / new"
        " | land only old / only new (km2) | over close x coast | islands >= "
        "min_area kept 90 % old / new | changed > 10 % |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        if "old_s" not in r:
            old = r.get("old_failed", "")
            print(
                f"| {r['layer']} | {r['vertices']:,} | {old} | {r['new_s']:.1f} | | "
                f"{r['new_out']:,} | | | | |"
            )
            continue
        print(
            f"| {r['layer']} | {r['vertices']:,} | {r['old_s']:.1f} | "
            f"{r['new_s']:.1f} | {r['old_s'] / r['new_s']:.1f} | {r['old_out']:,} / "
            f"{r['new_out']:,} | {r['only_old']:,.0f} / {r['only_new']:,.0f} | "
            f"{r['share']:.4f} | {r['kept']['old']} / {r['kept']['new']} of "
            f"{r['islands']} | {r['changed']} |"
        )


def main(argv: list[str] | None = None) -> int:
    """Close each layer both ways; print the table (and a whole case's time)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--layers",
        default="i,proxy:europe,proxy",
        help="i, proxy or a path, each with :europe for a piece",
    )
    parser.add_argument("--proxy", type=Path, default=PROXY)
    parser.add_argument("--repeat", type=int, default=1, help="best of, for new")
    parser.add_argument("--no-reference", action="store_true", help="new only")
    parser.add_argument("--run", action="store_true", help="and a whole case")
    parser.add_argument("--scratch", type=Path, default=Path("/work/scratch/closing"))
    args = parser.parse_args(argv)
    from coastmesh.data import path as data_path

    paths = {"i": Path(data_path("world_gshhg_i.zip")), "proxy": args.proxy}
    names = args.layers.split(",")
    rows = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for name in names:
            layer = paths.get(name.split(":")[0], Path(name.split(":")[0]))
            rows.append(bench(name, layer, args.repeat, not args.no_reference))
    table(rows)
    if args.run:
        last = names[-1].split(":")[0]
        seconds, log = run_case(paths.get(last, Path(last)), args.scratch)
        print(f"\ncoastmesh run world.toml on {last}: {seconds:.0f} s\n{log}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
