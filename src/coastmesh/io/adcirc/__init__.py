"""ADCIRC ``fort.14`` and SCHISM ``hgrid.gr3`` grid files, with boundary segments.

Both files hold a title line, ``NE NP``, the nodes ``JN X Y DP``, the elements
``JE 3 NM1 NM2 NM3`` (1-based), then the open (elevation) boundary segments and the
land (normal flow) boundary segments as node lists. The layout follows the ADCIRC
manual (``adcirc/adcirc``: ``docs/technical_reference/input_files/fort14.rst`` and
``parameter_definitions/index.rst``) and the SCHISM manual (``schism-dev/schism``:
``docs/input-output/hgrid.md``, "same as fort.14 of ADCIRC").

The two differ only in how boundary segments are listed:

=========================  ================================  ==========================
                           ``fort.14`` (ADCIRC)              ``hgrid.gr3`` (SCHISM)
=========================  ================================  ==========================
open segment header        ``NVDLL IBTYPEE`` (``IBTYPEE=0``)  ``NVDLL`` only
island (closed land ring)  ``IBTYPE 1``, first node repeated  ``1``, first node not
                           at the end                        repeated
whole ring of one id       first node repeated at the end    two segments that share
(no other boundary on it)  (a lake, ``IBTYPE 0``)            their end nodes
=========================  ================================  ==========================

Sources: ADCIRC "General Notes for Normal Flow Boundary Conditions" (islands and
external boundaries that surround the domain "should be closed by repeating the
first node as the last node"); SCHISM ``hgrid.md`` (the last island node "is
different from the first node"; "if you have no open boundary, you can create two
land boundary segments that are linked to each other", and likewise for open).

A mesh with regions (farms, turbine footprints: ``Mesh.regions``) also gets its
region ids in a file beside the grid, in each model's convention: an ADCIRC
nodal attributes file ``fort.13`` (attribute ``coastmesh_region_id``, one id per
node) beside a ``fort.14``, a SCHISM element property file ``.regions.prop``
(one id per element) beside a ``hgrid.gr3``. The layouts, the rule that gives a
node its id, and their sources are in :mod:`coastmesh.io.adcirc._regions`.

The text tables are formatted with numpy in blocks (no Python loop per node), so
meshes of millions of triangles write in seconds (:mod:`coastmesh.io._table`).

===========================  =================================================
:func:`write_fort14`         Mesh -> ``fort.14`` (+ ``fort.13`` with regions)
:func:`write_gr3`            Mesh -> ``hgrid.gr3`` (+ ``.regions.prop``)
:func:`read_fort14_mesh`     ``fort.14`` (+ ``fort.13``) -> Mesh
:func:`read_gr3_mesh`        ``hgrid.gr3`` (+ ``.regions.prop``) -> Mesh
:func:`read_fort14`          ``fort.14`` or ``hgrid.gr3`` -> dict, as written
:func:`read_fort13`          ``fort.13`` -> dict, as written
:func:`node_regions`         each node's region id, as ``fort.13`` holds it
:func:`regions_from_nodes`   each triangle's region id from the nodes' ids
===========================  =================================================
"""

from __future__ import annotations

from coastmesh.io.adcirc._read import read_fort14, read_fort14_mesh, read_gr3_mesh
from coastmesh.io.adcirc._regions import node_regions, read_fort13, regions_from_nodes
from coastmesh.io.adcirc._write import write_fort14, write_gr3

__all__ = [
    "node_regions",
    "read_fort13",
    "read_fort14",
    "read_fort14_mesh",
    "read_gr3_mesh",
    "regions_from_nodes",
    "write_fort14",
    "write_gr3",
]
