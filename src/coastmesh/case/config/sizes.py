"""``[mesh_size]``: the element size field, with a key per size term.

:class:`SizeConfig` has the keys of the field itself (``h_max``, ``h_min``,
``cell``, ``rate``), then one key per size term of
:data:`coastmesh.case.terms.TERMS`, holding the term's config (its table, or
its array of tables). It is made from that list, so a new term needs no change
here.
"""

from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING, Any

from coastmesh.case import schema
from coastmesh.case.schema import Check, key
from coastmesh.case.terms import TERMS, SizeTerm
from coastmesh.errors import ConfigError
from coastmesh.sizing.gradation import DEFAULT_RATE

if TYPE_CHECKING:
    from coastmesh.case.terms import (
        BathymetryConfig,
        ChannelConfig,
        CourantConfig,
        GradationConfig,
    )

__all__ = ["SizeConfig", "floor", "terms_smallest"]


def _rate(value: object, key: str) -> float | None:
    """``rate``: a number > 0, or false (None) for no gradation limit."""
    if value is None or value is False:
        return None
    if value is True:
        raise ConfigError(f"{key} = true: give the limit (m per m), or false for none")
    return schema.positive(value, key)


_FIELD_KEYS: list[tuple[str, Any, Any]] = [
    (
        "h_max",
        float,
        key(check=schema.length(), unit="length", doc="the largest element size"),
    ),
    (
        "h_min",
        float | None,
        key(
            None,
            check=schema.length(),
            unit="length",
            default_doc="the smallest gradation `h_min`; without gradations, `h_max`",
            doc="a floor for the whole field (the channel term never goes below it)",
        ),
    ),
    (
        "cell",
        float | None,
        key(
            None,
            check=schema.length(),
            unit="length",
            default_doc="`max(extent / 1000, smallest h_min)`",
            doc="the spacing of the size grid",
        ),
    ),
    (
        "rate",
        float | None,
        key(
            DEFAULT_RATE,
            check=_rate,
            read=_rate,
            dump=lambda v: False if v is None else v,
            doc="gradation limit: the size grows by at most `rate` metres per metre; "
            "`false` for none. Steeper grading makes bad triangles: the paper's "
            "gradations (1.4 m per m) left 1 % of the NW-shelf triangles under 27.6 "
            "deg; at 0.7 the 1st percentile is 34-37 deg",
        ),
    ),
]


def _term_key(term: SizeTerm[Any]) -> tuple[str, Any, Any]:
    kind = tuple[term.config, ...] if term.many else term.config | None  # type: ignore[name-defined]
    return (
        term.key,
        kind,
        key(term.default, part=term.config, many=term.many, doc=term.doc),
    )


def _validate(self: Any, c: Check) -> Any:
    """Every gradation's ``h_min`` is at most ``h_max``."""
    for k, g in enumerate(getattr(self, "gradations", ())):
        if g.h_min > self.h_max:
            raise c.error(
                f"gradations[{k}].h_min",
                f"= {g.h_min:g} m is larger than h_max = {self.h_max:g} m",
            )
    return self


if TYPE_CHECKING:

    @dataclasses.dataclass(frozen=True)
    class SizeConfig:
        """What type checkers see of the class made below, from :data:`TERMS`.

        One field per key of ``_FIELD_KEYS`` and per term, in order
        (``tests/case/test_config_terms.py`` checks the two agree).
        """

        h_max: float
        h_min: float | None = None
        cell: float | None = None
        rate: float | None = DEFAULT_RATE
        gradations: tuple[GradationConfig, ...] = ()
        bathymetry: BathymetryConfig | None = None
        channels: ChannelConfig | None = dataclasses.field(
            default_factory=ChannelConfig
        )
        courant: CourantConfig | None = dataclasses.field(default_factory=CourantConfig)

        def __getattr__(self, name: str) -> Any:
            """Any other term's config: a new term needs no line here."""

else:
    SizeConfig = dataclasses.make_dataclass(
        "SizeConfig",
        _FIELD_KEYS + [_term_key(term) for term in TERMS],
        frozen=True,
        namespace={"_validate": _validate},
    )
    SizeConfig.__module__ = __name__
SizeConfig.__doc__ = """``[mesh_size]``: the element size field.

Attributes
----------
h_max : float or str
    The coarsest size (metres).
h_min : float or str, optional
    A floor of the whole field (metres); default the smallest gradation ``h_min``
    (:func:`floor`).
cell : float or str, optional
    Cell size of the size grid (metres); default 1/1000 of the extent.
rate : float or None, default :data:`coastmesh.sizing.DEFAULT_RATE` (0.7)
    Largest size change per unit distance, metres per metre; None (``rate =
    false`` in a case file) for no limit.
gradations, bathymetry, channels, courant, ...
    One per size term of :data:`coastmesh.case.terms.TERMS`: its config.
"""


def terms_smallest(size: Any, *, floors: bool = False) -> float | None:
    """Return the smallest size the terms ask for (:meth:`SizeTerm.smallest`).

    The gradations' smallest ``h_min`` and the fields' smallest size; with
    ``floors``, only the terms whose smallest size is a default floor (the
    gradations'). None if no term asks for a size of its own.
    """
    given = [
        term.smallest(getattr(size, term.key))
        for term in TERMS
        if term.floors or not floors
    ]
    return min((g for g in given if g is not None), default=None)


def floor(size: Any) -> float:
    """Return the size field's floor: ``h_min``, else the smallest gradation's.

    The smallest size of the terms that set the default floor (the
    gradations', :func:`terms_smallest` with ``floors``). Without any,
    ``h_max``: nothing is finer than the field's ceiling.

    Examples
    --------
    >>> from coastmesh.case.terms import GradationConfig
    >>> size = SizeConfig(h_max=5000.0, gradations=[
    ...     GradationConfig(("coast",), h_min=200.0, d_grade=1e4)])
    >>> floor(size), floor(SizeConfig(h_max=5000.0, h_min=100.0)), floor(
    ...     SizeConfig(h_max=5000.0))
    (200.0, 100.0, 5000.0)
    """
    if size.h_min:
        return float(size.h_min)
    smallest = terms_smallest(size, floors=True)
    return float(size.h_max) if smallest is None else smallest
