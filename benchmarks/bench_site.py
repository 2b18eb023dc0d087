"""A tidal site in the mesh: the targets of issue 32, measured on a case.

Builds a case with ``[[farms]]`` and ``[[turbines]]`` in memory
(``coastmesh.build_case``), writes its mesh as msh 2.2 and reads it back, and
prints one markdown table:

- the build's wall time (target: the Inner Sound example in <= 60 s);
- per region (the farm with its footprints, then each footprint): its
  elements' area on the WGS84 ellipsoid against the polygon's
  (``pyproj.Geod``; target 0.1 %), the median element size (the side of the
  equilateral triangle of each element's area) over the size asked (target
  0.8 to 1.25), and the 1st percentile and minimum of the minimum angle
  (target p01 >= 30 deg);
- for each node turbine, the distance of its node from its place (target 1 mm);
- the gradation: the ratio of neighbouring elements' mean edges at the site
  (a farm's or footprint's element or one beside it) and elsewhere (the size
  field keeps the rate; the elements scatter about it as anywhere);
- per ``[[lines]]``: its edges (all interior mesh edges?), how far its nodes
  lie from the line, the median edge over its ``h``;
- per format that holds region ids (or lines), whether each triangle's id
  (and each line) came back from the written file.

Run from the repository root::

    python benchmarks/bench_site.py                                  # the example
    python benchmarks/bench_site.py path/to/case.toml
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np
import shapely
from pyproj import CRS, Geod
from scipy.spatial import cKDTree

ROOT = Path(__file__).resolve().parents[1]
CASE = ROOT / "examples" / "orkney" / "inner_sound_farm.toml"
_GEOD = Geod(ellps="WGS84")


def _earth_areas(lonlat_triangles: np.ndarray) -> np.ndarray:
    """Areas of triangles given as (M, 3, 2) lon/lat, on the ellipsoid (m2)."""
    return np.array(
        [
            abs(_GEOD.polygon_area_perimeter(t[:, 0], t[:, 1])[0])
            for t in lonlat_triangles
        ]
    )


def _measures(result) -> list[str]:
    """Return the table's rows for a built case."""
    from coastmesh.geometry import reproject, reproject_points
    from coastmesh.meshing.cleanup.smoothing import min_angles

    mesh, site = result.mesh, result.site
    lonlat_crs = CRS.from_epsg(4326)
    lonlat = reproject_points(mesh.points, mesh.crs, lonlat_crs)
    plane = reproject_points(mesh.points, mesh.crs, site.crs)
    tri = mesh.triangles
    p = plane[tri]
    area = 0.5 * np.abs(
        (p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1])
        - (p[:, 2, 0] - p[:, 0, 0]) * (p[:, 1, 1] - p[:, 0, 1])
    )
    size = np.sqrt(area * 4 / np.sqrt(3))
    angles = min_angles(plane, tri)
    rows = []
    footprint_ids = [pid for _, pid, _ in site.footprints]
    for name, pid, polygon, h in site.farms:
        inside = np.isin(mesh.regions, [pid, *footprint_ids]) & _within(
            plane[tri].mean(axis=1), polygon
        )
        rows.append(
            _region_row(
                f"farm {name} ({pid})",
                inside,
                mesh.regions == pid,
                h,
                lonlat[tri],
                reproject(polygon, site.crs, lonlat_crs),
                size,
                angles,
            )
        )
    for (name, pid, polygon), t in zip(
        site.footprints,
        [t for t in site.turbines if t.region is not None],
        strict=True,
    ):
        here = mesh.regions == pid
        rows.append(
            _region_row(
                f"footprint {name} ({pid})",
                here,
                here,
                t.h,
                lonlat[tri],
                reproject(polygon, site.crs, lonlat_crs),
                size,
                angles,
            )
        )
    for t in site.turbines:
        if t.footprint == "node":
            gap = np.hypot(*(plane - t.xy).T).min()
            rows.append(
                f"| node turbine {t.name} | node {gap * 1000:.3f} mm from its place "
                "| | | | |"
            )
    rows += _line_rows(mesh, plane, site)
    rows.append(_gradation_row(p, tri, mesh.regions != mesh.surface_id))
    return rows


def _line_rows(mesh, plane: np.ndarray, site) -> list[str]:
    """Per ``[[lines]]``: its edges interior mesh edges, its nodes on the line."""
    from coastmesh.types.topology import unique_edges

    edges, ids = mesh.line_edges()
    inner, count = unique_edges(mesh.triangles, len(mesh.points))
    interior = {tuple(e) for e in inner[count == 2].tolist()}
    rows = []
    for name, pid, line, h in site.lines:
        mine = edges[ids == pid]
        ok = all((min(a, b), max(a, b)) in interior for a, b in mine.tolist())
        gap = shapely.distance(line, shapely.points(plane[mine.ravel()])).max()
        sides = np.linalg.norm(plane[mine[:, 0]] - plane[mine[:, 1]], axis=1)
        asked = f"{np.median(sides) / h:.2f}" if h else "-"
        rows.append(
            f"| line {name} ({pid}) | {len(mine)} edges, "
            f"{'all' if ok else 'NOT ALL'} interior mesh edges; nodes within "
            f"{gap * 1000:.3f} mm of the line | {np.median(sides):.1f} m | {asked} "
            "| | |"
        )
    return rows


def _within(points: np.ndarray, polygon) -> np.ndarray:
    shapely.prepare(polygon)
    return shapely.contains_xy(polygon, points[:, 0], points[:, 1])


def _region_row(label, area_of, sized, h, triangles, polygon, size, angles) -> str:
    """A region's row: Earth areas, median size over h, angles."""
    earth = _earth_areas(triangles[area_of]).sum()
    ring = np.asarray(polygon.exterior.coords)
    want = abs(_GEOD.polygon_area_perimeter(ring[:, 0], ring[:, 1])[0])
    median = np.median(size[sized]) if sized.any() else float("nan")
    ratio = "" if h is None else f"{median / h:.2f}"
    return (
        f"| {label} | {earth:,.2f} / {want:,.2f} m2 ({earth / want - 1:+.1e}) | "
        f"{median:.2f} m | {ratio} | {np.percentile(angles[sized], 1):.1f} | "
        f"{angles[sized].min():.1f} |"
    )


def _gradation_row(p, tri, site) -> str:
    """The ratio of neighbouring elements' mean edges, at the site and elsewhere.

    The size field itself keeps the rate (tests/sizing/test_patches.py); Gmsh's
    elements scatter about it, so the site's ratios are set against the rest
    of the mesh's.
    """
    mean = np.linalg.norm(p - np.roll(p, 1, axis=1), axis=2).mean(axis=1)
    edges = np.sort(
        np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]]), axis=1
    )
    owner = np.tile(np.arange(len(tri)), 3)
    order = np.lexsort((edges[:, 1], edges[:, 0]))
    edges, owner = edges[order], owner[order]
    same = (edges[1:] == edges[:-1]).all(axis=1)
    a, b = owner[:-1][same], owner[1:][same]
    ratio = np.maximum(mean[a], mean[b]) / np.minimum(mean[a], mean[b])
    near = site[a] | site[b]
    return (
        "| neighbouring elements' size ratio | at the site: max "
        f"{ratio[near].max():.2f}, "
        f"p99 {np.percentile(ratio[near], 99):.2f}; elsewhere: max "
        f"{ratio[~near].max():.2f}, p99 {np.percentile(ratio[~near], 99):.2f} | | | | |"
    )


def _round_trips(mesh):
    """Yield (format, region ids back?, lines back?) per format that holds them."""
    import coastmesh
    from coastmesh.io import mesh_formats

    with tempfile.TemporaryDirectory() as tmp:
        for name, fmt in mesh_formats().items():
            if fmt.read is None or not {"regions", "node_regions"} & fmt.holds:
                continue
            path = Path(tmp) / f"m-{name}{fmt.extensions[0]}"
            coastmesh.write_mesh(path, mesh, format=name)
            back = coastmesh.read_mesh(path, format=name, crs=mesh.crs)
            # formats may reorder nodes and triangles: match by centroid
            tree = cKDTree(back.points[back.triangles].mean(axis=1))
            at = tree.query(mesh.points[mesh.triangles].mean(axis=1))[1]
            wrong = int((back.regions[at] != mesh.regions).sum())
            same = wrong == 0 and len(back.triangles) == len(mesh.triangles)
            regions = "all" if same else f"{wrong:,} of {len(mesh.regions):,} differ"
            lines = "-"
            if "lines" in fmt.holds:
                got = {ln.id: len(ln.xy) for ln in back.lines}
                lines = (
                    "all" if got == {ln.id: len(ln.xy) for ln in mesh.lines} else "NO"
                )
            yield name, regions, lines


def main(argv: list[str] | None = None) -> int:
    """Build the case, measure it, print the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("case", nargs="?", default=str(CASE))
    args = parser.parse_args(argv)
    import coastmesh

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", coastmesh.CoastmeshWarning)
        started = time.perf_counter()
        result = coastmesh.build_case(coastmesh.read_case(args.case))
        seconds = time.perf_counter() - started
    if result.site is None:
        print(f"{args.case}: no [[farms]] or [[turbines]]", file=sys.stderr)
        return 1
    print(
        f"{result.name}: built in {seconds:.1f} s, {len(result.mesh.triangles):,} "
        "triangles"
    )
    print()
    print("| format | region ids back (per triangle) | lines back |")
    print("|---|---|---|")
    for fmt, regions, lines in _round_trips(result.mesh):
        print(f"| {fmt} | {regions} | {lines} |")
    print()
    print(
        "| what | area on the Earth (mesh / polygon) | median size | / h "
        "| p01 angle | min angle |"
    )
    print("|---|---|---|---|---|---|")
    for row in _measures(result):
        print(row)
    return 0


if __name__ == "__main__":
    sys.exit(main())
