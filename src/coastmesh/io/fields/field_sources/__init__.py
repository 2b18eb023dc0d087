"""Field sources: a model's results (or any mesh with values) read as fields.

:func:`read_field_source` reads the mesh and the values of a first run, for the
size term that sizes a mesh from a field (issue 50). It reads

==========  ===================================================================
``anuga``   ANUGA ``.sww`` (netCDF), as ``anuga/file/sww.py`` writes it
``schism``  SCHISM 2D outputs ``out2d_*.nc`` (v5.10 on) and ``schout_*.nc``
``adcirc``  ADCIRC netCDF outputs (``fort.63.nc``, ``fort.64.nc``,
            ``maxele.63.nc``, ``maxvel.63.nc``) and the ASCII ones (``fort.63``,
            ``fort.64``, ``maxele.63``, ``maxvel.63``) with their grid
``ugrid``   any UGRID-1.0 netCDF file with one 2D mesh (Delft3D FM map files,
            :func:`~coastmesh.io.write_mesh` ``format="ugrid"``, xugrid)
``vtu``     VTK unstructured grids (``.vtu``), through meshio
==========  ===================================================================

and tells them apart by their contents. Each format is read in a module of its
own (``_anuga``, ``_schism``, ``_adcirc``, ``_ugrid``, ``_vtu``), which says
where its layout comes from; ``_netcdf`` holds what the netCDF ones share and
``_source`` the type and the helpers they all use. Every source becomes a
:class:`FieldSource`: nodes, triangles (a quad or polygon split in a fan from its
first node) and variables with the dimensions ``("time", "node")``,
``("node",)``, ``("time", "triangle")`` or ``("triangle",)``. The time series of
the netCDF formats stay on disk, as dask arrays of :data:`TIME_CHUNK` records,
so a reduction over time reads a record block at a time.
"""

from __future__ import annotations

import logging
import os
from collections.abc import Callable
from typing import Any

from pyproj import CRS

from coastmesh.errors import FormatError
from coastmesh.io._inputs import check_input
from coastmesh.io.fields.field_sources._adcirc import (
    adcirc_ascii_header,
    read_adcirc_ascii,
    read_adcirc_netcdf,
)
from coastmesh.io.fields.field_sources._anuga import DRY_HEIGHT, read_anuga
from coastmesh.io.fields.field_sources._netcdf import TIME_CHUNK, open_netcdf
from coastmesh.io.fields.field_sources._schism import read_schism
from coastmesh.io.fields.field_sources._source import (
    KINDS,
    READS,
    ROLES,
    FieldSource,
    given_crs,
)
from coastmesh.io.fields.field_sources._ugrid import read_ugrid, topologies
from coastmesh.io.fields.field_sources._vtu import read_vtu
from coastmesh.types import Mesh

__all__ = [
    "DRY_HEIGHT",
    "KINDS",
    "ROLES",
    "TIME_CHUNK",
    "FieldSource",
    "read_field_source",
]

logger = logging.getLogger(__name__)


def read_field_source(
    path: str | os.PathLike[str],
    *,
    mesh: str | os.PathLike[str] | Mesh | None = None,
    crs: Any = None,
) -> FieldSource:
    """Read a model's results (or any mesh with values) as a :class:`FieldSource`.

    Parameters
    ----------
    path : str or path-like
        The file: an ANUGA ``.sww``, a SCHISM ``out2d_*.nc`` or ``schout_*.nc``,
        an ADCIRC netCDF output or ASCII ``fort.63``, ``fort.64``,
        ``maxele.63`` or ``maxvel.63``, a UGRID netCDF file or a ``.vtu``. The
        format is told from the contents (the ASCII outputs also by their name).
    mesh : str, path-like or Mesh, optional
        The grid of an ADCIRC ASCII output (which holds values only), such as the
        ``fort.14`` it was run on, read with :func:`~coastmesh.io.read_mesh`.
        Other sources do not use it.
    crs : pyproj.CRS or CRS-like, optional
        The CRS of the coordinates; it replaces the one the file declares.

    Returns
    -------
    FieldSource
        See Notes for each format.

    Raises
    ------
    InputDataError
        If the file is missing or cannot be read as its format (the message names
        it, and the variable or record), an ADCIRC ASCII output is read without
        ``mesh``, or its node count differs from the mesh's.
    FormatError
        If the file is none of the formats read; the message lists them.
    ConfigError
        If ``crs`` is not a CRS.

    Notes
    -----
    **ANUGA** ``.sww``: nodes ``x + xllcorner``, ``y + yllcorner`` (float64),
    triangles ``volumes``; times ``time``, seconds after ``starttime``. Every
    variable on the points (``stage``, ``xmomentum``, ``ymomentum``,
    ``elevation``, ``friction``, ...) or on the triangles (the centroid values
    ``stage_c``, ...). Added: ``u = xmomentum / h`` and ``v = ymomentum / h``
    with ``h = stage - elevation`` (or the stored ``height``), and ``u = v = 0``
    where ``h <= DRY_HEIGHT`` (1 mm, as ANUGA's ``plot_utils.get_output``; the
    solver's own ``minimum_allowed_height`` is 1e-5 m). Roles ``u``, ``v``,
    ``elevation = stage``, ``bed = elevation``. CRS: the ``epsg`` attribute
    (ANUGA 4 writes it), else UTM ``zone`` on ``datum`` (WGS84: EPSG 326zz or
    327zz) in the ``hemisphere`` (if undefined, the one its ``false_northing``
    belongs to: 0 north, 10 000 000 south); None for zone -1 (no UTM zone).

    **SCHISM** ``out2d_*.nc``: nodes ``SCHISM_hgrid_node_x/y``, faces
    ``SCHISM_hgrid_face_nodes`` (1-based; -1 or the fill value after the third
    node of a triangle); every variable on the nodes or faces, with a time axis
    or not; ``bed = -depth`` added. Roles ``elevation``, ``u =
    depthAverageVelX``, ``v = depthAverageVelY``, ``bed``. The older
    ``schout_*.nc``: ``elev`` and ``dahv`` (split into ``dahv_x``, ``dahv_y``).
    CRS: SCHISM writes one (global attribute ``crs``, and a grid mapping
    ``crs``) only for lon/lat grids (``ics = 2``: EPSG:4326); else None.

    **ADCIRC** netCDF: nodes ``x``, ``y``, triangles ``element`` (1-based);
    ``zeta``, ``u-vel``, ``v-vel``, ``zeta_max``, ``time_of_zeta_max``,
    ``vel_max``, ``time_of_vel_max``, ``depth``... with -99999 as NaN (dry);
    ``bed = -depth`` added. Roles ``elevation = zeta``, ``u``, ``v``,
    ``elevation_max = zeta_max``, ``speed_max = vel_max``, ``bed``. CRS:
    EPSG:4326, as ADCIRC's spherical runs (``ICS = 2``) store lon/lat in
    degrees; None if ``x`` is marked Cartesian (``ICS = 1``). ASCII: a header
    line, ``NDSETS NP DT NSPOOL IRTYPE``, then per record ``TIME IT`` (sparse:
    ``TIME IT NNONDEF DEFVAL``) and one line ``node value(s)`` per node, as
    ADCIRC's ``globalio.F`` writes them. ``fort.63`` gives ``zeta``,
    ``fort.64`` ``u-vel`` and ``v-vel`` (time, node); ``maxele.63`` gives
    ``zeta_max`` and ``maxvel.63`` ``vel_max`` from the first record, and the
    second record, if there, as ``time_of_zeta_max`` or ``time_of_vel_max``
    (node). The nodes, triangles and CRS are the mesh's (EPSG:4326 if it has
    none and its coordinates are lon/lat), ``depth`` and ``bed`` its depth. The
    ASCII files are read whole, into float64 arrays.

    **UGRID**: the variable with ``cf_role = "mesh_topology"`` and
    ``topology_dimension = 2``, its ``node_coordinates`` and
    ``face_node_connectivity`` (``start_index``, ``_FillValue`` or a negative
    index for faces of fewer nodes); every variable on its node or face
    dimension, with the time axis (the dimension of ``time``) or not. Roles
    from CF standard names, where one variable has that name (on the nodes,
    else anywhere): ``sea_surface_height`` -> ``elevation``,
    ``sea_water_x_velocity`` -> ``u``, ``altitude`` -> ``bed``, ...; a
    ``depth`` with ``positive = "down"`` gives ``bed = -depth``. CRS: the grid
    mapping of the coordinates, topology or variables (its ``epsg`` or
    ``EPSG_code`` first, as Delft3D FM writes them), else None.

    **VTU**: the points (x, y; z is left out); triangle, quad and polygon cells
    (other cells are left out); point data on the nodes, cell data on the
    triangles (a vector's components as ``name_x``, ``name_y``, ``name_z``). No
    time, no roles.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from coastmesh.io import write_mesh
    >>> m = Mesh([[0, 0], [1, 0], [1, 1], [0, 1]], [[0, 1, 2], [0, 2, 3]],
    ...          [[0, 1], [1, 2], [2, 3], [3, 0]], [1, 1, 1, 1], 1, "EPSG:32630",
    ...          {"depth": [5.0, 6.0, 7.0, 8.0]})
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "square.nc"
    >>> write_mesh(path, m)
    >>> source = read_field_source(path)
    >>> source.kind, source.crs.to_epsg(), source.roles["bed"]
    ('ugrid', 32630, 'bed')
    >>> source.variables["bed"].values.tolist()
    [-5.0, -6.0, -7.0, -8.0]
    """
    name = check_input(path)
    given = given_crs(crs)
    with open(name, "rb") as file:
        magic = file.read(8)
    if magic[:3] == b"CDF" or magic == b"\x89HDF\r\n\x1a\n":
        source = _read_netcdf(name, given)
    elif name.lower().endswith(".vtu") or magic[:5] in (b"<?xml", b"<VTKF"):
        source = read_vtu(name, given)
    elif adcirc_ascii_header(name) is not None:
        source = read_adcirc_ascii(name, mesh, given)
    else:
        raise FormatError(f"{name}: not a field source coastmesh reads; {READS}")
    logger.debug(
        "%s: %s, %d nodes, %d triangles, %s records, variables %s",
        name,
        source.kind,
        len(source.points),
        len(source.triangles),
        "no" if source.times is None else len(source.times),
        ", ".join(source.variables),
    )
    return source


def _read_netcdf(name: str, given: CRS | None) -> FieldSource:
    """Read a netCDF source: ANUGA, SCHISM, ADCIRC or any UGRID file."""
    dataset = open_netcdf(name)
    names = set(map(str, dataset.variables))
    reader: Callable[[Any, str, CRS | None], FieldSource]
    if "SCHISM_hgrid_node_x" in names:
        reader = read_schism
    elif {"x", "y", "volumes"} <= names:
        reader = read_anuga
    elif {"x", "y", "element"} <= names:
        reader = read_adcirc_netcdf
    elif topologies(dataset):
        reader = read_ugrid
    else:
        dataset.close()
        raise FormatError(
            f"{name}: a netCDF file with no mesh coastmesh knows (no ANUGA, SCHISM "
            f"or ADCIRC variables, no UGRID 2D mesh topology); {READS}"
        )
    try:
        return reader(dataset, name, given)
    except BaseException:
        dataset.close()
        raise
