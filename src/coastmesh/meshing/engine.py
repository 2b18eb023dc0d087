"""Gmsh meshing engine: a Domain and a size grid in, a Mesh out.

Gmsh is imported only inside :func:`~coastmesh.meshing.gmsh.model.gmsh_session`,
so ``import coastmesh.meshing`` stays light. One part is one Gmsh model here;
several parts are tasks (:mod:`coastmesh.meshing.parts.tasks`) for any executor. The
meshing CRS and the sizes in its map units come from
:mod:`coastmesh.geometry.projection`.
"""

from __future__ import annotations

import logging
import time
import warnings
from concurrent.futures import ThreadPoolExecutor
from typing import Any, cast

import numpy as np
import shapely
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.errors import CoastmeshWarning, MeshingError
from coastmesh.geometry.projection import (
    default_mesh_crs,
    project_points,
    project_rings,
    sample_size,
    to_map_units,
)
from coastmesh.meshing.cleanup.aside import done_now
from coastmesh.meshing.cleanup.fixes import fix_seam_slivers
from coastmesh.meshing.cleanup.report import (
    CleanupOptions,
    PartCleanup,
    combine,
    stats,
)
from coastmesh.meshing.gmsh.boundary_nodes import boundary_nodes
from coastmesh.meshing.gmsh.crossings import boundary_crossings, resample_valid
from coastmesh.meshing.gmsh.model import (
    ALGORITHMS,
    crop_grid,
)
from coastmesh.meshing.gmsh.sphere_sizes import SphereSizeGrid
from coastmesh.meshing.parts import cuts as cut_plans
from coastmesh.meshing.parts.cuts import (
    MIN_PART_TRIANGLES,
    auto_parts,
    expected_triangles,
    plan_cuts,
    water_cells,
)
from coastmesh.meshing.parts.faces import (
    Faces,
    canonical_order,
    face_polygon,
    merge_small_faces,
    split_faces,
)
from coastmesh.meshing.parts.inner import (
    Inner,
    InnerPlane,
    label_regions,
    node_line,
    node_ring,
    smallest_side,
)
from coastmesh.meshing.parts.junctions import join_cuts
from coastmesh.meshing.parts.report import PartsReport
from coastmesh.meshing.parts.seams import smooth_seams
from coastmesh.meshing.parts.tasks import (
    PartMesh,
    PartTask,
    Runner,
    merge_parts,
    mesh_part,
    part_tasks,
    serial_runner,
    start_workers,
)
from coastmesh.types import Domain, Mesh, MeshLine, Progress, SizeGrid
from coastmesh.types.topology import unique_edges

__all__ = ["ALGORITHMS", "PartsWarning", "generate_mesh", "mesh_in_parts"]

logger = logging.getLogger(__name__)

#: A piece of the boundary: its nodes (k, 2) and its physical id.
_Piece = tuple[NDArray[np.float64], int]
#: The boundary (:func:`_boundary`): the rings' segments as projected, as
#: resampled (pieces of each), and the ids of the rings' segments.
_Boundary = tuple[
    list[list[NDArray[np.float64]]],
    list[list[list[NDArray[np.float64]]]],
    list[list[int]],
]
#: The parts joined (:func:`_joined`): points, triangles, edges, edge ids, and
#: the seam's nodes moved and (flips, splits).
_Joined = tuple[
    NDArray[np.float64],
    NDArray[np.int64],
    NDArray[np.int64],
    NDArray[np.int64],
    tuple[int, tuple[int, int]],
]


class PartsWarning(CoastmeshWarning):
    """The water could not be cut cleanly into as many parts as asked."""


def generate_mesh(
    domain: Domain,
    size: SizeGrid,
    *,
    mesh_crs: Any = None,
    output_crs: Any = None,
    seed: int = 0,
    algorithm: str = "frontal-delaunay",
    optimize: bool = True,
    parts: int | str = 1,
    threads: int = 1,
    runner: Runner[Any, Any] | None = None,  # runs boundary batches and parts
    cleanup: CleanupOptions | None = None,
    progress: Progress | None = None,
    inner: Inner | None = None,
    fixed_boundary: bool = False,
) -> Mesh:
    """Mesh a domain with triangles whose edge lengths follow a size grid.

    Parameters
    ----------
    domain : Domain
        The polygon and its tagged boundary segments, in ``domain.crs``.
    size : SizeGrid
        Target edge length in metres on the Earth, on a regular grid in
        ``mesh_crs`` coordinates; clamped to the nearest grid value outside the
        grid. Build it in :func:`~coastmesh.meshing.default_mesh_crs` when
        ``mesh_crs`` is not given.
    mesh_crs : pyproj.CRS or CRS-like, optional
        The CRS to mesh in: projected and conformal, so elements keep their shape
        on the Earth. Default :func:`~coastmesh.meshing.default_mesh_crs`.
    output_crs : pyproj.CRS or CRS-like, optional
        The CRS of the returned points. Default ``domain.crs``.
    seed : int, default 0
        Seed of Gmsh's random number generator (``Mesh.RandomSeed``); >= 0.
    algorithm : {"frontal-delaunay", "delaunay", "meshadapt", "automatic"}
        Gmsh's 2D algorithm.
    optimize : bool, default True
        Improve the triangles' shapes after meshing (Gmsh "Relocate2D").
    parts : int or "auto", default 1
        Cut the water into this many parts of equal expected triangle count
        (:mod:`~coastmesh.meshing.parts.cuts`), each meshed alone as a task (or
        more, where a cut crosses the water several times). Each cut is
        discretised once and both parts get its nodes, so the mesh conforms
        (:mod:`~coastmesh.meshing.parts.tasks`). ``"auto"``: one part per 200,000
        expected triangles, to the nearest power of two (at most 64). Fewer
        parts are made where no clean cut exists (a warning says so when
        ``parts`` is a number). The same ``parts`` and ``seed`` give the same
        mesh whatever ``runner``: nodes are numbered in order of x, then y.
    threads : int, default 1
        Threads for the size field's map units and the cleanup's report. The
        boundary nodes (:mod:`~coastmesh.meshing.gmsh.boundary_nodes`) are
        made on one Gmsh thread whatever it is, so that the mesh is the same
        bytes on any number.
    runner : callable, optional
        ``runner(fn, tasks)`` returns ``[fn(t) for t in tasks]``, computed
        anywhere: a process pool or a Dask cluster
        (:func:`coastmesh.case.executor.open_runner`). Default: one after the
        other in this process.
    cleanup : CleanupOptions, optional
        Clean each part where it is meshed
        (:func:`~coastmesh.meshing.parts.tasks.clean_part`:
        :func:`~coastmesh.meshing.clean_mesh` with the nodes of the cuts held);
        :func:`mesh_in_parts` reports what it did. Default: no cleanup.
    progress : callable, optional
        Called as ``progress(done, total)`` after each of the stages.
    inner : Inner, optional
        Regions (farms, turbine footprints) meshed as faces of their own, with
        their outlines as mesh edges and their triangles tagged with their ids
        (``mesh.regions``), and points that must be nodes (turbines), in
        ``domain.crs`` (:mod:`~coastmesh.meshing.parts.inner`). No cut of the
        water crosses a region: where one would, the water is meshed in one
        part (a warning says so).
    fixed_boundary : bool, default False
        The points of the domain's segments are its boundary nodes, as they
        are: no resampling, no node added or moved on the boundary (a hole
        cut in an existing mesh, whose edges the new mesh must share). The
        domain must then be in ``mesh_crs``, so the nodes keep their bits;
        the cleanup holds them.

    Returns
    -------
    Mesh
        Points in ``output_crs``; triangles counter-clockwise; every boundary edge
        oriented with the domain on its left and tagged with the ``physical_id``
        of its segment; ``surface_id`` from the domain. ``point_data["size"]`` is
        the target size at each node in metres on the Earth, from ``size``.

    Raises
    ------
    TypeError
        If ``domain`` or ``size`` has the wrong type.
    ValueError
        If ``algorithm``, ``seed`` or ``mesh_crs`` is invalid: a geographic or
        non-conformal ``mesh_crs`` (angular distortion above 1e-3 degrees on the
        size grid), or one in which a size grid node has no longitude and
        latitude.
    MeshingError
        If the boundary self-intersects after resampling, or Gmsh fails; the
        message carries Gmsh's last error.

    Warns
    -----
    SmallIslandWarning
        If islands smaller than the local size were dropped.
    PartsWarning
        If ``parts`` is a number the water cannot be cleanly cut into.

    Notes
    -----
    The sizes are metres on the Earth, and a conformal projection maps a length
    of h metres near a point to h * k map units, k the point scale factor there
    (``pyproj.Proj(mesh_crs).get_factors``, at each grid node's longitude and
    latitude in ``mesh_crs.geodetic_crs``). k is 0.9996 to 1.001 in a UTM zone
    but 2 at 60 degrees latitude in Mercator, so the grid is converted once to
    map units, ``size.values * k``, before the boundary is resampled and Gmsh
    sees it; edge lengths measured on the ellipsoid then follow ``size``.

    Each segment is projected to ``mesh_crs`` and resampled to about two
    points per local target edge
    (:func:`~coastmesh.meshing.gmsh.resample.resample_rings`), keeping end points
    and corners. Gmsh's 1-D mesher then places the boundary nodes on splines
    through those points, once, for the whole boundary
    (:mod:`~coastmesh.meshing.gmsh.boundary_nodes`, integral of 1/h to a relative
    precision of 1e-4), and the nodes are fixed: every boundary edge goes to
    the 2-D mesher as a straight line with its two end nodes only, so the
    boundary is the same whether the water is meshed whole or in parts (where
    a cut meets the boundary, the nearer node moves onto the meeting point:
    :mod:`~coastmesh.meshing.parts.junctions`). The size grid is handed to Gmsh as a
    list-based post-processing view of quadrangles (bilinear interpolation),
    padded to the part's bounds with the edge values, and used as the
    background field; sizes from points, curvature and the boundary are
    switched off. The run is reproducible: a fixed seed, fixed options; the
    same input gives the same arrays.

    Examples
    --------
    >>> import shapely
    >>> from coastmesh.types import BoundarySegment
    >>> ring = [[0, 0], [1000, 0], [1000, 1000], [0, 1000], [0, 0]]
    >>> d = Domain(shapely.Polygon(ring), (BoundarySegment(ring, "open", "b", 3),),
    ...            crs="EPSG:32630")
    >>> g = SizeGrid([0.0, 1000.0], [0.0, 1000.0], np.full((2, 2), 250.0))
    >>> m = generate_mesh(d, g)
    >>> sorted(set(m.boundary_ids.tolist())), m.surface_id, m.crs.to_epsg()
    ([3], 1, 32630)
    """
    return mesh_in_parts(
        domain,
        size,
        mesh_crs=mesh_crs,
        output_crs=output_crs,
        seed=seed,
        algorithm=algorithm,
        optimize=optimize,
        parts=parts,
        threads=threads,
        runner=runner,
        cleanup=cleanup,
        progress=progress,
        inner=inner,
        fixed_boundary=fixed_boundary,
    )[0]


def mesh_in_parts(
    domain: Domain,
    size: SizeGrid,
    *,
    mesh_crs: Any = None,
    output_crs: Any = None,
    seed: int = 0,
    algorithm: str = "frontal-delaunay",
    optimize: bool = True,
    parts: int | str = 1,
    threads: int = 1,
    runner: Runner[Any, Any] | None = None,  # runs boundary batches and parts
    cleanup: CleanupOptions | None = None,
    progress: Progress | None = None,
    inner: Inner | None = None,
    fixed_boundary: bool = False,
) -> tuple[Mesh, PartsReport]:
    """:func:`generate_mesh`, also returning how the water was cut into parts.

    Takes the same arguments and raises the same errors.

    Returns
    -------
    mesh : Mesh
    parts : PartsReport
        The parts, their cuts (in ``output_crs``), each part's expected and
        actual triangles and meshing and cleanup time, and the cleanup's report
        (``parts.cleanup``).
    """
    _check_args(domain, size, algorithm, seed, parts)
    mesh_crs = _projected(domain, mesh_crs)
    output_crs = domain.crs if output_crs is None else CRS(output_crs)
    total = 4

    def step(done: int) -> None:
        if progress is not None:
            progress(done, total)

    started = time.perf_counter()
    map_size = to_map_units(size, mesh_crs, threads=threads)
    if fixed_boundary:
        pieces, water = _fixed_nodes(domain, mesh_crs)
        step(1)
    else:
        rings, resampled, ids = _boundary(domain, mesh_crs, map_size)
        step(1)
        pieces, water = _nodes(
            (rings, resampled, ids), map_size, mesh_crs, runner, parts
        )
    plane = _inner_plane(inner, domain.crs, mesh_crs, map_size)
    pieces, chords, wanted = _cut(pieces, water, map_size, parts, plane, threads)
    faces = _faces(pieces, water, chords, plane, map_size, wanted)
    tasks = part_tasks(
        faces,
        map_size,
        seed=int(seed),
        algorithm=algorithm,
        optimize=optimize,
        cleanup=cleanup,
        exact=plane.rings,
        points=plane.points,
        lines=plane.mesh_lines(),
    )
    step(2)
    if len(tasks) > 1:
        logger.info("meshing %d parts", len(tasks))
        results = (runner or serial_runner)(mesh_part, tasks)
    else:
        results = [mesh_part(tasks[0])]
    joined = _joined(results, cleanup, _held_numbers(tasks, plane))
    step(3)
    mesh, cleaned = _mesh(
        domain, size, results, joined, cleanup, threads, (mesh_crs, output_crs), plane
    )

    step(total)
    logger.info(
        "mesh: %d nodes, %d triangles, %d boundary edges in %.1f s",
        len(mesh.points),
        len(mesh.triangles),
        len(mesh.boundary_edges),
        time.perf_counter() - started,
    )
    report = _parts_report(
        parts, wanted, tasks, results, faces, cleaned, (mesh_crs, output_crs)
    )
    return mesh, report


def _projected(domain: Domain, mesh_crs: Any) -> CRS:
    """Return the meshing CRS: the one given, or the domain's UTM zone."""
    crs = default_mesh_crs(domain) if mesh_crs is None else CRS(mesh_crs)
    if not crs.is_projected:
        raise ValueError(
            f"mesh_crs {crs.name!r} is not projected; give a conformal "
            "projection in metres (default: the UTM zone of the domain)"
        )
    return crs


def _nodes(
    boundary: _Boundary,
    map_size: Any,
    mesh_crs: CRS,
    runner: Runner[Any, Any] | None,
    parts: int | str,
) -> tuple[list[_Piece], shapely.Polygon]:
    """Return the boundary's mesh nodes and the water they bound, checked.

    The workers start meanwhile, on a thread (a head start only).
    """
    rings, resampled, ids = boundary
    with ThreadPoolExecutor(1) as side:  # while Gmsh makes the boundary nodes
        warming = side.submit(start_workers, runner, parts, rings, map_size)
        pieces, water = boundary_nodes(
            resampled, ids, map_size, runner or serial_runner
        )
        if (error := warming.exception()) is not None:
            logger.warning("workers not started ahead: %s", error)
    _check_nodes(water, mesh_crs)
    return pieces, water


def _fixed_nodes(
    domain: Domain, mesh_crs: CRS
) -> tuple[list[tuple[NDArray[np.float64], int]], shapely.Polygon]:
    """Return the domain's segments as they are, as the boundary's node chains."""
    if domain.crs != mesh_crs:
        raise ValueError(
            "fixed_boundary: the domain must be in mesh_crs, so that its points "
            f"are the nodes bit for bit (it is in {domain.crs.name!r})"
        )
    rings, ids = project_rings(domain, mesh_crs)
    pieces = [
        (np.asarray(xy, dtype=np.float64), pid)
        for ring, ring_ids in zip(rings, ids, strict=True)
        for xy, pid in zip(ring, ring_ids, strict=True)
    ]
    water = domain.polygon
    _check_nodes(water, mesh_crs)
    return pieces, water


def _boundary(domain: Domain, mesh_crs: CRS, map_size: Any) -> _Boundary:
    """Project the domain's rings and resample them to the local size.

    Returns the rings as projected, resampled, and the ids of the rings kept
    (an island whose perimeter is under three target edges is dropped).
    """
    rings, ids = project_rings(domain, mesh_crs)
    resampled, dropped = resample_valid(
        rings,
        lambda xy: sample_size(map_size, xy),
        lambda x, y: _lonlat(x, y, mesh_crs),
    )
    ids = [ring_ids for r, ring_ids in enumerate(ids) if r not in set(dropped)]
    logger.info(
        "boundary: %d rings, %d -> %d nodes, %d islands dropped",
        len(rings),
        sum(len(c) for ring in rings for c in ring),
        sum(len(p) - 1 for ring in resampled for seg in ring for p in seg),
        len(dropped),
    )
    return rings, resampled, ids


def _check_nodes(water: shapely.Polygon, mesh_crs: CRS) -> None:
    """Raise if the boundary's mesh nodes bound no valid polygon, naming where.

    Gmsh places the nodes along the resampled coast at the size, so two
    coasts closer than that can still cross between nodes; the overlays of
    the parts would then fail in GEOS ("side location conflict") far from
    the cause.
    """
    rings = [[[np.asarray(r.coords)]] for r in (water.exterior, *water.interiors)]
    crossing = boundary_crossings(rings)
    if len(crossing):
        raise MeshingError(
            f"the boundary's mesh nodes cross at {len(crossing)} places, the "
            f"first at {_lonlat(crossing[0, 0], crossing[0, 1], mesh_crs)}: two "
            "coasts there "
            "are closer than the size resolves; close the water there ([domain] "
            "close at least the size), or make the size there smaller"
        )


def _lonlat(x: float, y: float, crs: CRS) -> str:
    """Return a point of ``crs`` as ``"(lon, lat)"`` for a message."""
    lonlat = CRS.from_epsg(4326)
    lon, lat = project_points(np.array([[x, y]]), crs, lonlat, what="a point")[0]
    return f"({lon:.4f}, {lat:.4f}) (lon, lat)"


def _mesh(
    domain: Domain,
    size: Any,
    results: list[PartMesh],
    joined: _Joined,
    cleanup: CleanupOptions | None,
    threads: int,
    crss: tuple[CRS, CRS],
    plane: InnerPlane,
) -> tuple[Mesh, Any]:
    """Make the joined parts the mesh (in the output CRS); its cleanup's report."""
    mesh_crs, output_crs = crss
    points, triangles, edges, edge_ids, seam = joined
    with ThreadPoolExecutor(1) as side:
        # measured in a thread while the triangles are oriented, the nodes
        # projected and the boundary checked, with more than one worker
        # (numpy lets go of the GIL): the two took 1.2 s together in a profile
        # of the NW-shelf fine case, of about 4 s after the parts are joined
        aside = side.submit if threads > 1 else done_now
        cleaned = aside(
            _cleanup_report, results, points, triangles, edges, cleanup, seam
        )
        target = aside(sample_size, size, points)
        # oriented in the plane: conformal, so it is the orientation on the
        # Earth, and a triangle across the antimeridian has no sign in lon/lat
        triangles = _orient(points, triangles)
        regions = label_regions(
            points[triangles].mean(axis=1), plane, domain.surface_id
        )
        at = _line_nodes(points, plane)
        points = project_points(points, mesh_crs, output_crs, what="mesh nodes")
        lines = tuple(
            MeshLine(pid, name, points[nodes])
            for pid, name, nodes in zip(
                plane.line_ids, plane.line_names, at, strict=True
            )
        )
        edges, edge_ids = _check_edges(triangles, edges, edge_ids)
        report, sizes = cleaned.result(), target.result()
    mesh = Mesh(
        points,
        triangles,
        edges,
        edge_ids,
        domain.surface_id,
        output_crs,
        {"size": sizes},
        {s.physical_id: s.name for s in domain.segments},
        {s.physical_id: s.kind for s in domain.segments},
        regions,
        dict(zip(plane.ids, plane.names, strict=True)),
        lines,
    )
    return mesh, report


def _line_nodes(
    points: NDArray[np.float64], plane: InnerPlane
) -> list[NDArray[np.int64]]:
    """Return the node indices of each line of ``plane`` among ``points``.

    A line's nodes are held in every part and seam, so each is a mesh node at
    exactly its noded place.
    """
    if not plane.lines:
        return []
    probe = Mesh(
        points,
        np.empty((0, 3), np.int64),
        np.empty((0, 2), np.int64),
        np.empty(0, np.int64),
        1,
        None,
        lines=tuple(MeshLine(1, "line", xy) for xy in plane.lines),
    )
    try:
        edges = probe.line_edges()[0]
    except ValueError as exc:
        raise MeshingError(f"the mesh lost a node of a line: {exc}") from None
    sizes = np.cumsum([len(xy) - 1 for xy in plane.lines])[:-1]
    return [np.append(e[:, 0], e[-1, 1]) for e in np.split(edges, sizes)]


def _parts_report(
    parts: int | str,
    wanted: int,
    tasks: list[PartTask],
    results: list[PartMesh],
    faces: Any,
    cleaned: Any,
    crss: tuple[CRS, CRS],
) -> PartsReport:
    """How the water was cut into parts (the cuts and centres in the output CRS)."""
    mesh_crs, output_crs = crss
    cuts = tuple(
        project_points(c, mesh_crs, output_crs, what="cuts")
        for c, pid in zip(faces.curves, faces.ids, strict=True)
        if pid is None
    )
    if len(tasks) == 1:
        tasks, results = [], []  # one part: nothing to report but the aim
    centres = (
        project_points(
            np.array([t.centre for t in tasks]), mesh_crs, output_crs, what="parts"
        )
        if tasks
        else np.empty((0, 2))
    )
    return PartsReport.of(
        parts,
        wanted,
        tasks,
        results,
        cuts,
        tuple(map(tuple, centres.tolist())),
        cleaned,
    )


def _joined(
    results: list[PartMesh], cleanup: CleanupOptions | None, held: set[int]
) -> _Joined:
    """Join the parts; smooth the cuts; points, triangles, edges, ids, seam.

    ``seam``: the nodes moved at the cuts, and the slivers flipped and split
    there.

    ``held``: the shared numbers of the nodes that never move (region
    outlines, turbines).
    """
    points, triangles, edges, edge_ids = merge_parts(results)
    moved, fixes = 0, (0, 0)
    if cleanup is not None and cleanup.smooth and len(results) > 1:
        # the cuts' nodes (numbered first) were held in the parts: smooth them
        count = max(int(r.shared.max()) + 1 for r in results)
        fixed = np.zeros(len(points), dtype=bool)
        fixed[sorted(held)] = True
        seam = np.flatnonzero(~fixed[:count])
        if len(seam):
            points, moved = smooth_seams(points, triangles, edges, seam, fixed)
            # and the slivers there, which no part could reach whole
            points, triangles, fixes = fix_seam_slivers(
                points, triangles, edges, seam, fixed, cleanup.min_angle
            )
    points, triangles, edges, edge_ids = canonical_order(
        points, triangles, edges, edge_ids
    )
    return points, triangles, edges, edge_ids, (moved, fixes)


def _cleanup_report(
    results: list[PartMesh],
    points: NDArray[np.float64],
    triangles: NDArray[np.int64],
    edges: NDArray[np.int64],
    cleanup: CleanupOptions | None,
    seam: tuple[int, tuple[int, int]],
) -> Any:
    """Return the parts' cleanup reports combined, None without a cleanup."""
    if cleanup is None:
        return None
    # the "after" numbers, measured on the whole mesh
    on_boundary = np.zeros(len(points), dtype=bool)
    on_boundary[edges.ravel()] = True
    after = stats(points, triangles, on_boundary, cleanup.min_angle)
    # every part was cleaned: part_tasks gave each task this cleanup
    reports = cast("list[PartCleanup]", [r.cleanup for r in results])
    cleaned = combine(reports, after, seam_moved=seam[0], seam_fixes=seam[1])
    logger.info("cleanup: %s", cleaned.summary())
    return cleaned


def _check_args(domain: Any, size: Any, algorithm: str, seed: Any, parts: Any) -> None:
    """Refuse arguments of the wrong type or value (see :func:`generate_mesh`)."""
    if not isinstance(domain, Domain):
        raise TypeError(f"domain is a {type(domain).__name__}, expected Domain")
    if not isinstance(size, SizeGrid | SphereSizeGrid):
        raise TypeError(
            f"size is a {type(size).__name__}, expected SizeGrid or SphereSizeGrid"
        )
    if algorithm not in ALGORITHMS:
        raise ValueError(
            f"algorithm is {algorithm!r}; pick one of {sorted(ALGORITHMS)}"
        )
    if isinstance(seed, bool) or not isinstance(seed, int | np.integer) or seed < 0:
        raise ValueError(f"seed is {seed!r}, expected an integer >= 0")
    if parts != "auto" and (
        isinstance(parts, bool) or not isinstance(parts, int | np.integer) or parts < 1
    ):
        raise ValueError(f'parts is {parts!r}, expected "auto" or an integer >= 1')


def _faces(
    pieces: list[_Piece],
    water: shapely.Polygon,
    chords: list[NDArray[np.float64]],
    plane: InnerPlane,
    size: SizeGrid,
    wanted: int,
) -> Faces:
    """Return the faces of water the cuts and the inner outlines make.

    No face is left of a few triangles between two cuts: a face of under a
    tenth of its share of the water (the water's expected triangles over
    ``wanted``) and under the planners' floor joins a neighbour across a
    piece of cut (never an inner outline). Parts asked for on purpose that
    are small all the same (``[mesh] parts = 3`` on a small case) stay.
    """
    rings = [shapely.LineString(r) for r in plane.rings]
    faces = split_faces(pieces, water, [shapely.LineString(c) for c in chords] + rings)
    if len(faces.faces) < 2:
        return faces

    def cost(polygon: shapely.Polygon) -> float:
        return expected_triangles(polygon, crop_grid(size, polygon.bounds))

    total = sum(cost(face_polygon(faces, i)) for i in range(len(faces.faces)))
    small = min(cut_plans.MIN_PART_TRIANGLES, 0.1 * total / max(wanted, 1))
    faces, dropped = merge_small_faces(faces, water, cost, small, fixed=rings)
    if dropped:
        logger.info("%d pieces of cut dropped: faces of few triangles", dropped)
    return faces


def _cut(
    pieces: list[_Piece],
    water: shapely.Polygon,
    size: SizeGrid,
    parts: int | str,
    plane: InnerPlane,
    threads: int = 1,
) -> tuple[list[_Piece], list[NDArray[np.float64]], int]:
    """Cut the water into parts: the pieces joined to the cuts, chords, aim.

    No cut may cross a region of ``plane`` (or come within two of its
    outline's edges of it): if one would, the water is one part.
    """
    if parts == 1:
        return pieces, [], 1
    cells = water_cells(water, size, threads)  # a world's are 100 MB: let go below
    wanted = auto_parts(water, size, cells=cells) if parts == "auto" else int(parts)
    if wanted == 1:
        return pieces, [], 1
    ends = np.array([p[i] for p, _ in pieces for i in (0, -1)])
    cuts, missed = plan_cuts(water, size, wanted, ends=ends, cells=cells)
    del cells
    if parts != "auto" and missed:
        # counted as asked: a part cut again for its size (OVERSIZE) is not
        # one of them, so the count of parts alone would hide a shortfall
        warnings.warn(
            f"parts = {parts}: the water can be cut cleanly (every part at least "
            f"{MIN_PART_TRIANGLES:,} expected triangles, cuts clear of the coast "
            f"and of each other) at only {wanted - 1 - missed} of the "
            f"{wanted - 1} places asked; meshing {len(cuts) + 1} parts",
            PartsWarning,
            stacklevel=4,
        )
    if (plane.polygons or plane.lines) and cuts:
        keep_off = shapely.union_all(
            [
                shapely.buffer(g, 2 * smallest_side(plane))
                for g in [*plane.polygons, *map(shapely.LineString, plane.lines)]
            ]
        )
        if shapely.intersects(keep_off, shapely.MultiLineString(cuts)):
            warnings.warn(
                f"parts = {parts}: a cut of the water would cross a farm, a "
                "turbine footprint or a line; meshing the water in one part",
                PartsWarning,
                stacklevel=4,
            )
            return pieces, [], 1
    pieces, chords = join_cuts(pieces, water, cuts)
    return pieces, chords, wanted


def _signed_areas(
    points: NDArray[np.float64], triangles: NDArray[np.int64]
) -> NDArray[np.float64]:
    a, b, c = (points[triangles[:, k]] for k in range(3))
    return 0.5 * (
        (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1])
        - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    )


def _orient(
    points: NDArray[np.float64], triangles: NDArray[np.int64]
) -> NDArray[np.int64]:
    """Make every triangle counter-clockwise; raise on degenerate ones."""
    area = _signed_areas(points, triangles)
    if (area == 0).any():
        raise MeshingError(f"Gmsh made {(area == 0).sum()} triangles of zero area")
    triangles = triangles.copy()
    flip = area < 0
    triangles[flip] = triangles[flip][:, [0, 2, 1]]
    return triangles


def _check_edges(
    triangles: NDArray[np.int64], edges: NDArray[np.int64], ids: NDArray[np.int64]
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """Orient tagged edges along triangles, check they are the boundary, sort."""
    n = int(triangles.max()) + 1
    directed = np.concatenate(
        [triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]
    )
    undirected = directed.min(axis=1) * n + directed.max(axis=1)
    # an edge of one triangle only is a boundary edge; its directed key is
    # found by binary search (np.isin on millions of keys sorts both arrays
    # together, ten times slower)
    pairs, count = unique_edges(triangles, n)  # in increasing order of key
    single = pairs[count == 1] @ np.array([n, 1])
    boundary = np.sort(directed[_member(undirected, single)] @ np.array([n, 1]))
    forward = edges[:, 0] * n + edges[:, 1]
    flip = ~_member(forward, boundary)
    edges = edges.copy()
    edges[flip] = edges[flip][:, ::-1]
    tagged = edges[:, 0] * n + edges[:, 1]
    if len(tagged) != len(boundary) or not _member(boundary, np.sort(tagged)).all():
        raise MeshingError(
            f"the mesh has {len(boundary)} boundary edges but {len(tagged)} tagged "
            "edges match them; Gmsh did not conform to the boundary"
        )
    order = np.argsort(ids, kind="stable")
    return edges[order], ids[order].astype(np.int64)


def _member(
    keys: NDArray[np.int64], sorted_keys: NDArray[np.int64]
) -> NDArray[np.bool_]:
    """Return which of ``keys`` are in ``sorted_keys`` (ascending)."""
    if len(sorted_keys) == 0:
        return np.zeros(len(keys), dtype=bool)
    at = np.minimum(np.searchsorted(sorted_keys, keys), len(sorted_keys) - 1)
    found: NDArray[np.bool_] = sorted_keys[at] == keys  # numpy's stub: Any
    return found


def _inner_plane(
    inner: Inner | None, crs: CRS, mesh_crs: CRS, map_size: Any
) -> InnerPlane:
    """Return ``inner`` in the meshing CRS, its outlines noded at the local size."""
    if not inner:
        return InnerPlane([], [], [], [], np.empty((0, 2)))
    rings, polygons = [], []
    crs = CRS(inner.crs) if inner.crs is not None else CRS(crs)
    for polygon, _, _ in inner.regions:
        ring = np.asarray(polygon.exterior.coords)
        projected = ring
        if not crs.equals(mesh_crs):
            projected = project_points(ring, crs, mesh_crs, what="regions")
        noded = node_ring(projected, lambda xy: sample_size(map_size, xy))
        rings.append(noded)
        polygons.append(shapely.Polygon(noded))
    points = np.asarray(inner.points, dtype=np.float64).reshape(-1, 2)
    if len(points) and not crs.equals(mesh_crs):
        points = project_points(points, crs, mesh_crs, what="turbines")
    lines: list[NDArray[np.float64]] = []
    for given, _, _ in inner.lines:
        xy = np.asarray(given, dtype=np.float64)
        if not crs.equals(mesh_crs):
            xy = project_points(xy, crs, mesh_crs, what="lines")
        lines.append(node_line(xy, lambda p: sample_size(map_size, p)))
    return InnerPlane(
        rings,
        polygons,
        [int(pid) for _, pid, _ in inner.regions],
        [str(name) for _, _, name in inner.regions],
        points,
        lines,
        [int(pid) for _, pid, _ in inner.lines],
        [str(name) for _, _, name in inner.lines],
    )


def _held_numbers(tasks: list[PartTask], plane: InnerPlane) -> set[int]:
    """Return the shared numbers of the region outlines' and embedded nodes."""
    noded = {(float(x), float(y)) for ring in plane.rings for x, y in ring}
    held: set[int] = set()
    for task in tasks:
        for curve, pid, numbers in zip(task.curves, task.ids, task.shared, strict=True):
            if pid is None and all((float(x), float(y)) in noded for x, y in curve):
                held.update(numbers.tolist())
        held.update(task.embedded_numbers.tolist())
        for numbers in task.line_numbers:
            held.update(numbers.tolist())
    return held
