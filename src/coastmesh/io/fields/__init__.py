"""Fields: values to size a mesh by, from a raster or from a model's results.

=========================  ====================================================
:mod:`.field_sources`      a model's results (ANUGA, SCHISM, ADCIRC, UGRID,
                           VTU) read as a mesh with values on it
:mod:`.field_values`       a field's values at the nodes of a size grid
=========================  ====================================================
"""
