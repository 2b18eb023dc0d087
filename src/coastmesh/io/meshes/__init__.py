"""Mesh files: one module per format, and the registry that reads and writes them.

=========================  ====================================================
:mod:`._registry`          :func:`~coastmesh.io.read_mesh`,
                           :func:`~coastmesh.io.write_mesh`: the format by name
                           or extension; :mod:`._mesh_format` is one entry and
                           :mod:`._builtin` registers the built-in ones
:mod:`.msh`                Gmsh ``.msh`` 2.2 and 4.1
:mod:`.adcirc`             ADCIRC ``fort.14`` and SCHISM ``hgrid.gr3``, their
                           boundary segments and region files
:mod:`.ugrid`              UGRID netCDF
:mod:`.mike`               DHI MIKE ``.mesh``
:mod:`.telemac`            Telemac SELAFIN and ``.cli``, written
                           (:mod:`.telemac_read` and :mod:`._telemac_cli` read)
:mod:`.vtu`                VTK unstructured grids
:mod:`.mesh_gpkg`          a mesh as a GeoPackage (:mod:`._dateline` cuts a
                           global one at the antimeridian)
:mod:`.model_tests`        ADCIRC and SCHISM smoke-test run folders
:mod:`.sphere`             meshes on the sphere: crossings, the sphere check
=========================  ====================================================

What the formats share: :mod:`._model` (what the writers take from a mesh),
:mod:`._reading` (a Mesh from what a reader read), :mod:`._table` (text tables)
and :mod:`._meshio` (the readers through meshio). Nothing is imported here, so
importing one format does not import the others.
"""
