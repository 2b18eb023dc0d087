"""Patch a site into an existing mesh: remesh inside a polygon, keep the rest.

================================  ============================================
:func:`patch_mesh`                the whole patch: cut, size, mesh, merge
:class:`Patched`                  the patched mesh, its report, the hole
:class:`PatchReport`              what changed: counts, seam quality, dt
:func:`~.cut.cut_hole`            the elements that meet the polygon, out
:func:`~.hole.hole_domain`        the hole as a domain of the mesh's nodes
================================  ============================================
"""

from __future__ import annotations

from coastmesh.case.patch.patch import Patched, patch_mesh, site_polygon
from coastmesh.case.patch.report import PatchReport

__all__ = ["PatchReport", "Patched", "patch_mesh", "site_polygon"]
