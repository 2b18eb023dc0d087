"""``[mesh_size.channels]``: elements across every channel, on by default.

The width of the water at a point is the diameter of the largest disk in the
water that holds it (:func:`coastmesh.sizing.channel.local_width`); the size is
at most ``width / elements_across``, and at least the field's floor ``h_min``.
Channels narrower than two elements of ``h_min`` are kept (and reported, with a
warning) or closed: taken out of the domain as land before meshing.
"""

from __future__ import annotations

from dataclasses import dataclass

from coastmesh.case import schema
from coastmesh.case.schema import Check, key
from coastmesh.case.terms.base import SizeTerm
from coastmesh.sizing.terms import NARROW_CHOICES

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
