"""``[[mesh_size.fields]]``: sizes from a field, a raster or a model's results.

Each entry takes a field from a ``source`` and maps its value to a size:

* a **raster** (any raster GDAL reads, in any CRS; a NetCDF variable by
  ``variable``), read at the size grid's nodes bilinearly, or ``sample =
  "nearest"`` for classes and codes
  (:meth:`~coastmesh.sizing.grid.Grid.sample`);
* a **mesh file** with results (an ANUGA ``.sww``, a SCHISM ``out2d_*.nc``,
  ADCIRC ``fort.63``/``fort.64``/``maxvel.63``/``maxele.63``, text or NetCDF,
  a UGRID NetCDF, a VTU): a ``variable`` at its nodes (linear in each
  triangle) or on its faces (constant in each), reduced over time by
  ``reduce``, sampled at the size grid's nodes inside the mesh's triangles
  (:func:`coastmesh.sizing.fields.triangles_on_grid`).

The value may be derived (formulas in ``docs/sizes-from-fields.md``):
``variable = "speed"`` is ``sqrt(u^2 + v^2)`` of each record;
``"elevation"`` the free surface; ``"vorticity"`` ``|dv/dx - du/dy|`` of each
record on the source mesh. ``reduce`` takes the records' ``max``, ``min``,
``mean``, ``range`` (max - min: the tidal range of ``"elevation"``) or the
record ``at`` a ``time``; ``gradient = true`` then takes the magnitude of the
reduced field's gradient on the source mesh (per metre).

The value maps to a size by ``mapping`` (``"thresholds"``, ``"ramp"`` or
``"power"``; :class:`coastmesh.sizing.fields.SizeMapping`). Where the mapping
asks for nothing, and outside the source's cover, the term does not apply; a
warning gives the share of the domain's sea the source does not cover (the
size grid's nodes within two cells of its cover take its nearest value: a
first run's coast cuts corners). The sizes are capped at ``h_max`` and graded
at ``rate`` as every term's. Without ``h_min`` they stand below the field's
default floor (the smallest gradation ``h_min``) where the entry applies, and
nowhere else: the mesh elsewhere is the mesh without the term. A given
``h_min`` clamps them, with a warning. Several entries combine by their
minimum; the report (``size_field.fields`` of ``report.json``) gives, for each,
the area where it set the size, the median size there without and with it,
and the elements that takes (the area over that of an equilateral triangle of
the size).

The sizes hold: the entry's sizes are spread by ``1 + ceil(size / (sqrt(3)
cell))`` grid cells (:func:`spread_cells`), so that every node of an element
whose centroid the value reaches gets them, and after meshing the nodes in
its zone are moved (and a few crowded ones taken out) until its elements are
within 10 % of their size where the boundary allows (``report.json``
``conform``; :func:`~coastmesh.meshing.cleanup.conform.conform_sizes`, how in
``docs/sizes-from-fields.md``). ``[cleanup] enabled = false`` turns that off.

An entry without ``source`` takes the result of a first run given by
``coastmesh run CASE --refine-from RESULT``; without it the entry is off (the
first pass of the refinement loop).
"""

from __future__ import annotations

import math
import os
import warnings
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from coastmesh.case import schema
from coastmesh.case.schema import Check, key
from coastmesh.case.terms.base import SizeCase, SizeTerm
from coastmesh.depth import READINGS
from coastmesh.errors import CoastmeshWarning, ConfigError
from coastmesh.sizing.combine import Applied, TermSizes
from coastmesh.sizing.fields import MAPPINGS, SizeMapping
from coastmesh.sizing.grid import Grid
from coastmesh.types import Report

if TYPE_CHECKING:
    from coastmesh.io.fields.field_values import Sampled

__all__ = ["FieldConfig", "Fields", "FieldsReport", "spread_cells", "with_result"]

#: The reductions of a time series.
REDUCTIONS = ("max", "min", "mean", "range", "at")


def _numbers(value: object, where: str) -> tuple[float, ...]:
    """Convert a non-empty list of numbers (``-inf`` and ``inf`` allowed)."""
    if isinstance(value, int | float) and not isinstance(value, bool):
        value = [value]
    if isinstance(value, str) or not isinstance(value, list | tuple) or not value:
        raise ConfigError(f"{where} = {value!r}: expected a list of numbers")
    return tuple(schema.number(v, f"{where}[{k}]") for k, v in enumerate(value))


def _lengths(value: object, where: str) -> tuple[float, ...]:
    """Convert a non-empty list of lengths > 0 (metres, or strings with a unit)."""
    if isinstance(value, int | float | str) and not isinstance(value, bool):
        value = [value]
    if not isinstance(value, list | tuple) or not value:
        raise ConfigError(f"{where} = {value!r}: expected a list of sizes")
    return tuple(schema.length()(v, f"{where}[{k}]") for k, v in enumerate(value))


@dataclass(frozen=True)
class FieldConfig:
    """One ``[[mesh_size.fields]]`` entry."""

    values: tuple[float, ...] = key(
        check=_numbers,
        doc="the field's values the mapping starts from: the thresholds "
        "(increasing), the ramp's two ends, or the power law's reference value",
    )
    sizes: tuple[float, ...] = key(
        check=_lengths,
        read=_lengths,
        doc='one size per value, metres or with a unit (`"50 m"`); `thresholds`: '
        "all decreasing or all increasing",
    )
    source: Path | None = key(
        None,
        check=schema.path,
        path=True,
        default_doc="the `--refine-from` result",
        doc="a raster (any GDAL raster, any CRS) or a mesh file with results "
        "(ANUGA `.sww`, SCHISM `out2d_*.nc`, ADCIRC `fort.63`/`fort.64`/"
        "`maxvel.63`/`maxele.63` text or NetCDF, UGRID `.nc`, `.vtu`)",
    )
    variable: str | None = key(
        None,
        check=schema.string,
        default_doc="a raster's only band",
        doc='the variable: a name in the file, or `"speed"`, `"elevation"`, '
        '`"vorticity"` (derived; a mesh source needs one)',
    )
    reduce: str | None = key(
        None,
        check=schema.choice(REDUCTIONS),
        default_doc="none (a time series needs one)",
        doc="over a time series: `max`, `min`, `mean`, `range` (max - min) or "
        "`at` (the record nearest `time`)",
    )
    time: float | None = key(
        None,
        check=schema.duration,
        unit="duration",
        doc='with `reduce = "at"`: the time, from the file\'s time origin',
    )
    gradient: bool = key(
        False,
        check=schema.boolean,
        doc="map the magnitude of the (reduced) field's gradient on the source "
        "mesh, per metre, not the field",
    )
    sample: str = key(
        "bilinear",
        check=schema.choice(READINGS),
        doc='how a raster is read at the size grid\'s nodes: `"bilinear"`, or '
        '`"nearest"` (the value of the cell a node is in: a raster of classes or '
        "codes, such as a habitat map); a mesh source is read in its triangles",
    )
    mapping: str = key(
        "thresholds",
        check=schema.choice(MAPPINGS),
        doc='value to size: `"thresholds"` (a size from each value up), '
        '`"ramp"` (linear between two values) or `"power"` '
        "(`h = sizes[0] (v / values[0])^exponent`)",
    )
    exponent: float = key(
        -1.0, check=schema.number, doc='the power law\'s exponent (`mapping = "power"`)'
    )
    mesh: Path | None = key(
        None,
        check=schema.path,
        path=True,
        doc="the grid (fort.14) of an ADCIRC text output, which has no nodes",
    )
    crs: str | None = key(
        None,
        check=schema.crs,
        default_doc="the file's own",
        doc="the source's CRS, where the file stores none (SCHISM, VTU)",
    )
    name: str | None = key(
        None,
        check=schema.string,
        default_doc="the source's file name",
        doc="the entry's name in the report",
    )

    def _validate(self, c: Check) -> FieldConfig:
        self.size_mapping(c.key("mapping"))
        if (self.reduce == "at") != (self.time is not None):
            raise c.error("time", 'give time with reduce = "at", and only then')
        if self.sample != "bilinear" and self.source is not None:
            from coastmesh.io.fields.field_values import is_mesh_source

            if is_mesh_source(self.source):
                raise c.error(
                    "sample",
                    f"= {self.sample!r} reads a raster; {self.source} is a mesh "
                    "file, read in its triangles: leave sample out",
                )
        return self

    def size_mapping(self, where: str = "mesh_size.fields") -> SizeMapping:
        """Return the entry's :class:`~coastmesh.sizing.fields.SizeMapping`."""
        return SizeMapping(
            self.mapping,
            self.values,
            self.sizes,
            exponent=self.exponent,
            where=where.removesuffix(".mapping"),
        )

    @property
    def label(self) -> str:
        """The entry's name in reports: ``name``, else the source's file name."""
        if self.name:
            return self.name
        return self.source.name if self.source is not None else "--refine-from"


@dataclass(frozen=True, slots=True)
class FieldReport(Report):
    """What one ``[[mesh_size.fields]]`` entry did to the size field.

    Attributes
    ----------
    name : str
        The entry's name (its source's file name by default).
    source : str
        The source file.
    variable : str
        What was mapped (``"speed max"``, ``"elevation range gradient"``).
    value_min, value_max : float or None
        The field's range over the domain's sea nodes it covers.
    uncovered : float
        The share of the domain's sea nodes outside the source (0 to 1).
    km2 : float
        The sea area where the entry set the size (smaller than the other terms').
    size_before_m, size_after_m : float or None
        The median size there without the entry, and with it.
    elements_before, elements_after : int
        Triangles the field asks for there, without and with the entry
        (the area over that of an equilateral triangle of the size).
    """

    name: str
    source: str
    variable: str
    value_min: float | None
    value_max: float | None
    uncovered: float
    km2: float
    size_before_m: float | None
    size_after_m: float | None
    elements_before: int
    elements_after: int

    def summary(self) -> str:
        """Return one line."""
        if not self.km2:
            return f"{self.name}: set no size"
        return (
            f"{self.name}: {self.km2:,.1f} km2 at {self.size_before_m:.0f} -> "
            f"{self.size_after_m:.0f} m, ~{self.elements_before:,} -> "
            f"~{self.elements_after:,} elements"
        )


@dataclass(frozen=True, slots=True)
class FieldsReport(Report):
    """The reports of the ``[[mesh_size.fields]]`` entries, in order."""

    entries: tuple[FieldReport, ...]

    def summary(self) -> str:
        """Return one line: each entry's."""
        return "fields: " + "; ".join(e.summary() for e in self.entries)


class Fields(SizeTerm[tuple[FieldConfig, ...]]):
    """The term of ``[[mesh_size.fields]]``."""

    key = "fields"
    config = FieldConfig
    many = True
    default = ()
    reports = True
    doc = "sizes from a field: a raster or a model's results (below)"

    def smallest(self, settings: tuple[FieldConfig, ...]) -> float | None:
        """Return the smallest size the entries with a source ask for.

        The size grid is no coarser. It is not the field's floor: where an entry
        applies, its sizes lower the floor there (``h_min`` unset) and nowhere
        else, so the mesh elsewhere is the mesh without the term.
        """
        return min((min(f.sizes) for f in settings if f.source), default=None)

    def sizes(self, grid: Grid, case: SizeCase) -> TermSizes | None:
        """Return the entries' sizes, combined by minimum; None without entries."""
        from coastmesh.io.fields.field_values import sample_field

        entries = self.settings(case)
        for k, entry in enumerate(entries):
            if entry.source is None:
                warnings.warn(
                    f"mesh_size.fields[{k}] ({entry.label}) has no source: it is off "
                    "in this run; `coastmesh run CASE --refine-from RESULT` gives it "
                    "a first run's results",
                    CoastmeshWarning,
                    stacklevel=2,
                )
        if not any(f.source is not None for f in entries):
            return None
        upper = np.full(grid.shape, np.inf)
        sampled = []
        for k, entry in enumerate(entries):
            if entry.source is None:
                continue
            where = f"mesh_size.fields[{k}]"
            field = sample_field(
                grid,
                entry.source,
                variable=entry.variable,
                reduce=entry.reduce,
                time=entry.time,
                gradient=entry.gradient,
                sample=entry.sample,
                mesh=entry.mesh,
                crs=entry.crs,
                where=where,
            )
            # spread: Gmsh's bilinear reading of the grid then gives the mapping's
            # size everywhere the value is reached, and at every node of an
            # element whose centroid it reaches, not only at the grid's nodes
            size = grid.neighbour_min(
                entry.size_mapping(where).sizes_of(field.values),
                spread_cells(
                    min(max(entry.sizes), case.config.size.h_max), grid.cell_m
                ),
            )
            if grid.domain is not None and grid.sea.any():
                size = grid.over_land(size, grid.sea)
            sampled.append((entry, field, size))
            np.minimum(upper, size, out=upper)
        floor = None
        if case.config.size.h_min is None:
            floor = np.where(np.isfinite(upper), upper, np.nan)
        elif np.nanmin(upper) < case.floor:
            warnings.warn(
                f"mesh_size.fields: sizes down to {float(np.min(upper)):g} m are "
                f"asked for, below mesh_size.h_min = {case.floor:g} m; they are "
                "clamped to h_min (leave h_min out to let them stand)",
                CoastmeshWarning,
                stacklevel=2,
            )
        return TermSizes(
            upper=upper,
            floor=floor,
            conform=np.isfinite(upper),
            history=f"{len(sampled)} fields",
            report=lambda applied: _report(grid, sampled, applied, case.floor),
        )


def spread_cells(size: float, cell: float) -> int:
    """Return how many cells a field's sizes are spread by.

    ``1 + ceil(size / (sqrt(3) cell))``: one cell, so that Gmsh's bilinear
    reading of the grid holds the size in every cell the value reaches; and
    the circumradius of an equilateral triangle of the size,
    ``size / sqrt(3)``, so that every node of an element whose centroid the
    value reaches has it too.

    Examples
    --------
    >>> spread_cells(50.0, 50.0), spread_cells(400.0, 50.0), spread_cells(10.0, 50.0)
    (2, 6, 2)
    """
    return 1 + math.ceil(size / (math.sqrt(3.0) * cell))


def with_result(
    fields: tuple[FieldConfig, ...], result: Path
) -> tuple[FieldConfig, ...]:
    """Give ``result`` to every entry without a ``source`` (``--refine-from``).

    Raises
    ------
    ConfigError
        If every entry has a source (or there is none): nothing would take it.
    """
    if not any(f.source is None for f in fields):
        raise ConfigError(
            f"--refine-from {os.fspath(result)}: the case has no [[mesh_size.fields]] "
            "entry without a source to take it; add one (its variable, reduce, "
            "values and sizes) and leave out source"
        )
    return tuple(replace(f, source=result) if f.source is None else f for f in fields)


def _report(
    grid: Grid,
    sampled: list[tuple[FieldConfig, Sampled, NDArray[np.float64]]],
    applied: Applied,
    floor: float,
) -> FieldsReport:
    """Measure what each entry did, where it set the size."""
    sea = grid.sea
    areas = grid.areas  # m2 per node; None: a cell each
    node_m2 = np.full(grid.shape, grid.cell**2) if areas is None else areas
    entries = []
    for entry, field, size in sampled:
        covered = field.inside & sea
        value = field.values[covered & np.isfinite(field.values)]
        bound = sea & (size < applied.before) & (size <= applied.floored)
        before = np.maximum(applied.before[bound], floor)
        after = applied.floored[bound]
        entries.append(
            FieldReport(
                name=entry.label,
                source=os.fspath(entry.source or ""),
                variable=field.what,
                value_min=float(value.min()) if value.size else None,
                value_max=float(value.max()) if value.size else None,
                uncovered=1.0 - float(covered.sum()) / max(int(sea.sum()), 1),
                km2=grid.km2(bound),
                size_before_m=float(np.median(before)) if before.size else None,
                size_after_m=float(np.median(after)) if after.size else None,
                elements_before=_triangles(before, node_m2[bound]),
                elements_after=_triangles(after, node_m2[bound]),
            )
        )
    return FieldsReport(tuple(entries))


def _triangles(size: NDArray[np.float64], area_m2: NDArray[np.float64]) -> int:
    """Equilateral triangles of ``size`` that fill each node's area (m2)."""
    if not size.size:
        return 0
    return round(float(np.sum(area_m2 / (math.sqrt(3) / 4 * size**2))))
