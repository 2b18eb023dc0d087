"""ADCIRC ``fort.14`` and SCHISM ``hgrid.gr3`` grid files, with boundary segments.

Both files hold a title line, ``NE NP``, the nodes ``JN X Y DP``, the elements
``JE 3 NM1 NM2 NM3`` (1-based), then the open (elevation) boundary segments and the
land (normal flow) boundary segments as node lists. The layout follows the ADCIRC
manual (``adcirc/adcirc``: ``docs/technical_reference/input_files/fort14.rst`` and
``parameter_definitions/index.rst``) and the SCHISM manual (``schism-dev/schism``:
``docs/input-output/hgrid.md``, "same as fort.14 of ADCIRC").

Each model has its own rules for the boundary lists, read in its source and docs
and named in :mod:`coastmesh.io.meshes.adcirc._segments` (A1 to A5, S1 to S4):

=========================  ================================  ==========================
                           ``fort.14`` (ADCIRC)              ``hgrid.gr3`` (SCHISM)
=========================  ================================  ==========================
open segment header        ``NVDLL IBTYPEE`` (``IBTYPEE=0``)  ``NVDLL`` only
open boundaries that meet  one segment: no node listed       one segment per id, the
                           twice (A5)                        corner shared (S2)
coast between two open     one segment, ``IBTYPE 0`` (or      one segment, flag ``0``
boundaries                 20), whatever its sets (A4)
island (closed land ring)  one segment, ``IBTYPE 1`` (or     one segment, flag ``1``,
                           21), first node repeated (A3)     first node not repeated
whole ring of one kind     land: first node repeated (A2);   two segments that share
(no other boundary on it)  open: each node once (A5)         their end nodes (S1, S4)
=========================  ================================  ==========================

The boundary ids a segment holds are kept in the comment after its counts
(``: id 10 near; id 5 @301 far``), which both models skip and the readers give
back; :func:`rule_breaks` lists the rules a file from another tool breaks.

A mesh with regions (farms, turbine footprints: ``Mesh.regions``) also gets its
region ids in a file beside the grid, in each model's convention: an ADCIRC
nodal attributes file ``fort.13`` (attribute ``coastmesh_region_id``, one id per
node) beside a ``fort.14``, a SCHISM element property file ``.regions.prop``
(one id per element) beside a ``hgrid.gr3``. The layouts, the rule that gives a
node its id, and their sources are in :mod:`coastmesh.io.meshes.adcirc._regions`.

The text tables are formatted with numpy in blocks (no Python loop per node), so
meshes of millions of triangles write in seconds (:mod:`coastmesh.io.meshes._table`).

===========================  =================================================
:func:`write_fort14`         Mesh -> ``fort.14`` (+ ``fort.13`` with regions)
:func:`write_gr3`            Mesh -> ``hgrid.gr3`` (+ ``.regions.prop``)
:func:`read_fort14_mesh`     ``fort.14`` (+ ``fort.13``) -> Mesh
:func:`read_gr3_mesh`        ``hgrid.gr3`` (+ ``.regions.prop``) -> Mesh
:func:`read_fort14`          ``fort.14`` or ``hgrid.gr3`` -> dict, as written
:func:`read_fort13`          ``fort.13`` -> dict, as written
:func:`node_regions`         each node's region id, as ``fort.13`` holds it
:func:`regions_from_nodes`   each triangle's region id from the nodes' ids
:func:`rule_breaks`          the model rules a file's boundary lists break
===========================  =================================================
"""

from __future__ import annotations

from coastmesh.io.meshes.adcirc._read import (
    read_fort14,
    read_fort14_mesh,
    read_gr3_mesh,
)
from coastmesh.io.meshes.adcirc._regions import (
    node_regions,
    read_fort13,
    regions_from_nodes,
)
from coastmesh.io.meshes.adcirc._rules import RuleBreak, rule_breaks
from coastmesh.io.meshes.adcirc._write import write_fort14, write_gr3

__all__ = [
    "RuleBreak",
    "node_regions",
    "read_fort13",
    "read_fort14",
    "read_fort14_mesh",
    "read_gr3_mesh",
    "regions_from_nodes",
    "rule_breaks",
    "write_fort14",
    "write_gr3",
]
