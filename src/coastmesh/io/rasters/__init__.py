"""Raster files: GeoTIFF and NetCDF grids as :class:`xarray.DataArray`.

=========================  ====================================================
:mod:`.raster`             read and write a whole raster
:mod:`.raster_stream`      read and write a window of rows at a time, for grids
                           larger than memory
:mod:`.raster_window`      read only the window that some points need
=========================  ====================================================
"""
