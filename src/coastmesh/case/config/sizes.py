"""``[mesh_size]``: the element size field, and the registry of the size terms.

:class:`SizeConfig` has the keys of the field itself (``h_max``, ``h_min``,
``cell``, ``rate``), then one key per size term, each declared by
:func:`term_key`: that line is the term's whole registration. :data:`TERMS`
lists the terms so declared, in order.
"""

from __future__ import annotations

import dataclasses
from typing import TypeVar, cast

from coastmesh.case import schema
from coastmesh.case.schema import Check, key
from coastmesh.case.terms import (
    AnyTerm,
    Bathymetry,
    BathymetryConfig,
    ChannelConfig,
    Channels,
    Courant,
    CourantConfig,
    FieldConfig,
    Fields,
    GradationConfig,
    Gradations,
    SizeTerm,
)
from coastmesh.errors import ConfigError
from coastmesh.sizing.gradation import DEFAULT_RATE

__all__ = ["TERMS", "SizeConfig", "floor", "term_key", "terms_of", "terms_smallest"]

_Settings = TypeVar("_Settings")


def _rate(value: object, key: str) -> float | None:
    """``rate``: a number > 0, or false (None) for no gradation limit."""
    if value is None or value is False:
        return None
    if value is True:
        raise ConfigError(f"{key} = true: give the limit (m per m), or false for none")
    return schema.positive(value, key)


def _dump_rate(value: object) -> object:
    """``rate`` in a case file: false for None (no limit)."""
    return False if value is None else value


def term_key(term: SizeTerm[_Settings]) -> _Settings:
    """Declare a size term's key of ``[mesh_size]``: the term's registry entry.

    ``name: Settings = term_key(Term())`` in :class:`SizeConfig` is the whole
    registration of a term: its key (the field's name, which must be the term's
    :attr:`~coastmesh.case.terms.SizeTerm.key`), its config type (the field's
    annotation, which a type checker holds to the term's settings) and its place
    in the order the terms' sizes are applied (the fields' order).
    """
    made = key(term.default, part=term.config, many=term.many, doc=term.doc)
    return cast(
        _Settings,  # as dataclasses.field: the field's type, whatever it is
        dataclasses.field(
            default=made.default,
            default_factory=made.default_factory,
            metadata={**made.metadata, "term": term},
        ),
    )


@dataclasses.dataclass(frozen=True)
class SizeConfig:
    """``[mesh_size]``: the element size field, and the size terms' registry.

    Attributes
    ----------
    h_max : float or str
        The coarsest size (metres).
    h_min : float or str, optional
        A floor of the whole field (metres); default the smallest gradation
        ``h_min`` (:func:`floor`).
    cell : float or str, optional
        Cell size of the size grid (metres); default 1/1000 of the extent.
    rate : float or None, default :data:`coastmesh.sizing.DEFAULT_RATE` (0.7)
        Largest size change per unit distance, metres per metre; None (``rate =
        false`` in a case file) for no limit.
    gradations, bathymetry, channels, courant, fields
        One per size term (:func:`term_key`), in the order their sizes are
        applied: the term's config (None: off), or its tuple of configs.
    """

    h_max: float = key(
        check=schema.length(), unit="length", doc="the largest element size"
    )
    h_min: float | None = key(
        None,
        check=schema.length(),
        unit="length",
        default_doc="the smallest gradation `h_min`; without gradations, `h_max`",
        doc="a floor for the whole field (the channel term never goes below it)",
    )
    cell: float | None = key(
        None,
        check=schema.length(),
        unit="length",
        default_doc="`max(extent / 1000, smallest h_min)`",
        doc="the spacing of the size grid",
    )
    rate: float | None = key(
        DEFAULT_RATE,
        check=_rate,
        read=_rate,
        dump=_dump_rate,
        doc="gradation limit: the size grows by at most `rate` metres per metre; "
        "`false` for none. Steeper grading makes bad triangles: the paper's "
        "gradations (1.4 m per m) left 1 % of the NW-shelf triangles under 27.6 "
        "deg; at 0.7 the 1st percentile is 34-37 deg",
    )
    # The size terms, in the order their sizes are applied: a new term is its
    # module in coastmesh.case.terms and its line here, typed by its settings.
    gradations: tuple[GradationConfig, ...] = term_key(Gradations())
    bathymetry: BathymetryConfig | None = term_key(Bathymetry())
    channels: ChannelConfig | None = term_key(Channels())
    courant: CourantConfig | None = term_key(Courant())
    fields: tuple[FieldConfig, ...] = term_key(Fields())

    def _validate(self, c: Check) -> SizeConfig:
        """Every gradation's ``h_min`` is at most ``h_max``."""
        for k, g in enumerate(self.gradations):
            if g.h_min > self.h_max:
                raise c.error(
                    f"gradations[{k}].h_min",
                    f"= {g.h_min:g} m is larger than h_max = {self.h_max:g} m",
                )
        return self


def terms_of(size: SizeConfig | type[SizeConfig]) -> tuple[AnyTerm, ...]:
    """Return the size terms of a ``[mesh_size]`` config (or its class), in order.

    Its :func:`term_key` fields; a subclass of :class:`SizeConfig` with more of
    them adds terms (a term kept outside the package, through the Python API).

    Raises
    ------
    TypeError
        A term registered under a name other than its key, or one that reads
        (:attr:`~coastmesh.case.terms.SizeTerm.reads`) a term not before it.
    """
    kind = size if isinstance(size, type) else type(size)
    terms: list[AnyTerm] = []
    for f in dataclasses.fields(kind):
        term = f.metadata.get("term")
        if term is None:
            continue
        if f.name != term.key:
            raise TypeError(
                f"{kind.__name__}.{f.name} registers {type(term).__name__}, "
                f"whose key is {term.key!r}: name the field as the term's key"
            )
        unknown = set(term.reads) - {t.key for t in terms}
        if unknown:
            raise TypeError(
                f"size term {term.key!r} reads {sorted(unknown)}: a term reads "
                "only the fields of terms registered before it"
            )
        terms.append(term)
    return tuple(terms)


#: The size terms of ``[mesh_size]``, in the order their sizes are applied.
TERMS: tuple[AnyTerm, ...] = terms_of(SizeConfig)


def terms_smallest(size: SizeConfig, *, floors: bool = False) -> float | None:
    """Return the smallest size the terms ask for (:meth:`SizeTerm.smallest`).

    The gradations' smallest ``h_min`` and the fields' smallest size; with
    ``floors``, only the terms whose smallest size is a default floor (the
    gradations'). None if no term asks for a size of its own.
    """
    given = [
        term.smallest(term.of(size))
        for term in terms_of(size)
        if term.floors or not floors
    ]
    return min((g for g in given if g is not None), default=None)


def floor(size: SizeConfig) -> float:
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
