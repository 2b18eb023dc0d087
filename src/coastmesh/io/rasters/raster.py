"""Read and write rasters (GeoTIFF, NetCDF, and for reading anything GDAL reads).

A raster is an :class:`xarray.DataArray` of float64 with dims ``("y", "x")``, 1-D
coordinates of cell centres, north-up (``y`` descending), NaN for missing cells,
and attrs ``crs`` (WKT or None), ``transform`` (the 6 affine coefficients
``a, b, c, d, e, f`` of the cell corners), ``nodata``, ``dtype`` (of the file) and
``source``.
"""

from __future__ import annotations

import logging
import math
import os
import warnings
from collections.abc import Sequence
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np
import rasterio
import rasterio.windows
import xarray as xr
from affine import Affine
from numpy.typing import NDArray
from pyproj import CRS
from pyproj.exceptions import CRSError
from rasterio.errors import NotGeoreferencedWarning, RasterioError, RasterioIOError

from coastmesh.errors import FormatError, InputDataError
from coastmesh.io._atomic import atomic_write
from coastmesh.io._cf import axis_attrs, grid_mapping_attrs
from coastmesh.io._drivers import raster_driver
from coastmesh.io._inputs import check_bbox, check_input

__all__ = ["raster_transform", "read_raster", "write_raster"]

logger = logging.getLogger(__name__)

_RESERVED_ATTRS = frozenset({"crs", "transform", "nodata", "dtype", "source"})
_NETCDF_DEFAULT_FILLS = (9.969209968386869e36, -2147483647, -32767, -127, 255)
_EDGE_TOLERANCE = 1e-9


def read_raster(
    path: str | os.PathLike[str], *, bbox: Sequence[float] | None = None
) -> xr.DataArray:
    """Read the first band of a raster into a north-up float64 DataArray.

    Parameters
    ----------
    path : str or path-like
        Any raster GDAL reads: GeoTIFF, GEBCO-style NetCDF with ``lat``/``lon``
        coordinates (either latitude order), ... A NetCDF file with several
        variables can be named ``NETCDF:"file.nc":variable``.
    bbox : sequence of 4 floats, optional
        ``(minx, miny, maxx, maxy)`` in the raster's CRS units; only the cells
        that overlap it are read.

    Returns
    -------
    xarray.DataArray of shape (ny, nx)
        Values in the file's units, NaN where the file has no data.

    Raises
    ------
    InputDataError
        If the file is missing, has several variables, ``bbox`` misses it, or its
        CRS is not understood.
    FormatError
        If GDAL cannot read the file as a raster, or the grid is rotated.
    ConfigError
        If ``bbox`` is malformed.

    Examples
    --------
    >>> from coastmesh.data import path as data_path
    >>> depth = read_raster(data_path("etopo1_0.1deg_orkney_wide.tif"))
    >>> depth.shape, depth.dims
    ((51, 101), ('y', 'x'))
    """
    source = check_input(path)
    box = None if bbox is None else check_bbox(bbox)
    with rasterio.Env():
        dataset = _open(source)
        with dataset:
            return _read(dataset, source, box)


def write_raster(
    path: str | os.PathLike[str], raster: xr.DataArray, *, overwrite: bool = False
) -> None:
    """Write a raster to GeoTIFF or NetCDF, atomically.

    Parameters
    ----------
    path : str or path-like
        ``.tif``/``.tiff`` (GeoTIFF, deflate-compressed) or ``.nc`` (CF NetCDF-4
        with ``lat``/``lon`` or ``y``/``x`` coordinates, latitude ascending, and a
        ``crs`` grid-mapping variable).
    raster : xarray.DataArray of shape (ny, nx)
        As returned by :func:`read_raster`. The attrs ``dtype`` and ``nodata`` set
        the stored type and missing-value marker (integers are rounded); other
        string and number attrs (``history``, ``units``, ...) are stored as
        GeoTIFF tags or NetCDF attributes.
    overwrite : bool, default False
        Whether an existing file may be replaced.

    Raises
    ------
    FormatError
        If the extension is unknown, or NaN cells cannot be stored (an integer
        type without ``nodata``).
    OutputExistsError
        If ``path`` exists and ``overwrite`` is false.
    ValueError
        If ``raster`` is not 2-D or its grid cannot be worked out.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> grid = xr.DataArray([[1.0, 2.0], [3.0, 4.0]], dims=("y", "x"),
    ...                     coords={"y": [1.5, 0.5], "x": [0.5, 1.5]},
    ...                     attrs={"crs": "EPSG:32630"})
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "grid.tif"
    >>> write_raster(path, grid)
    >>> read_raster(path).values.tolist()
    [[1.0, 2.0], [3.0, 4.0]]
    """
    target = Path(path)
    driver = raster_driver(target)
    if raster.ndim != 2:
        raise ValueError(f"raster must be 2-D (y, x), got dims {raster.dims}")
    transform = raster_transform(raster)
    dtype = np.dtype(raster.attrs.get("dtype", raster.dtype))
    values, nodata = _encode(np.asarray(raster.values), dtype, raster.attrs, target)
    crs = _crs_of(raster)
    notes = {
        str(k): v
        for k, v in raster.attrs.items()
        if k not in _RESERVED_ATTRS and isinstance(v, str | int | float)
    }
    grid = _Grid(values, transform, crs, nodata, notes, raster.name)
    write = _write_geotiff if driver == "GTiff" else _write_netcdf
    with atomic_write(target, overwrite=overwrite) as staged:
        write(staged, grid)
    logger.debug("wrote %s: %d x %d cells", target, *raster.shape)


def raster_transform(raster: xr.DataArray) -> Affine:
    """Return the affine transform (cell corners) of a raster.

    Parameters
    ----------
    raster : xarray.DataArray of shape (ny, nx)
        With a ``transform`` attr, or regularly spaced 1-D coordinates of cell
        centres.

    Returns
    -------
    affine.Affine

    Raises
    ------
    ValueError
        If there is no ``transform`` attr and the coordinates are missing,
        shorter than 2 or not evenly spaced.

    Examples
    --------
    >>> grid = xr.DataArray([[1.0, 2.0], [3.0, 4.0]], dims=("y", "x"),
    ...                     coords={"y": [1.5, 0.5], "x": [0.5, 1.5]})
    >>> tuple(raster_transform(grid))[:6]
    (1.0, 0.0, 0.0, 0.0, -1.0, 2.0)
    """
    if raster.attrs.get("transform") is not None:
        return Affine(*raster.attrs["transform"][:6])
    ydim, xdim = raster.dims
    steps = []
    for dim in (xdim, ydim):
        if dim not in raster.coords or raster.sizes[dim] < 2:
            raise ValueError(
                f"raster has no 'transform' attr and no coordinate {dim!r} with at "
                "least 2 values to work it out from"
            )
        centres = np.asarray(raster.coords[dim], dtype=np.float64)
        step = np.diff(centres)
        if not np.allclose(step, step[0], rtol=1e-6, atol=0):
            raise ValueError(f"coordinate {dim!r} is not evenly spaced")
        steps.append((centres[0], float(step.mean())))
    (x0, dx), (y0, dy) = steps
    return Affine(dx, 0.0, x0 - dx / 2, 0.0, dy, y0 - dy / 2)


def _open(source: str) -> rasterio.io.DatasetReader:
    try:
        with warnings.catch_warnings():
            # a NetCDF container has no geotransform; _read checks each band's
            warnings.simplefilter("ignore", NotGeoreferencedWarning)
            dataset = rasterio.open(source)
    except RasterioIOError as exc:
        message = str(exc)
        if "No such file" in message:
            raise InputDataError(f"cannot be opened: {message}", path=source) from None
        reason = message.split(";", 1)[0].strip()
        detail = "" if "not recognized" in reason else f" ({reason})"
        raise FormatError(
            f"{source}: not a raster file GDAL can read{detail}"
        ) from None
    if dataset.count == 0 and dataset.subdatasets:
        subdatasets = list(dataset.subdatasets)
        dataset.close()
        if len(subdatasets) > 1:
            names = ", ".join(s.rsplit(":", 1)[-1] for s in subdatasets)
            raise InputDataError(
                f"holds {len(subdatasets)} variables ({names}); name one as "
                f'NETCDF:"{source}":VARIABLE',
                path=source,
            )
        return rasterio.open(subdatasets[0])
    if dataset.count == 0:
        dataset.close()
        raise InputDataError("has no raster bands", path=source)
    return dataset


def _read(
    dataset: rasterio.io.DatasetReader,
    source: str,
    box: tuple[float, float, float, float] | None,
) -> xr.DataArray:
    transform = dataset.transform
    if transform.b != 0 or transform.d != 0:
        raise FormatError(f"{source}: rotated or sheared grids are not supported")
    if transform == Affine.identity() and dataset.crs is None:
        raise InputDataError(
            "has no georeferencing (no geotransform and no CRS)", path=source
        )
    if dataset.count > 1:
        logger.info("%s: %d bands; reading band 1", source, dataset.count)
    window = rasterio.windows.Window(0, 0, dataset.width, dataset.height)
    if box is not None:
        window = _window(dataset, box, source)
    transform = Affine(
        transform.a,
        0.0,
        transform.c + transform.a * window.col_off,
        0.0,
        transform.e,
        transform.f + transform.e * window.row_off,
    )
    values = dataset.read(1, window=window).astype(np.float64)
    valid = dataset.read_masks(1, window=window) > 0
    values[~valid] = np.nan
    ny, nx = values.shape
    x = transform.c + transform.a * (np.arange(nx) + 0.5)
    y = transform.f + transform.e * (np.arange(ny) + 0.5)
    if transform.e > 0:
        values, y = values[::-1], y[::-1]
        transform = Affine(
            transform.a,
            0.0,
            transform.c,
            0.0,
            -transform.e,
            transform.f + transform.e * ny,
        )
    attrs: dict[str, Any] = {
        "crs": _crs_wkt(dataset, source),
        "transform": tuple(float(v) for v in transform[:6]),
        "nodata": _nodata(dataset),
        "dtype": dataset.dtypes[0],
        "source": source,
    }
    units = dataset.units[0] or dataset.tags(1).get("units")
    if units:
        attrs["units"] = units
    name = dataset.descriptions[0] or dataset.tags(1).get("NETCDF_VARNAME")
    raster = xr.DataArray(
        values,
        dims=("y", "x"),
        coords={"y": y, "x": x},
        name=name,
        attrs=attrs,
    )
    logger.info("read %s: %d x %d cells", source, ny, nx)
    return raster


def _window(
    dataset: rasterio.io.DatasetReader,
    box: tuple[float, float, float, float],
    source: str,
) -> rasterio.windows.Window:
    minx, miny, maxx, maxy = box
    t = dataset.transform  # not rotated: checked by the caller
    cols = ((minx - t.c) / t.a, (maxx - t.c) / t.a)
    rows = ((maxy - t.f) / t.e, (miny - t.f) / t.e)
    col0 = max(math.floor(min(cols) + _EDGE_TOLERANCE), 0)
    col1 = min(math.ceil(max(cols) - _EDGE_TOLERANCE), dataset.width)
    row0 = max(math.floor(min(rows) + _EDGE_TOLERANCE), 0)
    row1 = min(math.ceil(max(rows) - _EDGE_TOLERANCE), dataset.height)
    if col0 >= col1 or row0 >= row1:
        bounds = tuple(round(v, 6) for v in dataset.bounds)
        raise InputDataError(
            f"bbox {box} does not overlap the raster, whose bounds are {bounds}",
            path=source,
        )
    return rasterio.windows.Window(col0, row0, col1 - col0, row1 - row0)


def _crs_wkt(dataset: rasterio.io.DatasetReader, source: str) -> str | None:
    if dataset.crs is None:
        return None
    try:
        return CRS.from_user_input(dataset.crs.to_wkt()).to_wkt()
    except CRSError as exc:
        raise InputDataError(f"unknown CRS: {exc}", path=source) from None


def _nodata(dataset: rasterio.io.DatasetReader) -> float | None:
    nodata = dataset.nodata
    if nodata is None:
        return None
    if dataset.driver == "netCDF":
        tags = dataset.tags(1)
        declared = "_FillValue" in tags or "missing_value" in tags
        if not declared and any(
            np.isclose(nodata, fill, rtol=1e-7) for fill in _NETCDF_DEFAULT_FILLS
        ):
            return None
    return float(nodata)


def _crs_of(raster: xr.DataArray) -> CRS | None:
    crs = raster.attrs.get("crs")
    if crs is None or crs == "":
        return None
    return crs if isinstance(crs, CRS) else CRS.from_user_input(crs)


def _encode(
    values: NDArray[np.float64],
    dtype: np.dtype,
    attrs: dict[str, Any],
    target: Path,
) -> tuple[NDArray, float | None]:
    """Return the values in the stored type, NaN replaced by nodata, and nodata."""
    nodata = attrs.get("nodata")
    missing = np.isnan(values)
    if missing.any() and nodata is None:
        if dtype.kind != "f":
            raise FormatError(
                f"{target}: {int(missing.sum())} cells are missing but dtype {dtype} "
                "has no nodata value; set raster.attrs['nodata']"
            )
        nodata = float("nan")
    if dtype.kind in "iu":
        info = np.iinfo(dtype)
        values = np.clip(np.rint(values), info.min, info.max)
    filled = np.where(missing, nodata if nodata is not None else 0, values)
    return filled.astype(dtype), nodata


class _Grid(NamedTuple):
    """A raster ready to write: stored values, grid, CRS, nodata, notes, name."""

    values: NDArray
    transform: Affine
    crs: CRS | None
    nodata: float | None
    notes: dict[str, Any]
    name: object


def _axis_attrs(crs: CRS | None, axis: str) -> dict[str, str]:
    """Return the CF attributes of a coordinate; projected if the CRS is unknown."""
    return axis_attrs(crs, axis) or {
        "standard_name": f"projection_{axis.lower()}_coordinate"
    }


def _write_geotiff(path: Path, grid: _Grid) -> None:
    values, transform, crs, nodata, notes, name = grid
    ny, nx = values.shape
    profile: dict[str, Any] = {
        "driver": "GTiff",
        "height": ny,
        "width": nx,
        "count": 1,
        "dtype": values.dtype.name,
        "crs": None if crs is None else crs.to_wkt(),
        "transform": transform,
        "nodata": nodata,
        "compress": "deflate",
        "predictor": 3 if values.dtype.kind == "f" else 2,
    }
    if nx >= 256 and ny >= 256:
        profile.update(tiled=True, blockxsize=256, blockysize=256)
    try:
        with rasterio.Env(), rasterio.open(path, "w", **profile) as dst:
            dst.write(values, 1)
            dst.update_tags(**{k: str(v) for k, v in notes.items()})
            if name is not None:
                dst.set_band_description(1, str(name))
            if "units" in notes:
                dst.update_tags(1, units=str(notes["units"]))
    except RasterioError as exc:
        raise FormatError(
            f"{path.name}: GeoTIFF cannot hold this raster: {exc}"
        ) from None


def _write_netcdf(path: Path, grid: _Grid) -> None:
    values, transform, crs, nodata, notes, name = grid
    ny, nx = values.shape
    x = transform.c + transform.a * (np.arange(nx) + 0.5)
    y = transform.f + transform.e * (np.arange(ny) + 0.5)
    if transform.e < 0:
        values, y = values[::-1], y[::-1]
    geographic = crs is not None and crs.is_geographic
    xname, yname = ("lon", "lat") if geographic else ("x", "y")
    variable = str(name) if name is not None else "z"
    data_attrs: dict[str, Any] = {}
    if "units" in notes:
        data_attrs["units"] = str(notes["units"])
    coords = {
        yname: (yname, y, {**_axis_attrs(crs, "Y"), "axis": "Y"}),
        xname: (xname, x, {**_axis_attrs(crs, "X"), "axis": "X"}),
    }
    data_vars: dict[str, Any] = {variable: ((yname, xname), values, data_attrs)}
    if crs is not None:
        data_attrs["grid_mapping"] = "crs"
        data_vars["crs"] = ((), np.int32(0), grid_mapping_attrs(crs))
    global_attrs = {"Conventions": "CF-1.8"}
    global_attrs.update({k: v for k, v in notes.items() if k != "units"})
    dataset = xr.Dataset(data_vars, coords=coords, attrs=global_attrs)
    encoding: dict[str, dict[str, Any]] = {
        variable: {
            "dtype": values.dtype,
            "_FillValue": nodata,
            "zlib": True,
            "complevel": 4,
        },
        xname: {"_FillValue": None},
        yname: {"_FillValue": None},
    }
    dataset.to_netcdf(path, engine="netcdf4", format="NETCDF4", encoding=encoding)
