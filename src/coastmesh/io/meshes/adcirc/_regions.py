"""Region ids beside a grid: ADCIRC ``fort.13`` and SCHISM ``.regions.prop``.

A mesh's triangles carry region ids (``Mesh.regions``: a tidal farm's, a turbine
footprint's, else the domain's ``surface_id``). Neither ``fort.14`` nor
``hgrid.gr3`` has a place for them, so the writers put them in a file beside
the grid, in each model's own convention, when the mesh has a region other than
its surface id.

ADCIRC, ``<stem>.13`` (``fort.13`` beside ``fort.14``): a nodal attributes file
with one attribute, ``coastmesh_region_id``, one value per node. The layout is
ADCIRC's (``adcirc/adcirc``: ``docs/technical_reference/input_files/fort13.rst``
and the format summary at the top of ``src/nodalattr.F``)::

    AGRID                 coastmesh region ids, innermost first: 100 20
    NumOfNodes            must equal NP of the fort.14
    NAttr                 1
    AttrName              coastmesh_region_id
    Units                 unitless
    ValuesPerNode         1
    DefaultAttrVal        the surface id (the sea)
    AttrName              coastmesh_region_id, again
    NumNodesNotDefaultVal
    n  value              one line per node whose id is not the default

Every value is written as an integer. ADCIRC does not know the attribute:
``ReadNodalAttr`` (``src/nodalattr.F``) logs "contains invalid name" for it and
skips its lines (three in the header, one per node in the body), and ``adcprep``
(``prep/prep.F``, ``PREP13``/``processNodalAttr``) splits it into the subdomain
files like any other attribute. So a run never stops on it; ADCIRC reads
``fort.13`` only when ``NWP > 0`` in ``fort.15``, and only uses the attributes
listed there. Names are read list-directed and compared whole, so no line holds
a comment (ADCIRC skips exactly one line of default values for an attribute it
does not know).

A node gets the id of the innermost region among its triangles: the surface id
only if all its triangles are the sea's; else, of the regions other than the
sea around it, the one with the smallest total area in the mesh (a turbine
footprint inside its farm), the smaller id of a tie. Every node of a footprint
keeps the footprint's id, as :mod:`coastmesh.io.meshes.msh` gives a footprint its own
nodes. The ``AGRID`` line lists that order, so a reader can undo it
(:func:`regions_from_nodes`).

SCHISM, ``<stem>.regions.prop`` (``hgrid.regions.prop`` beside ``hgrid.gr3``): an
element property file, one line per element, ``element_number region_id``
(1-based), no header, as SCHISM reads ``tvd.prop`` and ``fluxflag.prop``
(``schism-dev/schism``: ``docs/input-output/optional-inputs.md``, ".prop";
``src/Hydro/schism_init.F90`` reads ``j, value`` for each element in turn). It
holds the ids exactly, one per element. SCHISM reads no file of that name: it is
the source for the ``.prop`` and ``.gr3`` inputs a run uses (``fluxflag.prop``,
``drag.gr3``, ...; ``docs/formats.md`` shows how).
"""

from __future__ import annotations

import dataclasses
import os
import re
from pathlib import Path
from typing import IO, Any

import numpy as np
from numpy.typing import NDArray

from coastmesh.errors import FormatError, InputDataError, OutputExistsError
from coastmesh.io._inputs import check_input
from coastmesh.io.meshes._meshio import surface_of
from coastmesh.io.meshes._table import TextLines, put_lines, write_table
from coastmesh.types import Mesh

__all__ = [
    "ATTRIBUTE",
    "check_region_file",
    "has_regions",
    "node_regions",
    "read_fort13",
    "region_file",
    "regions_from_nodes",
    "with_region_file",
    "write_region_file",
]

#: The name of the nodal attribute in ``fort.13``: one word, as ADCIRC reads it.
ATTRIBUTE = "coastmesh_region_id"
UNITS = "unitless"
#: The ending of the region file beside each grid flavour.
SUFFIXES = {"fort14": ".13", "gr3": ".regions.prop"}
_ORDER = "coastmesh region ids, innermost first:"
# a line whose first word is the attribute's name
_NAME_LINE = re.compile(rf"^[ \t]*{ATTRIBUTE}(?=\s|$)", re.MULTILINE)
_ORDER_LINE = re.compile(r"^coastmesh region ids, innermost first:((?:\s+\d+)*)\s*$")


def has_regions(mesh: Mesh) -> bool:
    """Whether a triangle has a region id other than the mesh's surface id.

    Examples
    --------
    >>> m = Mesh([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]], [], [], 1, None)
    >>> has_regions(m)
    False
    """
    return bool((mesh.regions != mesh.surface_id).any())


def region_file(path: str | os.PathLike[str], flavour: str) -> Path:
    """Return the region file beside a grid: the grid's stem and its ending.

    Parameters
    ----------
    path : str or path-like
        The grid file.
    flavour : {"fort14", "gr3"}
        ``fort.13`` for ADCIRC, ``.regions.prop`` for SCHISM.

    Returns
    -------
    pathlib.Path

    Examples
    --------
    >>> region_file("run/fort.14", "fort14").as_posix()
    'run/fort.13'
    >>> region_file("hgrid.gr3", "gr3").name
    'hgrid.regions.prop'
    """
    return Path(path).with_suffix(SUFFIXES[flavour])


def check_region_file(
    path: str | os.PathLike[str], flavour: str, *, overwrite: bool
) -> Path:
    """Return the region file beside ``path``; refuse one that may not be written.

    Raises
    ------
    FormatError
        If the grid itself has the region file's name (``mesh.13`` as fort14).
    OutputExistsError
        If the region file exists and ``overwrite`` is false.
    """
    target = region_file(path, flavour)
    name = os.fspath(path)
    if os.path.abspath(target) == os.path.abspath(path):
        raise FormatError(
            f"{name}: the grid cannot end in {SUFFIXES[flavour]}, the ending of the "
            "region file written beside it; use .14 (or regions=False)"
        )
    if target.exists() and not overwrite:
        raise OutputExistsError(
            f"{target} already exists (the region ids beside {name}); use "
            "--overwrite (overwrite=True) to replace it, or regions=False to write "
            "the grid alone"
        )
    return target


def _areas(points: NDArray[np.float64], triangles: NDArray[np.int64]) -> NDArray:
    """Each triangle's area in the units of ``points`` squared."""
    p = points[triangles]
    d1, d2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    return 0.5 * np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])


def _innermost_first(ids: list[int], area: NDArray, regions: NDArray) -> list[int]:
    """Sort the ids by the area their triangles cover, smallest first, ties by id."""
    total = {r: float(area[regions == r].sum()) for r in ids}
    return sorted(ids, key=lambda r: (total[r], r))


def _region_order(mesh: Mesh) -> list[int]:
    """Return the mesh's region ids other than its surface id, innermost first."""
    return _innermost_first(
        [r for r in mesh.region_ids if r != mesh.surface_id],
        _areas(mesh.points, mesh.triangles),
        mesh.regions,
    )


def node_regions(mesh: Mesh) -> NDArray[np.int64]:
    """Return each node's region id: the innermost region among its triangles.

    Parameters
    ----------
    mesh : Mesh
        Its ``regions`` (one id per triangle) and ``surface_id``.

    Returns
    -------
    ndarray of shape (N,)
        int64. ``mesh.surface_id`` where every triangle around the node (or
        none) is the sea's; else, of the other regions around it, the one whose
        triangles cover the least area in the mesh (in the units of
        ``mesh.points``), the smaller id of a tie: a node on a turbine
        footprint's outline takes the footprint's id, not its farm's.

    Examples
    --------
    >>> m = Mesh([[0, 0], [1, 0], [1, 1], [0, 1]], [[0, 1, 2], [0, 2, 3]],
    ...          [], [], 1, None, regions=[1, 20])
    >>> node_regions(m).tolist()
    [20, 1, 20, 20]
    """
    order = _region_order(mesh)
    ranked = np.array([*order, mesh.surface_id], dtype=np.int64)
    rank = _ranks(mesh.regions, ranked)
    node_rank = np.full(len(mesh.points), len(order), dtype=np.int64)
    np.minimum.at(node_rank, mesh.triangles.ravel(), np.repeat(rank, 3))
    return ranked[node_rank]


def _ranks(values: NDArray[np.int64], ranked: NDArray[np.int64]) -> NDArray:
    """Return the place of each value in ``ranked`` (each value is one of them)."""
    order = np.argsort(ranked, kind="stable")
    return order[np.searchsorted(ranked[order], values)]


def regions_from_nodes(
    points: NDArray[np.float64],
    triangles: NDArray[np.int64],
    node_ids: NDArray[np.int64],
    surface_id: int,
    order: list[int] | None = None,
) -> NDArray[np.int64]:
    """Return each triangle's region id from node ids that :func:`node_regions` made.

    Parameters
    ----------
    points : ndarray of shape (N, 2)
        Node coordinates.
    triangles : ndarray of shape (M, 3)
        Node indices.
    node_ids : ndarray of shape (N,)
        Each node's region id.
    surface_id : int
        The sea's id.
    order : list of int, optional
        The ids other than ``surface_id``, innermost first, as the writer ranked
        them (the ``AGRID`` line of a ``fort.13`` coastmesh wrote). Without it
        (or if it lacks an id) they are ranked by the area of the triangles
        with a node of that id, smallest first, ties by id: a guess, which a
        footprint inside a farm of a few elements across passes, but a thin
        farm around a large region may not.

    Returns
    -------
    ndarray of shape (M,)
        The outermost id among each triangle's nodes: ``surface_id`` if one of
        them has it. This gives back the region of every triangle that has a
        node no region nested in its own took (a triangle whose three nodes all
        lie on the outlines of inner regions takes the outermost of those).

    Examples
    --------
    >>> points = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float)
    >>> triangles = np.array([[0, 1, 2], [0, 2, 3]])
    >>> regions_from_nodes(points, triangles, np.array([20, 1, 20, 20]), 1).tolist()
    [1, 20]
    """
    others = sorted(set(np.unique(node_ids).tolist()) - {surface_id})
    if order is not None:
        order = [r for r in order if r in set(others)]
    if order is None or sorted(order) != others:
        order = _star_order(points, triangles, node_ids, others)
    ranked = np.array([*order, surface_id], dtype=np.int64)
    return ranked[_ranks(node_ids, ranked)[triangles].max(axis=1, initial=0)]


def _star_order(
    points: NDArray[np.float64],
    triangles: NDArray[np.int64],
    node_ids: NDArray[np.int64],
    others: list[int],
) -> list[int]:
    """Sort ``others`` by the area of the triangles with a node of each id."""
    if not others:
        return []
    ids = np.asarray(others, dtype=np.int64)
    place = np.minimum(np.searchsorted(ids, node_ids), len(ids) - 1)
    place[ids[place] != node_ids] = -1  # the surface id
    corners = place[triangles]  # (M, 3)
    pairs = np.unique(  # each (triangle, id) once
        np.column_stack([np.repeat(np.arange(len(triangles)), 3), corners.ravel()]),
        axis=0,
    )
    pairs = pairs[pairs[:, 1] >= 0]
    area = np.bincount(
        pairs[:, 1],
        weights=_areas(points, triangles)[pairs[:, 0]],
        minlength=len(ids),
    )
    return sorted(others, key=lambda r: (area[others.index(r)], r))


def write_region_file(path: Path, mesh: Mesh, flavour: str) -> None:
    """Write the region ids as ``fort.13`` (``"fort14"``) or ``.regions.prop``.

    Parameters
    ----------
    path : pathlib.Path
        The file to write (a staging path: the caller publishes it).
    mesh : Mesh
        The mesh.
    flavour : {"fort14", "gr3"}
        Which file.
    """
    with open(path, "wb") as handle:
        if flavour == "gr3":
            m = len(mesh.triangles)
            write_table(handle, [(np.arange(1, m + 1), None), (mesh.regions, None)])
        else:
            _put_fort13(handle, mesh)


def _put_fort13(handle: IO[bytes], mesh: Mesh) -> None:
    ids = node_regions(mesh)
    surface = mesh.surface_id
    order = _region_order(mesh)
    nodes = np.flatnonzero(ids != surface)
    put_lines(
        handle,
        " ".join([_ORDER, *map(str, order)]),
        str(len(mesh.points)),
        "1",
        ATTRIBUTE,
        UNITS,
        "1",
        str(surface),
        ATTRIBUTE,
        str(len(nodes)),
    )
    if len(nodes):
        write_table(handle, [(nodes + 1, None), (ids[nodes], None)])


def read_fort13(path: str | os.PathLike[str]) -> dict[str, Any]:
    r"""Read an ADCIRC ``fort.13`` nodal attributes file as it is written.

    Parameters
    ----------
    path : str or path-like
        The file. Each attribute's default values are on one line, and each
        non-default node on one line, as ADCIRC skips them.

    Returns
    -------
    dict
        ``title`` (the ``AGRID`` line); ``np`` and ``nattr`` (ints, as declared);
        ``attributes``: a dict by name, in header order, of dicts with ``units``
        (str), ``values_per_node`` (int), ``default`` (float array of that
        length), ``nodes`` (int array, node numbers from 1, in file order) and
        ``values`` (float array of shape (len(nodes), values_per_node)).

    Raises
    ------
    InputDataError
        If the file is missing or ends early, a count or value is not a number,
        a body attribute is not in the header, or a node number is outside
        ``1..NumOfNodes``; the message names the line.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "fort.13"
    >>> _ = path.write_text("grid\n3\n1\nsurface_submergence_state\nunitless\n1\n"
    ...                     "0\nsurface_submergence_state\n1\n2 1\n")
    >>> attr = read_fort13(path)["attributes"]["surface_submergence_state"]
    >>> attr["default"].tolist(), attr["nodes"].tolist(), attr["values"].tolist()
    ([0.0], [2], [[1.0]])
    """
    return _parse_fort13(TextLines.read(check_input(path)))


def _parse_fort13(lines: TextLines) -> dict[str, Any]:
    """Parse the lines of a ``fort.13`` (:func:`read_fort13`)."""
    out: dict[str, Any] = {"title": lines.next_line().strip()}
    (out["np"],) = lines.ints(1, "NumOfNodes")
    (out["nattr"],) = lines.ints(1, "NAttr")
    attributes: dict[str, dict[str, Any]] = {}
    for _ in range(out["nattr"]):
        (name,) = lines.fields(1, "AttrName")
        units = lines.next_line().strip()
        (k,) = lines.ints(1, f"ValuesPerNode of {name}")
        if k < 1:
            raise lines.error(f"ValuesPerNode of {name}", "expected at least 1")
        default = lines.table(1, k, float, f"DefaultAttrVal of {name}")[0]
        attributes[name] = {"units": units, "values_per_node": k, "default": default}
    for _ in range(out["nattr"]):
        (name,) = lines.fields(1, "AttrName")
        if name not in attributes:
            raise lines.error("AttrName", "this attribute is not in the header")
        (count,) = lines.ints(1, f"NumNodesNotDefaultVal of {name}")
        k = attributes[name]["values_per_node"]
        table = lines.table(count, 1 + k, float, f"n AttrVal of {name}")
        nodes = table[:, 0].astype(np.int64)
        if nodes.size and (nodes.min() < 1 or nodes.max() > out["np"]):
            raise lines.error(
                f"n AttrVal of {name}", f"node numbers must be in 1..{out['np']}"
            )
        attributes[name].update(nodes=nodes, values=table[:, 1:])
    out["attributes"] = attributes
    return out


def with_region_file(mesh: Mesh, path: str | os.PathLike[str], flavour: str) -> Mesh:
    """Return ``mesh`` with the region ids of the file beside its grid, if any.

    Parameters
    ----------
    mesh : Mesh
        As read from the grid, in file order.
    path : str or path-like
        The grid file; the region file is :func:`region_file` of it.
    flavour : {"fort14", "gr3"}
        Which region file to look for.

    Returns
    -------
    Mesh
        ``mesh`` itself if there is no region file (or, for ``fort.13``, it has
        no ``coastmesh_region_id``); else a copy with ``regions`` and
        ``surface_id`` set: from ``fort.13`` the default value is the surface
        id and :func:`regions_from_nodes` gives the triangles' ids; from
        ``.regions.prop`` the ids are exact and the surface id is the id of the
        most triangles.

    Raises
    ------
    InputDataError
        If the region file does not fit the grid (node or element count) or an
        id is not an integer >= 1.
    """
    source = region_file(path, flavour)
    if not source.is_file():
        return mesh
    if flavour == "gr3":
        regions = _read_prop(source, len(mesh.triangles))
        surface = surface_of(regions)
    else:
        found = _fort13_nodes(source, len(mesh.points))
        if found is None:
            return mesh
        ids, surface, order = found
        regions = regions_from_nodes(mesh.points, mesh.triangles, ids, surface, order)
    try:
        return dataclasses.replace(mesh, surface_id=surface, regions=regions)
    except ValueError as exc:
        message = f"does not fit the grid beside it: {exc}"
        raise InputDataError(message, path=os.fspath(source)) from None


def _fort13_nodes(
    source: Path, n: int
) -> tuple[NDArray[np.int64], int, list[int] | None] | None:
    """Return the node ids, surface id and listed order of a ``fort.13``.

    None if no line names the attribute: the file is not parsed then, so a
    ``fort.13`` of the user's own (other attributes) never stops the read.
    """
    with open(source, encoding="utf-8", errors="replace") as handle:
        text = handle.read()
    if not _NAME_LINE.search(text):
        return None
    parsed = _parse_fort13(TextLines(source, text.splitlines()))
    attr = parsed["attributes"].get(ATTRIBUTE)
    if attr is None:
        return None
    name = os.fspath(source)
    if parsed["np"] != n or attr["values_per_node"] != 1:
        raise InputDataError(
            f"NumOfNodes is {parsed['np']} and {ATTRIBUTE} has "
            f"{attr['values_per_node']} values per node; the grid beside it has "
            f"{n} nodes and the attribute 1 value per node",
            path=name,
        )
    (surface,) = _whole_ids(attr["default"], name, "the default value", "")
    ids = np.full(n, float(surface))
    ids[attr["nodes"] - 1] = attr["values"][:, 0]
    match = _ORDER_LINE.match(parsed["title"])
    order = [int(w) for w in match.group(1).split()] if match else None
    return _whole_ids(ids, name, f"{ATTRIBUTE}", "node"), int(surface), order


def _read_prop(source: Path, m: int) -> NDArray[np.int64]:
    """Return the region id of each element from a ``.regions.prop`` file."""
    lines = TextLines.read(check_input(source))
    table = lines.table(m, 2, float, "element_number region_id")
    if not np.array_equal(table[:, 0], np.arange(1, m + 1)):
        bad = int(np.flatnonzero(table[:, 0] != np.arange(1, m + 1))[0])
        raise InputDataError(
            f"line {bad + 1} has element number {table[bad, 0]:g}; expected the "
            f"elements 1..{m} of the grid beside it, in order",
            path=os.fspath(source),
        )
    if lines.remaining():
        raise InputDataError(
            f"{lines.remaining()} lines follow the {m} elements of the grid beside "
            "it; the files do not match",
            path=os.fspath(source),
        )
    return _whole_ids(table[:, 1], os.fspath(source), "the region id", "element")


def _whole_ids(
    values: NDArray[np.float64], name: str, what: str, where: str
) -> NDArray[np.int64]:
    """Return the values as int64 ids; raise unless each is an integer >= 1."""
    with np.errstate(invalid="ignore"):
        bad = ~np.isfinite(values) | (values != np.round(values))
        bad |= (values < 1) | (values >= 2.0**53)
    if bad.any():
        k = int(np.flatnonzero(bad)[0])
        place = f" at {where} {k + 1} ({int(bad.sum())} such)" if where else ""
        raise InputDataError(
            f"{what} is {values[k]:g}{place}; region ids are integers >= 1",
            path=name,
        )
    return values.astype(np.int64)
