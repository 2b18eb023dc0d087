"""Whole runs behind the command-line commands: file names and options in, files out.

=================================  ===========================================
:func:`simplify_shoreline_file`    ``coastmesh simplify-shoreline``
:func:`simplify_raster_file`       ``coastmesh simplify-raster``
:func:`convert_mesh`               ``coastmesh convert``
:func:`run_demo`                   ``coastmesh demo``
=================================  ===========================================

``coastmesh run`` is :func:`coastmesh.case.run_case`. Each function checks its
parameters and opens its inputs before computing, and writes all its outputs
atomically, so a failure leaves no output behind. The command line
(:mod:`coastmesh.cli`) only parses options and calls these.
"""

from __future__ import annotations

from coastmesh.commands.convert import ConvertResult, convert_mesh
from coastmesh.commands.demo import DemoStep, run_demo
from coastmesh.commands.simplify_raster import RasterReport, simplify_raster_file
from coastmesh.commands.simplify_shoreline import simplify_shoreline_file

__all__ = [
    "ConvertResult",
    "DemoStep",
    "RasterReport",
    "convert_mesh",
    "run_demo",
    "simplify_raster_file",
    "simplify_shoreline_file",
]
