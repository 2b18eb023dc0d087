"""Size terms as plug-ins: :class:`SizeTerm`, one class per term.

A size term is a table of ``[mesh_size]`` (its config class, with its keys) and
what it asks of the size field. :data:`coastmesh.case.terms.TERMS` lists them;
``[mesh_size]`` has one key per term (:class:`~coastmesh.case.config.SizeConfig`
is made from the list), so a new term is one module and one entry there.
"""

from __future__ import annotations

from typing import Any, ClassVar

__all__ = ["SizeTerm"]


class SizeTerm:
    """A size term: its key in ``[mesh_size]`` and its config.

    Attributes
    ----------
    key : str
        The term's key in ``[mesh_size]`` (``"courant"``), and the field of
        :class:`~coastmesh.case.config.SizeConfig` that holds its config.
    config : type
        Its table's config class (keys declared with
        :func:`coastmesh.case.schema.key`).
    many : bool
        An array of tables (``[[mesh_size.gradations]]``), not one table.
    default : object
        Its config when the case gives none: None (the term is off), ``()``
        for an array, or an instance (on by default).
    doc : str
        One line for the key reference.
    """

    key: ClassVar[str]
    config: ClassVar[type]
    many: ClassVar[bool] = False
    default: ClassVar[Any] = None
    doc: ClassVar[str] = ""
