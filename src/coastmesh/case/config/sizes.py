"""``[mesh_size]``: the size field, its gradations and bathymetry terms."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from coastmesh.case import schema
from coastmesh.case.config._check import Check, sequence
from coastmesh.sizing.bathymetry import M2_PERIOD

__all__ = ["BathymetryConfig", "GradationConfig", "SizeConfig"]

_UP_DOWN = ("up", "down")


@dataclass(frozen=True, slots=True)
class GradationConfig:
    """``[[mesh_size.gradations]]``: the paper's gradation from named lines.

    Attributes
    ----------
    lines : sequence of str
        Shoreline sets and/or open boundaries, by name.
    h_min : float or str
        Size at the lines (metres).
    d_hold : float or str
        Distance over which ``h_min`` holds (metres).
    d_grade : float or str
        Distance over which the size then grows to ``h_max`` (metres).
    """

    lines: tuple[str, ...]
    h_min: float
    d_grade: float
    d_hold: float = 0.0

    def _checked(self, c: Check) -> GradationConfig:
        return GradationConfig(
            lines=c(schema.names, self.lines, "lines"),
            h_min=c(schema.length(), self.h_min, "h_min"),
            d_grade=c(schema.length(), self.d_grade, "d_grade"),
            d_hold=c(schema.length(positive=False), self.d_hold, "d_hold"),
        )


@dataclass(frozen=True, slots=True)
class BathymetryConfig:
    """``[mesh_size.bathymetry]``: size terms from a bathymetry raster.

    Attributes
    ----------
    path : path
        Any raster GDAL reads.
    positive : {"up", "down"}
        The raster's sign: ``"up"`` for elevations (GEBCO, ETOPO).
    per_wavelength : float, optional
        Elements per tidal wavelength.
    period : float or str
        The tide's period (seconds); default M2.
    per_slope : float, optional
        Elements per ``2 pi d / |grad d|``. At least one of the two terms.
    min_depth : float or str
        Depth floor of both terms (metres).
    """

    path: Path
    positive: str = "up"
    per_wavelength: float | None = None
    period: float = M2_PERIOD
    per_slope: float | None = None
    min_depth: float = 1.0

    def _checked(self, c: Check) -> BathymetryConfig:
        if self.per_wavelength is None and self.per_slope is None:
            raise c.error("per_wavelength", "give per_wavelength and/or per_slope")
        return BathymetryConfig(
            path=c(schema.path, self.path, "path"),
            positive=c(schema.choice(_UP_DOWN), self.positive, "positive"),
            per_wavelength=c.optional(
                schema.positive, self.per_wavelength, "per_wavelength"
            ),
            period=c(schema.duration, self.period, "period"),
            per_slope=c.optional(schema.positive, self.per_slope, "per_slope"),
            min_depth=c(schema.length(), self.min_depth, "min_depth"),
        )


@dataclass(frozen=True, slots=True)
class SizeConfig:
    """``[mesh_size]``: the element size field.

    Attributes
    ----------
    h_max : float or str
        The coarsest size (metres).
    gradations : sequence of GradationConfig
    h_min : float or str, optional
        A floor of the whole field (metres).
    cell : float or str, optional
        Cell size of the size grid (metres); default 1/1000 of the extent.
    rate : float, optional
        Largest size change per unit distance (gradation limit).
    bathymetry : BathymetryConfig, optional
    """

    h_max: float
    gradations: tuple[GradationConfig, ...] = ()
    h_min: float | None = None
    cell: float | None = None
    rate: float | None = None
    bathymetry: BathymetryConfig | None = None

    def _checked(self, c: Check) -> SizeConfig:
        h_max = c(schema.length(), self.h_max, "h_max")
        gradations = tuple(
            g._checked(c.at(f"gradations[{k}]"))
            for k, g in enumerate(sequence(self.gradations, c, "gradations"))
        )
        for k, g in enumerate(gradations):
            if g.h_min > h_max:
                raise c.error(
                    f"gradations[{k}].h_min",
                    f"= {g.h_min:g} m is larger than h_max = {h_max:g} m",
                )
        bathymetry = self.bathymetry
        return SizeConfig(
            h_max=h_max,
            gradations=gradations,
            h_min=c.optional(schema.length(), self.h_min, "h_min"),
            cell=c.optional(schema.length(), self.cell, "cell"),
            rate=c.optional(schema.positive, self.rate, "rate"),
            bathymetry=None
            if bathymetry is None
            else bathymetry._checked(c.at("bathymetry")),
        )
