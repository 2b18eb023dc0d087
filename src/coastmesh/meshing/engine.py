"""Gmsh meshing engine: a Domain and a size grid in, a Mesh out.

Gmsh is imported only inside :func:`~coastmesh.meshing.session.gmsh_session`,
so ``import coastmesh.meshing`` stays light. One part is one Gmsh model here;
several parts are tasks (:mod:`coastmesh.meshing.tasks`) for any executor. The
meshing CRS and the sizes in its map units come from
:mod:`coastmesh.meshing.projection`.
"""

from __future__ import annotations

import logging
import time
import warnings
from collections.abc import Callable
from typing import Any

import numpy as np
import shapely
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.errors import CoastmeshWarning, MeshingError
from coastmesh.meshing.boundary import check_boundary, resample_rings
from coastmesh.meshing.parts import MIN_PART_TRIANGLES, auto_parts, cut_lines
from coastmesh.meshing.projection import (
    default_mesh_crs,
    project_points,
    project_rings,
    sample_size,
    to_map_units,
)
from coastmesh.meshing.session import (
    ALGORITHMS,
    add_size_view,
    gmsh_session,
    set_options,
)
from coastmesh.meshing.surfaces import (
    Faces,
    canonical_order,
    chunked,
    ring_pieces,
    split_faces,
)
from coastmesh.meshing.tasks import (
    PartsReport,
    Runner,
    merge_parts,
    mesh_arrays,
    mesh_part,
    part_tasks,
    serial_runner,
)
from coastmesh.types import Domain, Mesh, Progress, SizeGrid

__all__ = ["ALGORITHMS", "PartsWarning", "generate_mesh", "mesh_in_parts"]

logger = logging.getLogger(__name__)


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
    runner: Runner | None = None,
    progress: Progress | None = None,
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
        (:mod:`~coastmesh.meshing.parts`), each meshed alone as a task (or
        more, where a cut crosses the water several times). Each cut is
        discretised once and both parts get its nodes, so the mesh conforms
        (:mod:`~coastmesh.meshing.tasks`). ``"auto"``: one part per 40,000
        expected triangles, rounded down to a power of two (at most 64). Fewer
        parts are made where no clean cut exists (a warning says so when
        ``parts`` is a number). The same ``parts`` and ``seed`` give the same
        mesh whatever ``runner``: nodes are numbered in order of x, then y.
    threads : int, default 1
        Gmsh threads (``General.NumThreads``) for a one-part mesh: its curves
        are meshed at once.
    runner : callable, optional
        ``runner(fn, tasks)`` returns ``[fn(t) for t in tasks]``, computed
        anywhere: a process pool or a Dask cluster
        (:func:`coastmesh.case.executor.open_runner`). Default: one after the
        other in this process.
    progress : callable, optional
        Called as ``progress(done, total)`` after each of the stages.

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

    Each segment is projected to ``mesh_crs`` and resampled to about two points
    per local target edge (:func:`~coastmesh.meshing.boundary.resample_rings`),
    keeping end points and corners. Every piece between kept points becomes a
    Gmsh spline through the resampled points, so the boundary is smooth at the
    target resolution. The size grid is handed to Gmsh as a list-based
    post-processing view of quadrangles (bilinear interpolation), padded to the
    domain's bounds with the edge values, and used as the background field;
    sizes from points, curvature and the boundary are switched off, and the
    integral of 1/h along curves is computed to a relative precision of 1e-4.
    The run is reproducible: one thread, a fixed seed, fixed options; the same
    input gives the same arrays.

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
        progress=progress,
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
    runner: Runner | None = None,
    progress: Progress | None = None,
) -> tuple[Mesh, PartsReport]:
    """:func:`generate_mesh`, also returning how the water was cut into parts.

    Takes the same arguments and raises the same errors.

    Returns
    -------
    mesh : Mesh
    parts : PartsReport
        The parts, their cuts (in ``output_crs``), and each part's expected and
        actual triangles and meshing time.
    """
    if not isinstance(domain, Domain):
        raise TypeError(f"domain is a {type(domain).__name__}, expected Domain")
    if not isinstance(size, SizeGrid):
        raise TypeError(f"size is a {type(size).__name__}, expected SizeGrid")
    if algorithm not in ALGORITHMS:
        raise ValueError(
            f"algorithm is {algorithm!r}; pick one of {sorted(ALGORITHMS)}"
        )
    if isinstance(seed, bool) or not isinstance(seed, int | np.integer) or seed < 0:
        raise ValueError(f"seed is {seed!r}, expected an integer >= 0")
    numbers = {"threads": threads} | ({} if parts == "auto" else {"parts": parts})
    for name, value in numbers.items():
        if (
            isinstance(value, bool)
            or not isinstance(value, int | np.integer)
            or value < 1
        ):
            raise ValueError(f"{name} is {value!r}, expected an integer >= 1")
    mesh_crs = default_mesh_crs(domain) if mesh_crs is None else CRS(mesh_crs)
    if not mesh_crs.is_projected:
        raise ValueError(
            f"mesh_crs {mesh_crs.name!r} is not projected; give a conformal "
            "projection in metres (default: the UTM zone of the domain)"
        )
    output_crs = domain.crs if output_crs is None else CRS(output_crs)
    total = 4

    def step(done: int) -> None:
        if progress is not None:
            progress(done, total)

    started = time.perf_counter()
    map_size = to_map_units(size, mesh_crs)
    rings, ids = project_rings(domain, mesh_crs)
    resampled, dropped = resample_rings(rings, lambda xy: sample_size(map_size, xy))
    ids = [ring_ids for r, ring_ids in enumerate(ids) if r not in set(dropped)]
    check_boundary(resampled)
    n_boundary = sum(len(p) - 1 for ring in resampled for seg in ring for p in seg)
    logger.info(
        "boundary: %d rings, %d -> %d vertices, %d islands dropped",
        len(rings),
        sum(len(c) for ring in rings for c in ring),
        n_boundary,
        len(dropped),
    )
    step(1)
    faces, wanted = _cut(resampled, ids, map_size, parts)
    if faces is None:
        tasks, results = [], []
        with gmsh_session() as gmsh:
            arrays = _run_gmsh(
                gmsh,
                resampled,
                ids,
                map_size,
                domain.surface_id,
                seed,
                algorithm,
                optimize,
                step,
                threads=int(threads),
            )
    else:
        tasks = part_tasks(
            faces, map_size, seed=int(seed), algorithm=algorithm, optimize=optimize
        )
        step(2)
        logger.info("meshing %d parts", len(tasks))
        results = (runner or serial_runner)(mesh_part, tasks)
        arrays = merge_parts(results)
    points, triangles, edges, edge_ids = canonical_order(*arrays)
    step(3)
    target = sample_size(size, points)
    points = project_points(points, mesh_crs, output_crs, what="mesh nodes")
    triangles = _orient(points, triangles)
    edges, edge_ids = _check_edges(triangles, edges, edge_ids)
    step(total)
    logger.info(
        "mesh: %d nodes, %d triangles, %d boundary edges in %.1f s",
        len(points),
        len(triangles),
        len(edges),
        time.perf_counter() - started,
    )
    cuts = (
        ()
        if faces is None
        else tuple(
            project_points(c, mesh_crs, output_crs, what="cuts")
            for c, pid in zip(faces.curves, faces.ids, strict=True)
            if pid is None
        )
    )
    mesh = Mesh(
        points,
        triangles,
        edges,
        edge_ids,
        domain.surface_id,
        output_crs,
        {"size": target},
        {s.physical_id: s.name for s in domain.segments},
        {s.physical_id: s.kind for s in domain.segments},
    )
    return mesh, PartsReport.of(parts, wanted, tasks, results, cuts)


def _cut(
    rings: list, ids: list, size: SizeGrid, parts: int | str
) -> tuple[Faces | None, int]:
    """Cut the water into parts; return its faces (None: one part) and the aim."""
    if parts == 1:
        return None, 1
    pieces, water = ring_pieces(rings, ids)
    wanted = auto_parts(water, size) if parts == "auto" else int(parts)
    if wanted == 1:
        return None, 1
    ends = np.array([p[i] for p, _ in pieces for i in (0, -1)])
    cuts = cut_lines(water, size, wanted, ends=ends)
    if parts != "auto" and len(cuts) < wanted - 1:
        warnings.warn(
            f"parts = {parts}: the water can be cut cleanly (every part at least "
            f"{MIN_PART_TRIANGLES:,} expected triangles, cuts clear of the coast "
            f"and of each other) at only {len(cuts)} places; meshing "
            f"{len(cuts) + 1} parts",
            PartsWarning,
            stacklevel=3,
        )
    if not cuts:
        return None, wanted
    faces = split_faces(pieces, water, cuts)
    return (faces if len(faces.faces) > 1 else None), wanted


def _run_gmsh(
    gmsh: Any,
    rings: list[list[list[NDArray[np.float64]]]],
    ids: list[list[int]],
    size: SizeGrid,
    surface_id: int,
    seed: int,
    algorithm: str,
    optimize: bool,
    step: Callable[[int], None],
    *,
    threads: int = 1,
) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """Build the one-part model, mesh it, and return its arrays."""
    try:
        set_options(gmsh, threads=threads, seed=seed, algorithm=algorithm)
        curve_ids = _build_model(gmsh, rings, ids, surface_id)
        bounds = shapely.MultiPoint(
            np.concatenate([p for ring in rings for seg in ring for p in seg])
        ).bounds
        add_size_view(gmsh, size, bounds)
        gmsh.model.mesh.generate(1)
        step(2)
        gmsh.model.mesh.generate(2)
        if optimize:
            gmsh.model.mesh.optimize("Relocate2D")
        return mesh_arrays(gmsh, curve_ids)
    except MeshingError:
        raise
    except Exception as exc:  # gmsh raises bare Exception with its last error
        raise MeshingError(f"Gmsh failed: {exc}") from exc


def _build_model(
    gmsh: Any,
    rings: list[list[list[NDArray[np.float64]]]],
    ids: list[list[int]],
    surface_id: int,
) -> dict[int, int]:
    """Add points, curves, the surface and physical groups; return curve -> id."""
    geo = gmsh.model.geo
    curve_ids: dict[int, int] = {}
    loops = []
    for ring, ring_ids in zip(rings, ids, strict=True):
        pieces = chunked(
            [(p, pid) for seg, pid in zip(ring, ring_ids, strict=True) for p in seg]
        )
        first = geo.addPoint(*pieces[0][0][0], 0.0)
        start = first
        curves = []
        for k, (piece, pid) in enumerate(pieces):
            inner = [geo.addPoint(x, y, 0.0) for x, y in piece[1:-1]]
            end = first if k == len(pieces) - 1 else geo.addPoint(*piece[-1], 0.0)
            tags = [start, *inner, end]
            curve = geo.addLine(*tags) if len(tags) == 2 else geo.addSpline(tags)
            curve_ids[curve] = pid
            curves.append(curve)
            start = end
        loops.append(geo.addCurveLoop(curves))
    surface = geo.addPlaneSurface(loops)
    geo.synchronize()
    for pid in sorted(set(curve_ids.values())):
        curves = [c for c, p in curve_ids.items() if p == pid]
        gmsh.model.addPhysicalGroup(1, curves, tag=pid)
    gmsh.model.addPhysicalGroup(2, [surface], tag=surface_id)
    return curve_ids


def _signed_areas(points: NDArray[np.float64], triangles: NDArray[np.int64]) -> NDArray:
    a, b, c = (points[triangles[:, k]] for k in range(3))
    return 0.5 * (
        (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1])
        - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    )


def _orient(points: NDArray[np.float64], triangles: NDArray[np.int64]) -> NDArray:
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
    key = directed[:, 0] * n + directed[:, 1]
    reverse = directed[:, 1] * n + directed[:, 0]
    boundary = key[~np.isin(key, reverse)]
    forward = edges[:, 0] * n + edges[:, 1]
    flip = ~np.isin(forward, boundary)
    edges = edges.copy()
    edges[flip] = edges[flip][:, ::-1]
    tagged = edges[:, 0] * n + edges[:, 1]
    if len(tagged) != len(boundary) or not np.isin(boundary, tagged).all():
        raise MeshingError(
            f"the mesh has {len(boundary)} boundary edges but {len(tagged)} tagged "
            "edges match them; Gmsh did not conform to the boundary"
        )
    order = np.argsort(ids, kind="stable")
    return edges[order], ids[order].astype(np.int64)
