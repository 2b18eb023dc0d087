"""``[mesh_size.channels]``: elements across every channel, on by default.

The width of the water at a point is the diameter of the largest disk in the
water that holds it: in a channel ``w`` wide it is ``w`` right across, and open
boundaries are not walls (:func:`coastmesh.sizing.channel.local_width`). The
size is at most ``width / elements_across``, and at least the field's floor
``h_min``. ``enabled = false`` turns the term off. Channels narrower than two
elements of ``h_min`` are closed by default: taken out of the domain as land
before meshing, and reported with their places and areas (``narrow = "keep"``
keeps them one element wide, with a warning). Inside ``[[sites]]`` they are
kept, and meshed with ``max(elements_across, 2)`` elements across, below
``h_min`` if need be.

In a global case, as in a regional one, the term is on by default. It measures the
width on the world grid by great-circle distance, across the antimeridian and
the poles (:func:`coastmesh.sizing.sphere_channel.sphere_width`); land more
than four cells from the water takes no bound. There ``[domain] close`` closes
narrow water before the size field, whatever ``narrow`` says. Water the grid
measures narrower than two elements of ``h_min`` by more than a cell (its
widths err narrow by up to one) is kept, with a warning; on the default world
grid (0.25 deg, 28 km) that is none below ``h_min = 14 km``. With
``narrow = "close"`` the dead-end channels and straits Gmsh makes one element
wide are closed after meshing, as in a regional case.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from coastmesh.case import schema
from coastmesh.case.schema import Check, key
from coastmesh.case.terms.base import SizeCase, SizeTerm, switched_on
from coastmesh.sizing.channel import channel_size
from coastmesh.sizing.combine import Applied, TermSizes
from coastmesh.sizing.grid import Grid
from coastmesh.sizing.narrow import (
    NARROW_CHOICES,
    NARROW_ELEMENTS,
    ChannelReport,
    narrow_places,
    warn_narrow,
)

__all__ = ["ChannelConfig", "Channels"]


@dataclass(frozen=True)
class ChannelConfig:
    """``[mesh_size.channels]``."""

    enabled: bool | None = key(
        None,
        check=schema.boolean,
        default_doc="`true`",
        doc="the term at all",
    )
    elements_across: float = key(
        3.0, check=schema.number, doc="elements across the water; at least 1"
    )
    narrow: str = key(
        "close",
        check=schema.choice(NARROW_CHOICES),
        doc="channels narrower than two elements of `h_min`, outside `[[sites]]`: "
        '`"close"` them (they become land, in two passes at most, the slivers '
        "each cut leaves with it; the dead-end strips and straits Gmsh still "
        "makes one element wide are closed after meshing; a warning and "
        "`report.json` give what closed, with places and areas, and what was "
        'left) or `"keep"` them (they are one element wide: '
        "a warning gives their number, area and places). Inside `[[sites]]` "
        "they are kept, with at least two elements across",
    )

    def _validate(self, c: Check) -> ChannelConfig:
        if not self.elements_across >= 1:
            raise c.error(
                "elements_across", f"= {self.elements_across:g}: must be at least 1"
            )
        return self


class Channels(SizeTerm[ChannelConfig | None]):
    """The term of ``[mesh_size.channels]``."""

    key = "channels"
    config = ChannelConfig
    many = False
    default = ChannelConfig()
    doc = "elements across every channel, on by default (below)"
    on_by_default = True
    reports = True

    def sizes(self, grid: Grid, case: SizeCase) -> TermSizes | None:
        """At most the width of the water over ``elements_across``; at least the floor.

        Off on a grid that does not measure widths, and with ``enabled = false``
        (:func:`~coastmesh.case.terms.base.switched_on`).
        """
        ch = self.settings(case)
        if ch is None or not switched_on(ch.enabled):
            return None
        width = grid.widths(
            case.domain, max_width=ch.elements_across * case.config.size.h_max
        )
        if width is None:
            return None
        h_min = case.floor
        term = grid.over_land(
            channel_size(width, elements_across=ch.elements_across, h_min=h_min),
            width > 0,
        )
        sites = case.sites(grid)
        outside = grid.sea if sites is None else grid.sea & ~sites
        _, found = grid.narrow_channels(width, outside, h_min=h_min)
        floor = None
        if sites is not None:  # channels in sites: two elements across, at least
            narrow = (width > 0) & (width < NARROW_ELEMENTS * h_min)
            inside = sites & grid.sea & narrow
            across = max(ch.elements_across, NARROW_ELEMENTS)
            floor = np.where(inside, width / across, np.nan)
            term = np.where(inside, np.minimum(term, width / across), term)
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
            warn_narrow(
                found_report,
                after_closing=case.closing.passes,
                closed_by=grid.narrow_closed_by,
            )

        def report(applied: Applied) -> ChannelReport:
            limited = grid.km2(grid.sea & (term < applied.before))
            return replace(found_report, limited_km2=limited)

        return TermSizes(
            upper=term,
            floor=floor,
            report=report,
            history=f"channels ({ch.elements_across:g} across)",
            layers={"width": width},
        )
