"""``[mesh_size.channels]``: elements across every channel, on by default.

The width of the water at a point is the diameter of the largest disk in the
water that holds it: in a channel ``w`` wide it is ``w`` right across, and open
boundaries are not walls (:func:`coastmesh.sizing.channel.local_width`). The
size is at most ``width / elements_across``, and at least the field's floor
``h_min``. ``enabled = false`` turns the term off. Channels narrower than two
elements of ``h_min`` are kept (and reported, with a warning) or closed: taken
out of the domain as land before meshing. A global case's grid does not measure
widths: there ``[domain] close`` closes narrow water instead.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from coastmesh.case import schema
from coastmesh.case.schema import Check, key
from coastmesh.case.terms.base import SizeCase, SizeTerm
from coastmesh.sizing.channel import channel_size, over_land
from coastmesh.sizing.combine import Applied, TermSizes
from coastmesh.sizing.grid import Grid
from coastmesh.sizing.narrow import (
    NARROW_CHOICES,
    ChannelReport,
    narrow_channels,
    narrow_places,
    warn_narrow,
)

__all__ = ["ChannelConfig", "Channels"]


@dataclass(frozen=True)
class ChannelConfig:
    """``[mesh_size.channels]``."""

    enabled: bool = key(True, check=schema.boolean, doc="the term at all")
    elements_across: float = key(
        3.0, check=schema.number, doc="elements across the water; at least 1"
    )
    narrow: str = key(
        "keep",
        check=schema.choice(NARROW_CHOICES),
        doc='channels narrower than two elements of `h_min`: `"keep"` them (they '
        "are one element wide: a warning gives their number, area and places, "
        'and `report.json` lists them) or `"close"` them (they become land; the '
        "domain is built again, twice at most; the report counts what closed and "
        "what was left)",
    )

    def _validate(self, c: Check) -> ChannelConfig:
        if not self.elements_across >= 1:
            raise c.error(
                "elements_across", f"= {self.elements_across:g}: must be at least 1"
            )
        return self


class Channels(SizeTerm):
    """The term of ``[mesh_size.channels]``."""

    key = "channels"
    config = ChannelConfig
    many = False
    default = ChannelConfig()
    doc = "elements across every channel, on by default (below)"
    reports = True

    def sizes(self, grid: Grid, case: SizeCase) -> TermSizes | None:
        """At most the width of the water over ``elements_across``; at least the floor.

        Off on a grid that does not measure widths (the sphere: a global case
        closes narrow water with ``[domain] close`` instead).
        """
        ch = case.config.size.channels
        if not ch.enabled:
            return None
        width = grid.widths(
            case.domain, max_width=ch.elements_across * case.config.size.h_max
        )
        if width is None:
            return None
        h_min = case.floor
        term = over_land(
            channel_size(width, elements_across=ch.elements_across, h_min=h_min),
            width > 0,
        )
        _, found = narrow_channels(width, grid.sea, h_min=h_min, cell=grid.cell)
        closed = case.closing.channels
        found_report = ChannelReport(
            elements_across=float(ch.elements_across),
            h_min=float(h_min),
            narrow=ch.narrow,
            limited_km2=0.0,
            narrow_channels=len(found),
            narrow_km2=sum(a for _, _, a, _ in found) / 1e6,
            worst=narrow_places(found, grid.x, grid.y, grid.crs),
            closed=0 if closed is None else closed.narrow_channels,
            closed_km2=0.0 if closed is None else closed.narrow_km2,
            slots=case.closing.slots,
        )
        if found:
            warn_narrow(found_report, after_closing=case.closing.passes)

        def report(applied: Applied) -> ChannelReport:
            limited = grid.km2(grid.sea & (term < applied.before))
            return replace(found_report, limited_km2=limited)

        return TermSizes(
            upper=term,
            report=report,
            history=f"channels ({ch.elements_across:g} across)",
            layers={"width": width},
        )
