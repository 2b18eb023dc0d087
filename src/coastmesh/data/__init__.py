"""The small real data sets bundled with coastmesh.

==================================  ===================================================
``norway_west_gshhg_f.geojson``     GSHHG 2.3.6 full-resolution shoreline, West Norway
                                    (lon 4..8, lat 60..62.5), 1,768 polygons
``orkney_gshhg_f.geojson``          GSHHG shoreline, Orkney and Caithness, 84 polygons
``etopo1_0.1deg_nwshelf.tif``       ETOPO1 bedrock relief on a 0.1 degree grid, NW
                                    European shelf (lon -16..26, lat 48..70), metres
``etopo1_0.1deg_nwshelf.nc``        the same grid as GEBCO-style NetCDF (lat ascending)
``etopo1_0.1deg_orkney_wide.tif``   ETOPO1 0.1 degree, Scotland/Orkney (lon -8..2,
                                    lat 56..61), 51 x 101 cells
``world_gshhg_l.zip``               GSHHG low resolution, whole world, with Antarctica
``world_gshhg_i.zip``               GSHHG intermediate resolution, whole world
``etopo1_0.5deg_world.tif``         ETOPO1 bedrock relief, whole world, 0.5 degree
==================================  ===================================================

Sources and licences are in ``coastmesh/data/README.md``.
"""

from __future__ import annotations

from importlib import resources
from pathlib import Path

from coastmesh.errors import ConfigError

__all__ = ["names", "path"]

_PACKAGE = "coastmesh"
_FOLDER = "data"
_SUFFIXES = (".geojson", ".tif", ".nc", ".zip", ".toml")


def names() -> list[str]:
    """Return the file names of the bundled data sets.

    Returns
    -------
    list of str
        Sorted file names, to pass to :func:`path`.

    Examples
    --------
    >>> "orkney_gshhg_f.geojson" in names()
    True
    """
    folder = resources.files(_PACKAGE) / _FOLDER
    return sorted(
        item.name
        for item in folder.iterdir()
        if item.is_file() and item.name.endswith(_SUFFIXES)
    )


def path(name: str) -> Path:
    """Return the path of a bundled data file.

    Parameters
    ----------
    name : str
        A file name from :func:`names`, e.g. ``"orkney_gshhg_f.geojson"``.

    Returns
    -------
    pathlib.Path
        A real file on disk, which GDAL can open.

    Raises
    ------
    ConfigError
        If there is no bundled file of that name; the message lists them.

    Examples
    --------
    >>> path("etopo1_0.1deg_orkney_wide.tif").name
    'etopo1_0.1deg_orkney_wide.tif'
    """
    known = names()
    if name not in known:
        raise ConfigError(
            f"no bundled data set {name!r}; pick one of {', '.join(known)}"
        )
    resource = resources.files(_PACKAGE) / _FOLDER / name
    return Path(str(resource))
