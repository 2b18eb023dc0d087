"""Issue 33's checks of a global case run: the mesh on the sphere, no stray refinement.

Two targets of issue 33, measured on a global case that has been run:

1. **Quality on the sphere**: the 1st-percentile minimum angle at least 30
   degrees, and no element inverted or duplicated across the antimeridian
   (:func:`coastmesh.meshing.quality.sphere_quality`: spherical angles;
   orientation seen from outside; coincident nodes, repeated triangles,
   edges of more than two triangles, folds; sides over 10 degrees of arc).
2. **No refinement where there is no coast**: no element smaller than 0.5 x the
   size the gradations give lies farther than 2 cells of the size grid from a
   coast the mesh keeps, unless the bathymetry term asks for it there.

For the second, the case's stages run in this process up to the size field
(the shorelines, the domain, the closing: about a minute and a half and
1.3 GB on ``world.toml``). Each term's sizes are then taken on the same grid
with the same case (:class:`coastmesh.case.terms.base.SizeCase`) and
combined as the size stage combines them (:func:`coastmesh.sizing.combine`:
floor, ``h_max``, gradation limit): all of them must give the stage's field
again (checked, and against ``size.tif``), the gradations alone give the
*gradation size*. That size is also worked out independently, as the case file
asks for it: :func:`~coastmesh.sizing.gradation.gradation_size` of the
great-circle distance from each grid node to the gradation's lines (the
domain's segments of those names, cut every 2 km on the sphere), combined the
same way. The two must agree (99 % of the grid nodes within 5 %): the verdict
of target 2 is taken against the independent one, and both counts are printed.

The mesh is read from the output folder. An element's size is the mean of its
three sides, chords on the sphere of :data:`~coastmesh.geometry.EARTH_RADIUS`;
the sizes are read at its centroid (bilinear in lon/lat, wrapping). Its
distance to the coast is to the mesh's boundary edges that are not open
boundaries, cut every 1 km. An element is excused when the bathymetry term
asks for it: it is at least 0.5 x the size that term asks for there, the term
as the size stage applies it, carried by the gradation limit the stage puts
on every term. That is the tolerance the target gives the gradations' size,
and the one of the whole check: no element far from the coast is under half
of what the terms ask. The term reads the depths the size stage reads:
raster land in the domain's sea takes the nearest sea depth (``land =
"nearest_sea"``), so a term that asks for small elements there asks at a
depth the domain keeps. The strict count excuses an element only where the
term's own size (before the floor and the gradation limit) is under 0.5 x
the gradation size: what is left then are elements near a shallow bank,
within the reach of its gradation. Both verdicts are counted; the default's
decides. The offenders are also counted against the case's final field
(below 0.5 x the gradation size: the case asked for them; otherwise the
mesher or the cleanup made them smaller than asked), and against half the
bathymetry term's own size, with their median size over the field.

Prints one JSON line, then a table and the offenders by cluster (triangles
joined by a node), largest first, each with its smallest element's place.
Exits 1 if a target fails::

    python benchmarks/bench_global_checks.py examples/global/world.toml out/world
    python benchmarks/bench_global_checks.py CASE.toml OUT --mesh OUT/world.gr3

(the mesh: ``--mesh``, else the case's ``.nc``, ``.gr3`` or ``.14`` in the folder)
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import warnings
from functools import partial
from pathlib import Path

import numpy as np

SMALL = 0.5  # an element below this times the gradation size is refined
CELLS = 2.0  # ... and one farther than this many grid cells from a coast strays
COAST_STEP = 1_000.0  # metres: the mesh's coast is cut this finely
LINE_STEP = 2_000.0  # metres: the gradations' lines are cut this finely
AGREE = (99.0, 0.05)  # percentile of grid nodes, relative difference allowed
LISTED = 10


def rebuild_sizes(config) -> dict:
    """Run the case up to its size field; return the grid and each size wanted.

    Returns the grid, the case's field (the size stage's), the gradation size
    (the gradations term alone, floored, capped and limited as the stage does),
    the same worked out independently, the bathymetry term's own size (None
    when the case has none) and the same carried by the gradation limit, the
    largest relative difference of all the terms recombined from the stage's
    field, and the stages' times.
    """
    from coastmesh.case.config import TERMS, floor
    from coastmesh.case.pipeline import STAGES, CaseRun, RunContext, strategy_of
    from coastmesh.case.pipeline.size import size_stage
    from coastmesh.case.terms.base import SizeCase
    from coastmesh.sizing.combine import TermSizes, combine
    from coastmesh.types import quiet_stage, serial_runner

    ctx = RunContext(1, serial_runner, quiet_stage)
    run = CaseRun(config, strategy_of(config))
    for stage in STAGES:
        run = stage(run, ctx)
        if stage is size_stage:
            break
    state, grid, size = run.domain, run.size.grid, config.size
    case = SizeCase(
        config,
        state.domain,
        floor(size),
        read_depth=partial(run.strategy.read_depth, run),
        runner=ctx.runner,
        closing=state.closing,
    )
    terms = {term.key: term.sizes(grid, case) for term in TERMS}

    def combined(chosen) -> np.ndarray:
        chosen = [(k, sizes) for k, sizes in chosen if sizes is not None]
        out = combine(grid, chosen, h_min=case.floor, h_max=size.h_max, rate=size.rate)
        return out.field.values

    field = run.size.field.values
    bathymetry = terms.get("bathymetry")
    upper = independent_gradations(grid, state.domain, size)
    return {
        "grid": grid,
        "field": field,
        "gradation": combined([("gradations", terms["gradations"])]),
        "independent": combined([("gradations", TermSizes(upper=upper))]),
        "bathymetry": None if bathymetry is None else bathymetry.upper,
        "bathymetry_graded": combined([("bathymetry", bathymetry)]),
        "recombined": float(np.max(np.abs(combined(terms.items()) / field - 1))),
        "h_max": size.h_max,
        "seconds": dict(ctx.seconds),
    }


def along(p: np.ndarray, q: np.ndarray, step: float) -> np.ndarray:
    """Points every ``step`` m or less from ``p`` to ``q`` (k, 3), on the sphere."""
    from coastmesh.geometry import EARTH_RADIUS

    # (a repeated vertex, p == q, gives its point twice, not a division by 0)
    cuts = (
        np.maximum(np.ceil(np.linalg.norm(q - p, axis=1) / step), 1).astype(np.int64)
        + 1
    )
    edge = np.repeat(np.arange(len(p)), cuts)
    k = np.arange(cuts.sum()) - np.repeat(np.cumsum(cuts) - cuts, cuts)
    t = (k / np.repeat(cuts - 1, cuts))[:, None]
    points = p[edge] + t * (q[edge] - p[edge])
    return points * (EARTH_RADIUS / np.linalg.norm(points, axis=1))[:, None]


def independent_gradations(grid, domain, size) -> np.ndarray:
    """The gradations' sizes at the grid's nodes, from great-circle distances.

    As ``[[mesh_size.gradations]]`` asks: each gradation's lines are the
    domain's segments of those names; its size is
    :func:`~coastmesh.sizing.gradation.gradation_size` of the distance to the
    nearest of them; the gradations combine by their minimum.
    """
    from scipy.spatial import cKDTree

    from coastmesh.geometry import EARTH_RADIUS, reproject_points
    from coastmesh.geometry.sphere import lonlat_to_xyz
    from coastmesh.sizing.gradation import gradation_size

    glon, glat = np.meshgrid(grid.x, grid.y)
    nodes = lonlat_to_xyz(np.column_stack([glon.ravel(), glat.ravel()]), EARTH_RADIUS)
    upper = np.full(glon.size, float(size.h_max))
    for g in size.gradations:
        parts = []
        for segment in domain.segments:
            if segment.name in g.lines:
                lonlat = reproject_points(segment.coords, domain.crs, "EPSG:4326")
                xyz = lonlat_to_xyz(lonlat, EARTH_RADIUS)
                parts.append(along(xyz[:-1], xyz[1:], LINE_STEP))
        if not parts:
            continue
        reach = g.d_hold + g.d_grade + LINE_STEP
        chord = cKDTree(np.vstack(parts)).query(nodes, distance_upper_bound=reach)[0]
        chord = np.minimum(chord, 2 * reach)  # nothing within reach: h_max
        arc = 2 * EARTH_RADIUS * np.arcsin(np.minimum(chord / (2 * EARTH_RADIUS), 1))
        graded = gradation_size(arc, g.h_min, size.h_max, g.d_hold, g.d_grade)
        np.minimum(upper, graded, out=upper)
    return upper.reshape(glon.shape)


def at_centroids(grid, values, h_max: float, lonlat: np.ndarray) -> np.ndarray:
    """Interpolate grid values at lon/lat (bilinear, wrapping); no size is h_max."""
    from coastmesh.meshing.gmsh.sphere_sizes import SphereSizeGrid
    from coastmesh.types import SizeGrid

    if values is None:
        return np.full(len(lonlat), np.inf)
    values = np.nan_to_num(np.fmin(values, h_max), nan=h_max)
    field = SphereSizeGrid(SizeGrid(grid.x, grid.y, values))
    return field.at_lonlat(lonlat[:, 0], lonlat[:, 1])


def measure_elements(mesh, sizes: dict) -> dict:
    """Each triangle's centroid, size, and the sizes wanted there (metres)."""
    from coastmesh.geometry import EARTH_RADIUS
    from coastmesh.geometry.sphere import lonlat_to_xyz, xyz_to_lonlat
    from coastmesh.meshing.quality.measure import triangle_measures

    xyz = lonlat_to_xyz(mesh.points, radius=EARTH_RADIUS)
    centres = xyz_to_lonlat(xyz[mesh.triangles].sum(axis=1))
    size = triangle_measures(xyz, mesh.triangles, True, ("mean_edge",))
    grid, h_max = sizes["grid"], sizes["h_max"]
    keys = ("field", "gradation", "independent", "bathymetry", "bathymetry_graded")
    row = {"size_m": size["mean_edge"]}
    row.update({f"{k}_m": at_centroids(grid, sizes[k], h_max, centres) for k in keys})
    return {"lonlat": centres, "row": row}


def coast_tree(mesh):
    """A k-d tree of points every km along the mesh's coast, on the sphere (m).

    The coast is the boundary edges (edges of one triangle) that are not
    tagged as an open boundary.
    """
    from scipy.spatial import cKDTree

    from coastmesh.geometry import EARTH_RADIUS
    from coastmesh.geometry.sphere import lonlat_to_xyz
    from coastmesh.types.topology import unique_edges

    n = len(mesh.points)
    edges, count = unique_edges(mesh.triangles, n)
    edges = edges[count == 1]
    open_ids = [i for i, kind in mesh.boundary_kinds.items() if kind == "open"]
    tagged = np.sort(mesh.boundary_edges[np.isin(mesh.boundary_ids, open_ids)], 1)
    edges = edges[~np.isin(edges[:, 0] * n + edges[:, 1], tagged @ [n, 1])]
    xyz = lonlat_to_xyz(mesh.points, radius=EARTH_RADIUS)
    return cKDTree(along(xyz[edges[:, 0]], xyz[edges[:, 1]], COAST_STEP))


def stray_refinement(
    elements: dict,
    reference: str,
    tree,
    far_m: float,
    *,
    strict: bool = False,
) -> dict:
    """Count the small elements far from the coast, and what asked for them.

    ``reference`` names the gradation size in ``elements["row"]``. An element
    is excused when it is at least half the bathymetry term's size as graded
    (``strict``: when the term's own size is under the limit). Fills
    ``elements["row"]["coast_km"]`` for the small elements.
    """
    from coastmesh.geometry import EARTH_RADIUS
    from coastmesh.geometry.sphere import lonlat_to_xyz

    row = elements["row"]
    limit = SMALL * row[reference]
    small = np.flatnonzero(row["size_m"] < limit)
    coast = row.setdefault("coast_km", np.full(len(limit), np.nan))
    todo = small[np.isnan(coast[small])]
    xyz = lonlat_to_xyz(elements["lonlat"][todo], radius=EARTH_RADIUS)
    coast[todo] = tree.query(xyz)[0] / 1e3 if len(todo) else 0.0
    far = small[coast[small] > far_m / 1e3]
    if strict:
        excused = far[row["bathymetry_m"][far] < limit[far]]
    else:
        excused = far[row["size_m"][far] >= SMALL * row["bathymetry_graded_m"][far]]
    offenders = np.setdiff1d(far, excused)
    counts = {
        "small": len(small),
        "small_and_far": len(far),
        "excused_by_bathymetry": len(excused),
        "offenders": len(offenders),
        "offenders_within_bathymetry_gradation": int(
            (row["bathymetry_graded_m"][offenders] < limit[offenders]).sum()
        ),
        "offenders_the_field_asked_for": int(
            (row["field_m"][offenders] < limit[offenders]).sum()
        ),
        "offenders_below_half_the_bathymetry_term": int(
            (row["size_m"][offenders] < SMALL * row["bathymetry_m"][offenders]).sum()
        ),
        "offenders_median_size_over_field": round(
            float(np.median(row["size_m"][offenders] / row["field_m"][offenders]))
            if len(offenders)
            else 0.0,
            3,
        ),
    }
    return {"counts": counts, "offenders": offenders}


def clusters(mesh, elements: dict, offenders: np.ndarray, reference: str) -> list:
    """Group the offenders into clusters (joined by a node); largest first."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    if len(offenders) == 0:
        return []
    k = len(offenders)
    nodes, column = np.unique(mesh.triangles[offenders].ravel(), return_inverse=True)
    links = coo_matrix(
        (np.ones(3 * k), (np.repeat(np.arange(k), 3), k + column)),
        shape=(k + len(nodes), k + len(nodes)),
    )
    label = connected_components(links, directed=False)[1][:k]
    row = elements["row"]
    ratio = row["size_m"][offenders] / row[reference][offenders]
    out = []
    for group in np.unique(label):
        members = np.flatnonzero(label == group)
        t = int(offenders[members[np.argmin(ratio[members])]])
        lon, lat = elements["lonlat"][t]
        out.append(
            {
                "elements": len(members),
                "triangle": t,
                "lon": round(float(lon), 4),
                "lat": round(float(lat), 4),
                **{key: _rounded(values[t]) for key, values in row.items()},
            }
        )
    return sorted(out, key=lambda c: (-c["elements"], c["triangle"]))


def _rounded(value: float) -> float | None:
    return round(float(value), 1) if np.isfinite(value) else None


def agreement(sizes: dict) -> dict:
    """How far the gradations term is from the gradations worked out alone."""
    differ = np.abs(sizes["gradation"] / sizes["independent"] - 1).ravel()
    share, allowed = AGREE
    at = float(np.percentile(differ, share))
    return {
        f"p{share:g}_rel": round(at, 4),
        "max_rel": round(float(differ.max()), 4),
        "nodes_below_h_max_term": int((sizes["gradation"] < sizes["h_max"]).sum()),
        "nodes_below_h_max_independent": int(
            (sizes["independent"] < sizes["h_max"]).sum()
        ),
        "ok": at <= allowed,
    }


def field_against_tif(field: np.ndarray, output: Path) -> float | None:
    """Largest relative difference of the rebuilt field from ``size.tif``."""
    from coastmesh.io import read_raster

    path = output / "size.tif"
    if not path.exists():
        return None
    tif = read_raster(path).sortby("y").sortby("x")
    values = np.asarray(tif.values, dtype=np.float64).squeeze()
    if values.shape != field.shape:
        return None
    return float(np.max(np.abs(values / field - 1)))


def find_mesh(config, output: Path, given: str | None) -> Path:
    """The mesh to check: ``given``, else the case's UGRID, gr3 or fort.14."""
    if given is not None:
        return Path(given)
    for suffix in (".nc", ".gr3", ".14"):
        path = output / f"{config.name}{suffix}"
        if path.exists():
            return path
    raise SystemExit(f"{output}: no {config.name}.nc, .gr3 or .14; give --mesh")


def table(sphere, checks: dict, agree: dict, listed: list[dict]) -> str:
    """The targets, measured, as text."""
    verdict = {True: "pass", False: "FAIL"}
    bad = sphere.inverted + sphere.duplicated + sphere.coincident_nodes
    bad += sphere.overused_edges + sphere.folded_edges + sphere.spanning
    share = f"p{AGREE[0]:g}"
    lines = [
        f"{'target':<60} {'measured':>10}  result",
        f"{'p01 minimum angle on the sphere >= 30 deg':<60} "
        f"{sphere.min_angle_p1:>10.2f}  {verdict[sphere.min_angle_p1 >= 30]}",
        f"{'inverted, duplicated, coincident, folded, spanning = 0':<60} "
        f"{bad:>10,}  {verdict[bad == 0]}",
    ]
    for name, found in checks.items():
        n = found["counts"]["offenders"]
        text = f"small elements > {CELLS:g} cells from a coast, unasked ({name})"
        result = "(info)" if name == "strict" else verdict[n == 0]
        lines.append(f"{text:<60} {n:>10,}  {result}")
    text = f"gradations term = gradations alone ({share} relative difference)"
    at = agree[f"{share}_rel"]
    lines.append(f"{text:<60} {at:>10.3f}  {verdict[agree['ok']]}")
    c = checks["independent"]["counts"]
    lines.append(
        f"  independent: {c['small']:,} elements < {SMALL:g} x gradation size, "
        f"{c['small_and_far']:,} of them far from a coast, "
        f"{c['excused_by_bathymetry']:,} asked by the bathymetry term; of the "
        f"offenders {c['offenders_below_half_the_bathymetry_term']:,} are also < "
        f"{SMALL:g} x the bathymetry term's size, median size / field "
        f"{c['offenders_median_size_over_field']:.2f}"
    )
    if listed:
        which = "independent" if checks["independent"]["offenders"].size else "strict"
        lines.append(
            f"offenders ({which}) by cluster, {len(listed)} largest: elements, "
            "lon, lat, size / gradation / bathymetry / field (km), coast (km)"
        )
        lines += [
            f"  {c['elements']:>6,}  {c['lon']:>10.4f} {c['lat']:>9.4f}  "
            f"{c['size_m'] / 1e3:6.1f} / {c['independent_m'] / 1e3:6.1f} / "
            f"{(c['bathymetry_m'] or np.inf) / 1e3:6.1f} / {c['field_m'] / 1e3:6.1f}"
            f"  {c['coast_km']:7.1f}"
            for c in listed
        ]
    return "\n".join(lines)


def check(mesh, sizes: dict) -> tuple[dict, list]:
    """Target 2 against both gradation sizes, and strictly; the clusters.

    The clusters are the offenders against the independent gradation size,
    by the default's verdict, or by the strict one when that passes.
    """
    elements = measure_elements(mesh, sizes)
    tree = coast_tree(mesh)
    far_m = CELLS * sizes["grid"].cell_m
    checks = {
        name: stray_refinement(elements, f"{name}_m", tree, far_m)
        for name in ("independent", "gradation")
    }
    checks["strict"] = stray_refinement(
        elements, "independent_m", tree, far_m, strict=True
    )
    offenders = checks["independent"]["offenders"]
    if len(offenders) == 0:
        offenders = checks["strict"]["offenders"]
    listed = clusters(mesh, elements, offenders, "independent_m")
    return checks, listed


def main(argv: list[str] | None = None) -> int:
    """Rebuild the sizes, read the mesh, check both targets; 1 if one fails."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("case", help="the global case file that was run")
    parser.add_argument("output", help="its finished output folder")
    parser.add_argument("--mesh", help="the mesh file (default: found in output)")
    args = parser.parse_args(argv)
    import coastmesh
    from coastmesh.io import read_mesh
    from coastmesh.meshing.quality import sphere_quality

    config = coastmesh.read_case(args.case)
    if config.domain.kind != "global":
        raise SystemExit(f"{args.case}: [domain] kind is not global")
    output, seconds = Path(args.output), {}
    t = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", coastmesh.CoastmeshWarning)
        sizes = rebuild_sizes(config)
    seconds["stages and sizes"] = time.perf_counter() - t
    path = find_mesh(config, output, args.mesh)
    mesh = read_mesh(path, crs="EPSG:4326" if path.suffix != ".nc" else None)
    t = time.perf_counter()
    sphere = sphere_quality(mesh)
    seconds["sphere quality"] = time.perf_counter() - t
    t = time.perf_counter()
    checks, listed = check(mesh, sizes)
    seconds["stray refinement"] = time.perf_counter() - t
    agree = agreement(sizes)
    passed = {
        "sphere": sphere.ok,
        "no_refinement": checks["independent"]["counts"]["offenders"] == 0,
        "gradations_term": agree["ok"],
    }
    report = {
        "case": str(args.case),
        "mesh": str(path),
        "nodes": len(mesh.points),
        "triangles": len(mesh.triangles),
        "sphere": sphere.to_dict(),
        "no_refinement": {
            "far_km": CELLS * sizes["grid"].cell_m / 1e3,
            **{name: found["counts"] for name, found in checks.items()},
            "clusters": len(listed),
            "listed": listed[:LISTED],
        },
        "size_field": {
            "cell_km": sizes["grid"].cell_m / 1e3,
            "recombined_vs_stage_max_rel": sizes["recombined"],
            "rebuilt_vs_size_tif_max_rel": field_against_tif(sizes["field"], output),
            "gradations_term_vs_independent": agree,
        },
        "seconds": {
            **{k: round(v, 2) for k, v in sizes["seconds"].items()},
            **{k: round(v, 2) for k, v in seconds.items()},
        },
        "passed": passed,
    }
    print(json.dumps(report))
    print(table(sphere, checks, agree, listed[:LISTED]))
    return 0 if all(passed.values()) else 1


if __name__ == "__main__":
    sys.exit(main())
