"""Read and write rasters a window of rows at a time, for grids larger than memory.

* :func:`open_raster_source` opens a raster once and describes it (grid, CRS,
  nodata, data type, and the window that ``bbox`` cuts) as a small
  :class:`RasterSource`, without reading its cells. A task on another thread,
  process or machine gets the :class:`RasterSource` (a path and a window, not the
  data) and reads its own cells with :func:`read_cells`.
* :class:`RasterWriter` writes a tiled, deflate-compressed GeoTIFF a rectangle
  of cells at a time, in any order.
* :func:`read_decimated` reads every k-th row and column, for figures.

Rows are counted north-up, as :func:`~coastmesh.io.read_raster` returns them,
whatever the file's order (GEBCO-style NetCDF runs south to north); cells are
float64 with NaN where the file has no data, as :func:`~coastmesh.io.read_raster`
gives them. The GDAL block cache is kept to :data:`GDAL_CACHE_MB` so that
reading a large file window by window does not fill memory with its blocks.
"""

from __future__ import annotations

import math
import os
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import rasterio
import rasterio.windows
import xarray as xr
from affine import Affine
from numpy.typing import NDArray
from rasterio.errors import NotGeoreferencedWarning, RasterioError

from coastmesh.errors import FormatError, InputDataError
from coastmesh.io._inputs import check_bbox, check_input
from coastmesh.io.rasters.raster import _crs_wkt, _encode, _nodata, _open, _window

__all__ = [
    "GDAL_CACHE_MB",
    "RasterSource",
    "RasterWriter",
    "encode_cells",
    "open_raster_source",
    "read_cells",
    "read_decimated",
]

#: Megabytes of GDAL block cache while streaming (GDAL's default is 5 % of RAM).
GDAL_CACHE_MB = 64
_TILE = 256  # default GeoTIFF tile side, in cells
_DECIMATED_CELLS = 1 << 22  # cells read at once by read_decimated


@dataclass(frozen=True, slots=True)
class RasterSource:
    """A raster file and the window of it to work on; small, to send to tasks.

    Attributes
    ----------
    path : str
        What GDAL opens (a NetCDF variable as ``NETCDF:"file.nc":name``);
        absolute, so that tasks elsewhere open the same file.
    row_off, col_off, height, width : int
        The window, in the file's rows and columns.
    flipped : bool
        Whether the file's rows run south to north (they are read upside down).
    transform : tuple of 6 floats
        Affine coefficients ``a, b, c, d, e, f`` of the window's cell corners,
        north-up.
    crs : str or None
        WKT.
    nodata : float or None
        The file's nodata value.
    dtype : str
        The file's data type.
    units, name : str or None
        Band units and variable name, if the file has them.
    source : str
        The path as given, for messages and the ``source`` attr.
    """

    path: str
    row_off: int
    col_off: int
    height: int
    width: int
    flipped: bool
    transform: tuple[float, ...]
    crs: str | None
    nodata: float | None
    dtype: str
    units: str | None
    name: str | None
    source: str

    @property
    def shape(self) -> tuple[int, int]:
        """``(rows, columns)`` of the window."""
        return self.height, self.width

    def attrs(self) -> dict[str, Any]:
        """Return the attrs :func:`~coastmesh.io.read_raster` gives this raster."""
        attrs: dict[str, Any] = {
            "crs": self.crs,
            "transform": self.transform,
            "nodata": self.nodata,
            "dtype": self.dtype,
            "source": self.source,
        }
        if self.units:
            attrs["units"] = self.units
        return attrs


def open_raster_source(
    path: str | os.PathLike[str], *, bbox: tuple[float, ...] | None = None
) -> RasterSource:
    """Open a raster and describe it (band 1) without reading its cells.

    Parameters
    ----------
    path : str or path-like
        Any raster GDAL reads, as for :func:`~coastmesh.io.read_raster`.
    bbox : sequence of 4 floats, optional
        ``(minx, miny, maxx, maxy)`` in the raster's CRS units: the window is
        the cells that overlap it.

    Returns
    -------
    RasterSource

    Raises
    ------
    InputDataError
        If the file is missing, has several variables, ``bbox`` misses it, or its
        CRS is not understood.
    FormatError
        If GDAL cannot read the file as a raster, or the grid is rotated.

    Examples
    --------
    >>> from coastmesh.data import path as data_path
    >>> source = open_raster_source(data_path("etopo1_0.1deg_nwshelf.nc"))
    >>> source.shape
    (221, 421)
    >>> read_cells(source, (0, 2), (10, 15)).shape
    (2, 5)
    """
    given = check_input(path)
    box = None if bbox is None else check_bbox(bbox)
    plain = not (given.startswith("/vsi") or "://" in given or ':"' in given)
    with _env():
        dataset = _open(os.path.abspath(given) if plain else given)
        with dataset:
            return _describe(dataset, given, box)


def read_cells(
    source: RasterSource,
    rows: tuple[int, int],
    columns: tuple[int, int] | None = None,
) -> NDArray[np.float64]:
    """Read rows ``[r0, r1)`` and columns ``[c0, c1)`` of a source's window.

    Parameters
    ----------
    source : RasterSource
        From :func:`open_raster_source`.
    rows : (int, int)
        ``(r0, r1)``: rows of the window, counted north-up,
        ``0 <= r0 < r1 <= height``.
    columns : (int, int), optional
        ``(c0, c1)``, ``0 <= c0 < c1 <= width``; all by default.

    Returns
    -------
    ndarray of shape (r1 - r0, c1 - c0)
        float64, north-up, NaN where the file has no data.

    Raises
    ------
    ValueError
        If the cells are outside the window.
    """
    columns = (0, source.width) if columns is None else columns
    for (start, stop), size, what in (
        (rows, source.height, "rows"),
        (columns, source.width, "columns"),
    ):
        if not 0 <= start < stop <= size:
            raise ValueError(
                f"{what} [{start}, {stop}) are outside the raster's {size} {what}"
            )
    with _env(), _open_quietly(source.path) as dataset:
        return _read(dataset, source, rows, columns)


def read_decimated(source: RasterSource, *, max_size: int = 1500) -> xr.DataArray:
    """Read every k-th row and column, so neither side exceeds ``max_size`` cells.

    The cells kept are rows and columns ``0, k, 2k, ...`` of the window (north-
    up), so two rasters on the same grid are sampled at the same cells. The
    file is read in bands of rows, about 4 million cells each.

    Parameters
    ----------
    source : RasterSource
        From :func:`open_raster_source`.
    max_size : int, default 1500
        Most cells along each side of the result.

    Returns
    -------
    xarray.DataArray of shape (ceil(height / k), ceil(width / k))
        As :func:`~coastmesh.io.read_raster` returns it, with cells ``k`` times
        larger in its ``transform``.

    Examples
    --------
    >>> from coastmesh.data import path as data_path
    >>> source = open_raster_source(data_path("etopo1_0.1deg_nwshelf.tif"))
    >>> read_decimated(source, max_size=100).shape
    (45, 85)
    """
    ny, nx = source.shape
    step = max(1, math.ceil(max(ny, nx) / max_size))
    band = max(1, _DECIMATED_CELLS // (nx * step)) * step  # rows read at once
    values = np.empty((math.ceil(ny / step), math.ceil(nx / step)))
    with _env(), _open_quietly(source.path) as dataset:
        for r0 in range(0, ny, band):
            cells = _read(dataset, source, (r0, min(ny, r0 + band)), (0, nx))
            values[r0 // step : (r0 + band) // step] = cells[::step, ::step]
    t = Affine(*source.transform)
    x = t.c + t.a * step * (np.arange(values.shape[1]) + 0.5)
    y = t.f + t.e * step * (np.arange(values.shape[0]) + 0.5)
    attrs = source.attrs()
    attrs["transform"] = (t.a * step, 0.0, t.c, 0.0, t.e * step, t.f)
    return xr.DataArray(
        values, dims=("y", "x"), coords={"y": y, "x": x}, name=source.name, attrs=attrs
    )


def encode_cells(
    values: NDArray[np.float64], dtype: str, nodata: float | None, target: str
) -> NDArray:
    """Return cells in the stored type, NaN replaced by ``nodata``.

    As :func:`~coastmesh.io.write_raster` stores a raster: integers are rounded
    and clipped to the type's range.

    Parameters
    ----------
    values : ndarray of shape (n, m)
        float64, NaN for missing cells.
    dtype : str
        The stored type.
    nodata : float or None
        The missing-value marker; NaN cells need one for an integer type.
    target : str
        The output, for the error message.

    Returns
    -------
    ndarray of shape (n, m)

    Raises
    ------
    FormatError
        If there are NaN cells, ``dtype`` is an integer type and ``nodata`` is None.
    """
    return _encode(values, np.dtype(dtype), {"nodata": nodata}, Path(target))[0]


class RasterWriter:
    """Write a GeoTIFF a rectangle of cells at a time, in any order, as a context.

    The file is tiled, deflate-compressed with a predictor, and BigTIFF if it
    might pass 4 GB. Give whole tiles (rectangles that start on a multiple of
    the tile's rows and columns), so that each tile is compressed and written
    once, and the file does not depend on the order of the writes.

    Parameters
    ----------
    path : str or path-like
        The file to create (a staging path: see :mod:`coastmesh.io._atomic`).
    shape : (int, int)
        Rows and columns.
    transform : tuple of 6 floats
        Affine coefficients of the cell corners.
    crs : str or None
        WKT.
    dtype : str
        The stored type.
    nodata : float or None
        The missing-value marker.
    tile : (int, int), default (256, 256)
        Rows and columns of a tile: multiples of 16.
    notes : dict, optional
        Tags (``history``, ``units``, ...).
    name : str, optional
        Band description.
    threads : int, default 1
        Threads GDAL compresses tiles on.

    Raises
    ------
    FormatError
        If GDAL cannot create the file, or the tiles are not multiples of 16.

    Examples
    --------
    >>> import numpy as np, tempfile, pathlib
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "a.tif"
    >>> t = (1.0, 0.0, 0.0, 0.0, -1.0, 3.0)
    >>> with RasterWriter(path, shape=(3, 2), transform=t, crs=None,
    ...                   dtype="float32", nodata=None) as out:
    ...     out.write(np.array([[5.0, 6.0]], dtype="float32"), row=2)
    ...     out.write(np.array([[1.0, 2.0], [3.0, 4.0]], dtype="float32"))
    >>> from coastmesh.io import read_raster
    >>> read_raster(path).values.tolist()
    [[1.0, 2.0], [3.0, 4.0], [5.0, 6.0]]
    """

    def __init__(
        self,
        path: str | os.PathLike[str],
        *,
        shape: tuple[int, int],
        transform: tuple[float, ...],
        crs: str | None,
        dtype: str,
        nodata: float | None,
        tile: tuple[int, int] = (_TILE, _TILE),
        notes: dict[str, Any] | None = None,
        name: str | None = None,
        threads: int = 1,
    ) -> None:
        self.path = Path(path)
        self.shape = (int(shape[0]), int(shape[1]))
        self.dtype = np.dtype(dtype)
        if any(side < 16 or side % 16 for side in tile):
            raise FormatError(
                f"{self.path.name}: tiles of {tile[0]} x {tile[1]} cells; GeoTIFF "
                "tiles need multiples of 16"
            )
        self.profile: dict[str, Any] = {
            "driver": "GTiff",
            "height": self.shape[0],
            "width": self.shape[1],
            "count": 1,
            "dtype": self.dtype.name,
            "crs": crs,
            "transform": Affine(*transform[:6]),
            "nodata": nodata,
            "tiled": True,
            "blockysize": tile[0],
            "blockxsize": tile[1],
            "compress": "deflate",
            "predictor": 3 if self.dtype.kind == "f" else 2,
            "BIGTIFF": "IF_SAFER",
            "NUM_THREADS": str(max(1, threads)),
        }
        self.notes = {str(k): str(v) for k, v in (notes or {}).items()}
        self.name = name
        self._env: Any = None
        self._dataset: Any = None

    def __enter__(self) -> RasterWriter:
        self._env = _env()
        self._env.__enter__()
        try:
            self._dataset = rasterio.open(self.path, "w", **self.profile)
            self._dataset.update_tags(**self.notes)
            if self.name is not None:
                self._dataset.set_band_description(1, str(self.name))
            if "units" in self.notes:
                self._dataset.update_tags(1, units=self.notes["units"])
        except RasterioError as exc:
            self.__exit__(None, None, None)
            raise FormatError(
                f"{self.path.name}: GeoTIFF cannot hold this raster: {exc}"
            ) from None
        return self

    def write(self, values: NDArray, *, row: int = 0, column: int = 0) -> None:
        """Write cells (in the stored type), the top left one at ``(row, column)``.

        Raises
        ------
        ValueError
            If the cells do not fit the raster or have another type.
        """
        n, m = values.shape
        ny, nx = self.shape
        if not (0 <= row <= ny - n and 0 <= column <= nx - m):
            raise ValueError(
                f"cells of shape {values.shape} at ({row}, {column}) do not fit a "
                f"raster of {ny} x {nx} cells"
            )
        if values.dtype != self.dtype:
            raise ValueError(f"cells are {values.dtype}; the file holds {self.dtype}")
        self._dataset.write(
            values, 1, window=rasterio.windows.Window(column, row, m, n)
        )

    def __exit__(self, *exc: object) -> None:
        try:
            if self._dataset is not None:
                self._dataset.close()
        finally:
            self._dataset = None
            if self._env is not None:
                self._env.__exit__(None, None, None)
                self._env = None


def _env() -> rasterio.Env:
    return rasterio.Env(GDAL_CACHEMAX=GDAL_CACHE_MB)


def _open_quietly(path: str) -> rasterio.io.DatasetReader:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NotGeoreferencedWarning)
        return rasterio.open(path)


def _read(
    dataset: rasterio.io.DatasetReader,
    source: RasterSource,
    rows: tuple[int, int],
    columns: tuple[int, int],
) -> NDArray[np.float64]:
    (start, stop), (c0, c1) = rows, columns
    first = source.row_off + (source.height - stop if source.flipped else start)
    window = rasterio.windows.Window(source.col_off + c0, first, c1 - c0, stop - start)
    values = dataset.read(1, window=window, out_dtype=np.float64)
    values[dataset.read_masks(1, window=window) == 0] = np.nan
    return values[::-1] if source.flipped else values


def _describe(
    dataset: rasterio.io.DatasetReader,
    given: str,
    box: tuple[float, float, float, float] | None,
) -> RasterSource:
    """Describe band 1 of ``dataset`` and the window ``box`` cuts (as ``_read``)."""
    t = dataset.transform
    if t.b != 0 or t.d != 0:
        raise FormatError(f"{given}: rotated or sheared grids are not supported")
    if t == Affine.identity() and dataset.crs is None:
        raise InputDataError(
            "has no georeferencing (no geotransform and no CRS)", path=given
        )
    window = rasterio.windows.Window(0, 0, dataset.width, dataset.height)
    if box is not None:
        window = _window(dataset, box, given)
    col_off, row_off = int(window.col_off), int(window.row_off)
    height, width = int(window.height), int(window.width)
    flipped = t.e > 0
    top = t.f + t.e * (row_off + (height if flipped else 0))
    transform = (t.a, 0.0, t.c + t.a * col_off, 0.0, -abs(t.e), top)
    return RasterSource(
        path=dataset.name,
        row_off=row_off,
        col_off=col_off,
        height=height,
        width=width,
        flipped=flipped,
        transform=tuple(float(v) for v in transform),
        crs=_crs_wkt(dataset, given),
        nodata=_nodata(dataset),
        dtype=dataset.dtypes[0],
        units=dataset.units[0] or dataset.tags(1).get("units") or None,
        name=dataset.descriptions[0] or dataset.tags(1).get("NETCDF_VARNAME"),
        source=given,
    )
