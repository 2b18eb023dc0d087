"""Figures, drawn with matplotlib, which is imported only when a plot is made.

=================================  ============================================
:func:`shoreline_figure`           a shoreline over its PCA approximation
:func:`raster_figure`              a raster, its approximation, the difference
:func:`plot_shoreline_overlay`     the same on one Axes
:func:`plot_raster_comparison`     the same on three Axes
:func:`domain_figure`              a domain, boundary segments coloured by id
:func:`mesh_figure`                a mesh, boundary edges coloured by id
:func:`mercator_figure`            a mesh in Mercator, whole and a detail
:func:`parts_figure`               the cuts into parts, each part's cost
:func:`size_figure`                a size field on a logarithmic scale
:func:`channel_figure`             the width of the water, narrow channels
:func:`quality_figure`             histograms of angles, ratios, edge sizes
:func:`depth_figure`               depth at the nodes
:func:`depth_source_figure`        which bathymetry source each node took
:func:`depth_rule_figure`          what each node's depth is (raster, wet, nearest)
:func:`time_step_figure`           stable time step and Courant number per element
:func:`patch_figure`               a mesh before and after a patch
:func:`save_figure`                save a figure atomically
=================================  ============================================

The ``plot_*`` functions draw on an Axes (a new pyplot one when ``ax`` is None,
on the Agg backend when there is no display) and return it; the ``*_figure``
functions build a whole :class:`matplotlib.figure.Figure` without pyplot, for
:func:`save_figure`. :mod:`coastmesh.plot.base` has the helpers they share
(axes in longitude and latitude, relief colours, extents).
"""

from __future__ import annotations

from coastmesh.plot.base import save_figure
from coastmesh.plot.globe import globe_figure
from coastmesh.plot.mesh import (
    channel_figure,
    domain_figure,
    mercator_figure,
    mesh_figure,
    size_figure,
)
from coastmesh.plot.parts import parts_figure
from coastmesh.plot.patch import patch_figure
from coastmesh.plot.pca import (
    plot_raster_comparison,
    plot_shoreline_overlay,
    raster_figure,
    shoreline_figure,
)
from coastmesh.plot.quality import (
    depth_figure,
    depth_rule_figure,
    depth_source_figure,
    quality_figure,
    time_step_figure,
)
from coastmesh.plot.site import site_figure

__all__ = [
    "channel_figure",
    "depth_figure",
    "depth_rule_figure",
    "depth_source_figure",
    "domain_figure",
    "globe_figure",
    "mercator_figure",
    "mesh_figure",
    "parts_figure",
    "patch_figure",
    "plot_raster_comparison",
    "plot_shoreline_overlay",
    "quality_figure",
    "raster_figure",
    "save_figure",
    "shoreline_figure",
    "site_figure",
    "size_figure",
    "time_step_figure",
]
