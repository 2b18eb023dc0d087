"""``[mesh_size]``: the size field, its gradations and bathymetry terms."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from coastmesh.case import schema
from coastmesh.case.config._check import Check, check_part, sequence
from coastmesh.case.config.sources import DepthSourceConfig, check_sources
from coastmesh.sizing.bathymetry import M2_PERIOD
from coastmesh.sizing.gradation import DEFAULT_RATE

__all__ = [
    "BathymetryConfig",
    "ChannelConfig",
    "CourantConfig",
    "GradationConfig",
    "SizeConfig",
]

_UP_DOWN = ("up", "down")
#: ``courant_max`` when neither bound is given (explicit models).
DEFAULT_COURANT_MAX = 0.5


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
    path : path, optional
        One raster GDAL reads; or ``sources``.
    positive : {"up", "down"}
        The raster's sign: ``"up"`` for elevations (GEBCO, ETOPO).
    sources : tuple of DepthSourceConfig
        ``[[mesh_size.bathymetry.sources]]``: several rasters, highest priority
        first; with ``path``, the one source it makes.
    per_wavelength : float, optional
        Elements per tidal wavelength.
    period : float or str
        The tide's period (seconds); default M2.
    per_slope : float, optional
        Elements per ``2 pi d / |grad d|``. At least one of the two terms.
    min_depth : float or str
        Depth floor of both terms (metres).
    """

    path: Path | None = None
    positive: str = "up"
    per_wavelength: float | None = None
    period: float = M2_PERIOD
    per_slope: float | None = None
    min_depth: float = 1.0
    sources: tuple[DepthSourceConfig, ...] = ()

    def _checked(self, c: Check) -> BathymetryConfig:
        if self.per_wavelength is None and self.per_slope is None:
            raise c.error("per_wavelength", "give per_wavelength and/or per_slope")
        positive = c(schema.choice(_UP_DOWN), self.positive, "positive")
        path, sources = check_sources(c, self.path, positive, self.sources)
        return BathymetryConfig(
            path=path,
            positive=positive,
            sources=sources,
            per_wavelength=c.optional(
                schema.positive, self.per_wavelength, "per_wavelength"
            ),
            period=c(schema.duration, self.period, "period"),
            per_slope=c.optional(schema.positive, self.per_slope, "per_slope"),
            min_depth=c(schema.length(), self.min_depth, "min_depth"),
        )


@dataclass(frozen=True, slots=True)
class ChannelConfig:
    """``[mesh_size.channels]``: elements across every channel (on by default).

    Attributes
    ----------
    enabled : bool
        False turns the term off.
    elements_across : float
        Elements across the water; at least 1 (default 3). The size is at most
        the local width of the water over this, and at least ``mesh_size.h_min``.
    narrow : {"keep", "close"}
        Channels narrower than two elements of ``h_min``: ``"keep"`` them
        (reported, with a warning) or ``"close"`` them (taken out of the domain
        as land, and counted in the report).
    """

    enabled: bool = True
    elements_across: float = 3.0
    narrow: str = "keep"

    def _checked(self, c: Check) -> ChannelConfig:
        from coastmesh.sizing.terms import NARROW_CHOICES

        across = c(schema.number, self.elements_across, "elements_across")
        if not across >= 1:
            raise c.error(
                "elements_across", f"= {self.elements_across!r}: must be at least 1"
            )
        return ChannelConfig(
            enabled=c(schema.boolean, self.enabled, "enabled"),
            elements_across=across,
            narrow=c(schema.choice(NARROW_CHOICES), self.narrow, "narrow"),
        )


@dataclass(frozen=True, slots=True)
class CourantConfig:
    """``[mesh_size.courant]``: sizes a model runs at its time step.

    The size is bounded so that ``C = dt (sqrt(g d) + u) / h`` stays between
    ``courant_min`` and ``courant_max``, with ``d`` from the bathymetry
    (``[mesh_size.bathymetry]``, else ``[bathymetry]``).

    Attributes
    ----------
    dt : float or str
        The model's time step (seconds).
    courant_max : float, optional
        Largest Courant number; sizes are raised to meet it. Default 0.5 when
        neither bound is given.
    courant_min : float, optional
        Smallest Courant number; sizes are lowered to meet it.
    velocity : float or str
        The flow speed ``u`` added to the wave speed (m/s); default 1 m/s.
    """

    dt: float
    courant_max: float | None = None
    courant_min: float | None = None
    velocity: float = 1.0

    def _checked(self, c: Check) -> CourantConfig:
        high = c.optional(schema.positive, self.courant_max, "courant_max")
        low = c.optional(schema.positive, self.courant_min, "courant_min")
        if high is None and low is None:
            high = DEFAULT_COURANT_MAX
        if high is not None and low is not None and low >= high:
            raise c.error(
                "courant_min",
                f"= {low:g} is not below courant_max = {high:g}: no Courant number "
                "fits between them",
            )
        return CourantConfig(
            dt=c(schema.duration, self.dt, "dt"),
            courant_max=high,
            courant_min=low,
            velocity=c(schema.speed, self.velocity, "velocity"),
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
        A floor of the whole field (metres). Default: the smallest gradation
        ``h_min`` (the channel term needs a floor).
    cell : float or str, optional
        Cell size of the size grid (metres); default 1/1000 of the extent.
    rate : float or None, default :data:`coastmesh.sizing.DEFAULT_RATE` (0.7)
        Largest size change per unit distance (gradation limit), metres per
        metre; None (``rate = false`` in a case file) for no limit.
    bathymetry : BathymetryConfig, optional
    channels : ChannelConfig
        The channel-width term; on by default.
    courant : CourantConfig, optional
        The Courant term.
    """

    h_max: float
    gradations: tuple[GradationConfig, ...] = ()
    h_min: float | None = None
    cell: float | None = None
    rate: float | None = DEFAULT_RATE
    bathymetry: BathymetryConfig | None = None
    channels: ChannelConfig = ChannelConfig()
    courant: CourantConfig | None = None

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
            rate=_rate(self.rate, c),
            bathymetry=None
            if bathymetry is None
            else bathymetry._checked(c.at("bathymetry")),
            channels=check_part(self.channels, ChannelConfig, c, "channels"),
            courant=None
            if self.courant is None
            else check_part(self.courant, CourantConfig, c, "courant"),
        )


def _rate(value: Any, c: Check) -> float | None:
    """``rate``: a number > 0, or false (None) for no gradation limit."""
    if value is None or value is False:
        return None
    if value is True:
        raise c.error("rate", "= true: give the limit (m per m), or false for none")
    return c(schema.positive, value, "rate")
