"""Write ``fort.14`` and ``hgrid.gr3`` files (:mod:`coastmesh.io.meshes.adcirc`).

Each boundary segment's count line ends with a comment naming its boundary id and
name (``= Number of nodes for open boundary 1: id 2 north``), which ADCIRC and
SCHISM skip and :func:`~coastmesh.io.meshes.adcirc.read_fort14_mesh` reads back.
"""

from __future__ import annotations

import logging
import os
import warnings
from typing import IO

import numpy as np
from numpy.typing import NDArray

from coastmesh.errors import CoastmeshWarning, ConfigError
from coastmesh.io._atomic import AtomicOutputs
from coastmesh.io.meshes._model import check_mesh, node_depth, require_kinds
from coastmesh.io.meshes._table import put_lines, write_table
from coastmesh.io.meshes.adcirc._regions import (
    check_region_file,
    has_regions,
    write_region_file,
)
from coastmesh.io.meshes.adcirc._segments import (
    DEFAULT_LAND,
    Segment,
    grid_segments,
    label,
    land_codes,
)
from coastmesh.io.meshes.sphere import on_sphere, pole_triangles
from coastmesh.types import Mesh

__all__ = ["write_fort14", "write_gr3"]

logger = logging.getLogger(__name__)

SIGNIFICANT = 15  # significant digits written for floats (float64 holds ~15.9)


def write_fort14(
    path: str | os.PathLike[str],
    mesh: Mesh,
    *,
    overwrite: bool = False,
    positive: str = "down",
    title: str | None = None,
    regions: bool = True,
    land: str = DEFAULT_LAND,
) -> None:
    """Write a mesh as an ADCIRC ``fort.14`` grid with its boundary segments.

    Parameters
    ----------
    path : str or path-like
        The output file, such as ``fort.14``.
    mesh : Mesh
        The mesh; every boundary id needs a kind in ``mesh.boundary_kinds``
        (``"open"`` or ``"shoreline"``). Depth is ``mesh.point_data["depth"]``
        (metres, positive down); without it every node gets depth 0, with a
        warning. Coordinates are written as they are (longitude, latitude in
        degrees for a geographic CRS, which ADCIRC runs with ``ICS`` 2 or 20 to
        24). In a global mesh, the elements that cross the antimeridian are
        written as every element is, counter-clockwise on the sphere (see
        Notes).
    overwrite : bool, default False
        Whether an existing file may be replaced.
    positive : {"down", "up"}, default "down"
        Sign of the written ``DP``: ``"down"`` writes the depth as it is (ADCIRC's
        ``DP`` is positive below the geoid), ``"up"`` writes its negative.
    title : str, optional
        The first line (``AGRID``); one line. By default ``coastmesh`` and the
        EPSG code of ``mesh.crs``.
    regions : bool, default True
        When the mesh has a region other than its surface id (a farm, a turbine
        footprint: ``mesh.regions``), also write the nodal attributes file
        ``fort.13`` beside the grid: the grid's stem with the ending ``.13``
        (``fort.14`` -> ``fort.13``, ``case.14`` -> ``case.13``). See Notes.
    land : {"essential", "natural"}, default "essential"
        The type of the land segments: ADCIRC's essential no-normal-flow
        boundaries, ``IBTYPE`` 0 (external) and 1 (islands), which set the
        normal velocity to zero at every coast node, or its natural ones,
        ``IBTYPE`` 20 and 21, which set the flux through the coast to zero in
        the continuity equation only
        (:func:`~coastmesh.io.meshes.adcirc._segments.land_codes` says why essential
        is the default).

    Raises
    ------
    FormatError
        If a boundary id has no kind, the boundary edges do not form simple rings,
        or the depth has the wrong shape or non-finite values; or, with a region
        file to write, the grid's own name ends in ``.13``.
    ConfigError
        If ``positive``, ``title`` or ``land`` is invalid.
    OutputExistsError
        If ``path``, or the ``.13`` file to write, exists and ``overwrite`` is
        false; then nothing is written.

    Warns
    -----
    CoastmeshWarning
        If the mesh has no ``depth`` point data (zeros are written), or a pole
        lies inside a triangle of a global mesh (ADCIRC then needs a rotation).

    Notes
    -----
    The boundary segments follow ADCIRC's rules, from its documentation and
    source (:mod:`coastmesh.io.meshes.adcirc._segments` names each):

    - the open boundaries (kind ``"open"``) are elevation-specified segments,
      ``IBTYPEE = 0``; open boundaries that meet at a corner are one segment,
      so no node is listed twice (ADCIRC adds the tide once per listing), and
      a ring open all round lists each node once;
    - each stretch of coast (kind ``"shoreline"``) between two open boundaries
      is one external land segment, from the end node of one open segment to
      the start node of the next, whatever shoreline sets make it up; a ring of
      coast with no open boundary on it (a lake) is one external segment closed
      by repeating its first node;
    - each island is one internal segment (``IBTYPE`` 1, or 21 with
      ``land="natural"``) closed by repeating its first node, whatever
      shoreline sets make it up;
    - the external segments come first, in order around the domain, then the
      islands; nodes run with the domain on the left (land on the right),
      counter-clockwise around the exterior and clockwise around islands, as
      the ADCIRC manual asks (``NBVV``).

    The boundary ids and names a segment cannot carry are kept in the comment
    after its counts, which ADCIRC skips: ``= Number of nodes for land boundary
    1: id 10 near; id 5 @301 far`` says that the segment's edges have id 10 up
    to its 301st node and id 5 from there
    (:func:`~coastmesh.io.meshes.adcirc._segments.label`).
    :func:`~coastmesh.io.meshes.adcirc.read_fort14_mesh` gives every edge its id back.

    A global mesh (:func:`~coastmesh.io.meshes.sphere.on_sphere`) keeps its longitudes
    in [-180, 180): ADCIRC finds each element that crosses the antimeridian by
    its negative Jacobian in the lon/lat plane and moves its lone node by 360
    degrees (``CAL_ELXV_SPCOOR`` in ``mesh.F``, ADCIRC v55), so the elements
    must run counter-clockwise on the sphere, as they do here. Its boundary is
    ordered on the sphere (:func:`~coastmesh.io.meshes.sphere.sphere_boundary_rings`):
    the exterior is the ring around the largest land, the other rings islands.

    The ``fort.13`` holds one nodal attribute, ``coastmesh_region_id``: its
    default is ``mesh.surface_id`` and each node whose id differs is listed with
    its id, an integer (:func:`~coastmesh.io.meshes.adcirc.node_regions`: a node takes
    the innermost region among its triangles). ADCIRC reads ``fort.13`` only
    when ``fort.15`` sets ``NWP > 0``, and does not know this attribute: it logs
    it as an invalid name and skips it (``nodalattr.F``), so a run never stops
    on it. Add the attributes a run uses (a bottom friction per region, ...) to
    this file and list those in ``fort.15``. Both files are written together
    through one staging step: an error leaves neither.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> m = Mesh([[0, 0], [1, 0], [1, 1], [0, 1]], [[0, 1, 2], [0, 2, 3]],
    ...          [[0, 1], [1, 2], [2, 3], [3, 0]], [2, 1, 1, 1], 1, None,
    ...          point_data={"depth": [5.0, 5.0, 4.0, 4.0]},
    ...          boundary_kinds={1: "shoreline", 2: "open"})
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "fort.14"
    >>> write_fort14(path, m)
    >>> from coastmesh.io.meshes.adcirc import read_fort14
    >>> grid = read_fort14(path)
    >>> grid["elements"].tolist(), grid["depth"].tolist()
    ([[1, 2, 3], [1, 3, 4]], [5.0, 5.0, 4.0, 4.0])
    >>> [(b["nodes"].tolist(), b["ibtypee"]) for b in grid["open_boundaries"]]
    [([1, 2], 0)]
    >>> [(b["nodes"].tolist(), b["ibtype"]) for b in grid["land_boundaries"]]
    [([2, 3, 4, 1], 0)]

    With a farm (region 20) in the second triangle, ``fort.13`` comes beside it:

    >>> farm = Mesh(m.points, m.triangles, m.boundary_edges, m.boundary_ids, 1,
    ...             None, m.point_data, boundary_kinds=m.boundary_kinds,
    ...             regions=[1, 20])
    >>> write_fort14(path, farm, overwrite=True)
    >>> print((path.parent / "fort.13").read_text())  # doctest: +NORMALIZE_WHITESPACE
    coastmesh region ids, innermost first: 20
    4
    1
    coastmesh_region_id
    unitless
    1
    1
    coastmesh_region_id
    3
    1 20
    3 20
    4 20
    """
    _write_grid(
        path,
        mesh,
        "fort14",
        overwrite=overwrite,
        positive=positive,
        title=title,
        regions=regions,
        land=land,
    )


def write_gr3(
    path: str | os.PathLike[str],
    mesh: Mesh,
    *,
    overwrite: bool = False,
    positive: str = "down",
    title: str | None = None,
    regions: bool = True,
) -> None:
    """Write a mesh as a SCHISM ``hgrid.gr3`` with its boundary segments.

    Parameters
    ----------
    path : str or path-like
        The output file, such as ``hgrid.gr3`` (or ``hgrid.ll`` in degrees).
    mesh : Mesh
        The mesh; as for :func:`write_fort14`.
    overwrite : bool, default False
        Whether an existing file may be replaced.
    positive : {"down", "up"}, default "down"
        Sign of the written depth: SCHISM's depth is positive down.
    title : str, optional
        The first line, one line; SCHISM ignores it.
    regions : bool, default True
        When the mesh has a region other than its surface id, also write the
        element property file ``<stem>.regions.prop`` beside the grid
        (``hgrid.gr3`` -> ``hgrid.regions.prop``): one line per element,
        ``element_number region_id``, as SCHISM's ``.prop`` inputs are.

    Raises
    ------
    FormatError
        As :func:`write_fort14`.
    ConfigError
        If ``positive`` or ``title`` is invalid.
    OutputExistsError
        If ``path``, or the ``.regions.prop`` file to write, exists and
        ``overwrite`` is false; then nothing is written.

    Warns
    -----
    CoastmeshWarning
        If the mesh has no ``depth`` point data (zeros are written).

    Notes
    -----
    The boundary segments follow SCHISM's rules, from its source and
    ``hgrid.md`` (:mod:`coastmesh.io.meshes.adcirc._segments` names each):

    - each open boundary id is one open segment, whose header holds the node
      count only; open boundaries that meet share their corner node (SCHISM
      allows a node on two open segments) and each gets its own line in
      ``bctides.in``;
    - each stretch of coast between two open boundaries is one land segment,
      flag ``0``, whatever shoreline sets make it up; each island is one
      segment, flag ``1``, that lists its nodes without repeating the first;
    - a ring with no other boundary on it (a lake, or a ring open all round)
      is two segments linked at both ends, as SCHISM stops on an open segment
      that ends on its first node;
    - every boundary node is on a segment; the exterior runs
      counter-clockwise, its segments first.

    As in :func:`write_fort14`, the comment after a segment's counts keeps the
    boundary ids of its edges (``: id 10 near; id 5 @301 far``), and the
    counts carry SCHISM's comments (``= Number of open boundaries``, ...);
    SCHISM and ADCIRC skip both.

    A global mesh is written as :func:`write_fort14` writes it: longitudes in
    [-180, 180), every element counter-clockwise on the sphere, the boundary
    ordered on the sphere. SCHISM reads it as ``hgrid.ll`` (and ``hgrid.gr3``)
    with ``ics = 2`` (``param.nml``), in degrees, and works in a local frame
    on the sphere, so elements across the antimeridian need nothing more.

    The region ids are per element, as in the mesh, so ``.regions.prop`` holds
    them exactly (:func:`~coastmesh.io.meshes.adcirc.read_gr3_mesh` reads them back).
    SCHISM reads no file of that name: derive from it the inputs a run uses
    (``fluxflag.prop``, ``tvd.prop``; node values for ``drag.gr3`` or
    ``manning.gr3`` with :func:`~coastmesh.io.meshes.adcirc.node_regions`).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> m = Mesh([[0, 0], [1, 0], [1, 1], [0, 1]], [[0, 1, 2], [0, 2, 3]],
    ...          [[0, 1], [1, 2], [2, 3], [3, 0]], [1, 1, 1, 1], 1, None,
    ...          point_data={"depth": [5.0, 5.0, 4.0, 4.0]},
    ...          boundary_kinds={1: "shoreline"})
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "hgrid.gr3"
    >>> write_gr3(path, m)
    >>> from coastmesh.io.meshes.adcirc import read_fort14
    >>> land = read_fort14(path)["land_boundaries"]
    >>> [(b["nodes"].tolist(), b["ibtype"]) for b in land]
    [([1, 2, 3], 0), ([3, 4, 1], 0)]
    """
    _write_grid(
        path,
        mesh,
        "gr3",
        overwrite=overwrite,
        positive=positive,
        title=title,
        regions=regions,
    )


def _write_grid(
    path: str | os.PathLike[str],
    mesh: Mesh,
    flavour: str,
    *,
    overwrite: bool,
    positive: str,
    title: str | None,
    regions: bool,
    land: str = DEFAULT_LAND,
) -> None:
    """Check everything, then write a fort.14 (``flavour="fort14"``) or gr3.

    With ``regions`` and a mesh with regions, the region file goes beside it
    (:mod:`coastmesh.io.meshes.adcirc._regions`); both are published together.
    """
    check_mesh(mesh)
    name = os.fspath(path)
    land_codes(land)
    beside = None
    if regions and has_regions(mesh):
        beside = check_region_file(path, flavour, overwrite=overwrite)
    depth = node_depth(mesh, name, positive=positive, stacklevel=4)
    line = _title(mesh, title)
    kinds = require_kinds(mesh, name)
    open_segments, land_segments = grid_segments(mesh, name, kinds, flavour, land=land)
    if flavour == "fort14":
        _warn_poles(mesh, name)
    with AtomicOutputs(overwrite=overwrite) as outputs:
        grid = outputs.stage(path)
        staged = outputs.stage(beside) if beside is not None else None
        with open(grid, "wb") as handle:
            _put_grid(handle, mesh, line, depth, (open_segments, land_segments))
        if staged is not None:
            write_region_file(staged, mesh, flavour)
    logger.debug(
        "wrote %s (%s)%s: %d nodes, %d triangles, %d open and %d land segments",
        name,
        flavour,
        f" and {beside}" if beside is not None else "",
        len(mesh.points),
        len(mesh.triangles),
        len(open_segments),
        len(land_segments),
    )


def _put_grid(
    handle: IO[bytes],
    mesh: Mesh,
    line: str,
    depth: NDArray[np.float64],
    segment_lists: tuple[list[Segment], list[Segment]],
) -> None:
    """Write the grid: title, counts, nodes, elements, open then land segments."""
    n, m = len(mesh.points), len(mesh.triangles)
    put_lines(handle, line, f"{m} {n}")
    write_table(
        handle,
        [
            (np.arange(1, n + 1), None),
            (mesh.points[:, 0], SIGNIFICANT),
            (mesh.points[:, 1], SIGNIFICANT),
            (depth, SIGNIFICANT),
        ],
    )
    write_table(
        handle,
        [(np.arange(1, m + 1), None), (np.full(m, 3), None)]
        + [(mesh.triangles[:, k] + 1, None) for k in range(3)],
    )
    for word, segments in zip(("open", "land"), segment_lists, strict=True):
        put_lines(
            handle,
            f"{len(segments)} = Number of {word} boundaries",
            f"{sum(len(s.nodes) for s in segments)} = Total number of {word} "
            "boundary nodes",
        )
        for k, segment in enumerate(segments, start=1):
            code = "" if segment.code is None else f" {segment.code}"
            put_lines(
                handle,
                f"{len(segment.nodes)}{code} = Number of nodes for {word} boundary "
                f"{k}{label(segment.runs, mesh.boundary_names)}",
            )
            write_table(handle, [(segment.nodes + 1, None)])


def _warn_poles(mesh: Mesh, name: str) -> None:
    """Warn if a pole lies inside a triangle: ADCIRC must rotate it onto land."""
    if not on_sphere(mesh):
        return
    poles = pole_triangles(mesh.points, mesh.triangles)
    count = int(np.count_nonzero(poles))
    if count:
        which = " and ".join(
            label
            for sign, label in ((1, "North"), (-1, "South"))
            if (poles == sign).any()
        )
        warnings.warn(
            f"{name}: the {which} Pole lies inside the mesh ({count} triangle(s) "
            "around it); ADCIRC's spherical equations are singular there: run with "
            "a negative ICS (-20 to -24) and a fort.rotm that rotates the poles "
            "onto land",
            CoastmeshWarning,
            stacklevel=4,
        )


def _title(mesh: Mesh, title: str | None) -> str:
    if title is None:
        epsg = mesh.crs.to_epsg() if mesh.crs is not None else None
        return "coastmesh" + (f" EPSG:{epsg}" if epsg else "")
    if not isinstance(title, str) or "\n" in title or "\r" in title:
        raise ConfigError(f"title={title!r}: expected a string of one line")
    return title
