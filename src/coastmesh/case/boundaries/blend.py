"""``kind = "blend"``: the paper's blended loxodromes.

``P(s) = (1 - s) L1(s) + s L2(1 - s)``, given by ``first`` and ``second``, each an
inline table with the loxodrome keys; ``P`` runs from the start of ``first`` to
the start of ``second`` (:func:`coastmesh.geometry.blend_loxodromes`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from numpy.typing import NDArray

from coastmesh.case.boundaries.base import BoundaryConfig
from coastmesh.case.boundaries.loxodrome import LoxodromeConfig
from coastmesh.case.schema import key
from coastmesh.geometry import blend_loxodromes

__all__ = ["BlendBoundary"]


@dataclass(frozen=True)
class BlendBoundary(BoundaryConfig):
    """``kind = "blend"``: two loxodromes blended into one curve."""

    kind: ClassVar[str] = "blend"

    first: LoxodromeConfig = key(
        part=LoxodromeConfig, doc="the first loxodrome: an inline table", kw_only=True
    )
    second: LoxodromeConfig = key(
        part=LoxodromeConfig, doc="the second loxodrome", kw_only=True
    )

    def lonlat(self, spacing: float) -> NDArray[np.float64]:
        """Sample the blend every ``spacing`` metres at most."""
        return blend_loxodromes(
            self.first.loxodrome, self.second.loxodrome, spacing=spacing
        )
