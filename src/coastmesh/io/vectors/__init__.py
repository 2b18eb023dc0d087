"""Vector files: shorelines and other layers as :class:`~coastmesh.types.Features`.

=========================  ====================================================
:mod:`.vector`             read and write a vector layer (GeoPackage,
                           shapefile, GeoJSON, FlatGeobuf, ...)
:mod:`.domain_gpkg`        a meshing domain, and other layers, in one GeoPackage
=========================  ====================================================
"""
