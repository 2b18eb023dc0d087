"""The kinds of case (``[domain] kind``) and what each allows in a case file.

A case file is checked before its run has a strategy
(:mod:`coastmesh.case.pipeline.strategy`), so the rules of a case file that
depend on the kind of case live here: one :class:`DomainKind` per kind, in
:data:`DOMAIN_KINDS`. The reader, the checks and the dumper ask
:func:`domain_kind` what the case's kind allows, and never compare its name.
A new kind of case is an entry here and its strategy in
:data:`coastmesh.case.pipeline.STRATEGIES`.

Examples
--------
>>> kind = domain_kind("global")
>>> kind.boundaries, kind.refuses_sites is None
('cuts', False)
>>> domain_kind("regional").refuses_model_tests is None
True
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["DEFAULT_KIND", "DOMAIN_KINDS", "DomainKind", "domain_kind"]


@dataclass(frozen=True)
class DomainKind:
    """A kind of case, as its case file sees it: a row of :data:`DOMAIN_KINDS`.

    Attributes
    ----------
    name : str
        Its ``[domain] kind``.
    boundaries : str
        The table of its open boundaries (``[[cuts]]`` in a global case, with
        the keys of ``[[open_boundaries]]``); another kind's table is refused.
    keys : tuple of str
        The ``[domain]`` keys a dump writes for this kind alone (left out of
        the other kinds' dumps).
    refuses_sites : str or None
        Why its case takes no farms, turbines, wakes, lines or structures (the
        error's text); None: it takes them.
    refuses_model_tests : str or None
        Why its case takes no ``[output] model_test`` (the error's text);
        None: it does, with depths and open boundaries.
    other_boundaries : str or None
        What a case of this kind is told when it gives another kind's table of
        open boundaries, after the table and the names in it; None: that the
        table is for the other kind.
    """

    name: str
    boundaries: str = "open_boundaries"
    keys: tuple[str, ...] = ()
    refuses_sites: str | None = None
    refuses_model_tests: str | None = None
    other_boundaries: str | None = None

    def refuse_boundaries(self, table: str, given: object) -> str:
        """Return the error for another kind's ``table`` (its entries ``given``)."""
        if self.other_boundaries is not None:
            # the file's value: an array of tables, or one value (not an array)
            entries = given if isinstance(given, list) else [given]
            names = [t.get("name") if isinstance(t, dict) else t for t in entries]
            return f"[[{table}]] {names}: {self.other_boundaries}"
        owner = next(k for k in DOMAIN_KINDS.values() if k.boundaries == table)
        return (
            f'[[{table}]] are for {owner.name} cases ([domain] kind = "{owner.name}"); '
            f"a {self.name} case gives its open boundaries as [[{self.boundaries}]]"
        )


_REGIONAL = DomainKind("regional")
_GLOBAL = DomainKind(
    "global",
    boundaries="cuts",
    keys=("kind", "pole", "close"),
    refuses_sites="farms, turbines, lines and structures are for regional cases; a "
    "global case has none",
    refuses_model_tests="a global case cannot be described by these smoke tests, "
    "which force a regional model through its open boundaries (a global ocean "
    "needs tidal potential, and ADCIRC a rotation of the poles); remove the key, "
    "or mesh a regional case",
    other_boundaries="a global case meshes the whole ocean, which has no open "
    "boundary. To cut a sea off the ocean with an open boundary (the Mediterranean "
    "at Gibraltar, say), give the line as [[cuts]], with the keys of "
    "[[open_boundaries]], and put [domain] seed in the ocean you keep",
)

#: Every kind of case, by its ``[domain] kind``.
DOMAIN_KINDS: dict[str, DomainKind] = {k.name: k for k in (_REGIONAL, _GLOBAL)}
#: ``[domain] kind`` when a case gives none.
DEFAULT_KIND = _REGIONAL.name


def domain_kind(name: object) -> DomainKind:
    """Return the kind of case named ``name`` (``[domain] kind``).

    Every other value gives the default kind: the key's own check reports it.
    """
    if isinstance(name, str) and name in DOMAIN_KINDS:
        return DOMAIN_KINDS[name]
    return DOMAIN_KINDS[DEFAULT_KIND]
