"""One entry of the mesh format registry: a name, extensions, a writer, a reader.

The entry checks the signatures of its writer and reader when it is made, so a
format that could not be called the way :func:`coastmesh.io.write_mesh` and
:func:`coastmesh.io.read_mesh` call it is refused at registration, with a message
that says the expected signature.
"""

from __future__ import annotations

import inspect
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from coastmesh.types import Mesh

__all__ = ["HOLDS", "MeshFormat"]

#: What a format's files can hold besides nodes, triangles and boundary edges.
HOLDS = {
    "ids": "boundary ids",
    "names": "boundary names",
    "kinds": "each boundary's kind (open or shoreline)",
    "depth": "depth at the nodes",
    "node_data": "every node field (depth, size, depth_source, ...)",
    "crs": "the CRS",
    "sphere_xyz": "nodes as x, y, z on the sphere (option sphere_xyz)",
    "regions": "a region id per element",
    "lines": "lines inside the mesh (`[[lines]]`) as edges with their ids",
    "node_regions": "a region id per node (ADCIRC fort.13); the elements' ids are "
    "read back from it where their nodes determine them",
}

# the keyword each role must take, and how it is called: the first two parameters
# of a writer are the path and the mesh, the first of a reader the path
_ROLES = {
    "write": ("overwrite", "write(path, mesh, *, overwrite, ...)"),
    "read": ("crs", "read(path, *, crs, ...)"),
}


@dataclass(frozen=True, slots=True)
class MeshFormat:
    """A mesh format: its name, file extensions, writer and reader.

    Parameters
    ----------
    name : str
        The name given as ``format=``; stored in lower case, no spaces.
    extensions : sequence of str
        File name endings of this format, at least one, each starting with
        ``"."`` (such as ``".msh"`` or ``".14"``); stored in lower case. The first
        is the one to give new files. A file name selects the format that
        registered its ending first (:func:`coastmesh.io.format_for_path`).
    write : callable or None
        ``write(path, mesh, *, overwrite, **options)``: writes ``mesh`` to
        ``path`` atomically and refuses an existing ``path`` unless
        ``overwrite``. Its other keyword parameters are the format's options.
        None for a format that is read only.
    description : str
        One line for listings.
    read : callable, optional
        ``read(path, *, crs, **options) -> Mesh``; ``crs`` is the CRS for files
        that store none. None (the default) for a format that is write only.
    model : str
        The models and tools that read it.
    holds : frozenset of str
        What its files hold besides nodes, triangles and boundary edges, from
        :data:`HOLDS`: a writer of cases asks, never the format's name.
    companions : tuple of str
        Endings of the files the writer writes beside the mesh (Telemac's
        ``.cli``), with the same stem.
    positive : {"up", "down"} or None
        The sign its depths are written with by default (the writer's
        ``positive`` option overrides it); None for a format without depth.
    region_companions : tuple of str
        Endings of the files the writer writes beside the mesh, with the same
        stem, only when the mesh has a region other than its surface id
        (ADCIRC's ``.13``): :meth:`companions_for` says which a mesh gets.

    Raises
    ------
    ValueError
        If the name or an extension is malformed, there is neither a reader nor a
        writer, or one is not callable or lacks its ``overwrite``/``crs`` keyword.

    Examples
    --------
    >>> from coastmesh.io import mesh_format
    >>> fmt = mesh_format("msh4")
    >>> fmt.extensions, fmt.options, fmt.read_options, fmt.mode
    (('.msh',), ('binary', 'sphere_xyz', 'radius'), (), 'read and write')
    """

    name: str
    extensions: tuple[str, ...]
    write: Callable[..., object] | None  # what it returns is not used
    description: str
    read: Callable[..., Mesh] | None = None
    model: str = ""
    holds: frozenset[str] = frozenset()
    companions: tuple[str, ...] = ()
    positive: str | None = None
    region_companions: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        name = self.name
        if not isinstance(name, str) or not name or name != "".join(name.split()):
            raise ValueError(
                f"mesh format name {name!r}: expected a non-empty string without spaces"
            )
        extensions = (
            (self.extensions,)
            if isinstance(self.extensions, str)
            else tuple(self.extensions)
        )
        if not extensions:
            raise ValueError(
                f"mesh format {name!r}: give at least one extension, such as '.msh'"
            )
        for ext in extensions:
            if not isinstance(ext, str) or len(ext) < 2 or not ext.startswith("."):
                raise ValueError(
                    f"mesh format {name!r}: extension {ext!r} must be a string "
                    "starting with '.', such as '.msh'"
                )
        if self.write is None and self.read is None:
            raise ValueError(f"mesh format {name!r}: give a writer, a reader or both")
        unknown = sorted(set(self.holds) - set(HOLDS))
        if unknown:
            raise ValueError(
                f"mesh format {name!r}: holds {unknown}: expected some of "
                f"{', '.join(HOLDS)}"
            )
        if self.positive not in (None, "up", "down"):
            raise ValueError(
                f"mesh format {name!r}: positive = {self.positive!r}: expected "
                "'up', 'down' or None"
            )
        for field in ("companions", "region_companions"):
            endings = getattr(self, field)
            endings = (endings,) if isinstance(endings, str) else tuple(endings)
            for ext in endings:
                if not isinstance(ext, str) or not ext.startswith("."):
                    raise ValueError(
                        f"mesh format {name!r}: companion {ext!r} must start with '.'"
                    )
            object.__setattr__(self, field, endings)
        object.__setattr__(self, "holds", frozenset(self.holds))
        for role in _ROLES:
            self._options(role)
        object.__setattr__(self, "name", name.lower())
        object.__setattr__(
            self, "extensions", tuple(dict.fromkeys(e.lower() for e in extensions))
        )
        object.__setattr__(self, "description", str(self.description))

    @property
    def options(self) -> tuple[str, ...] | None:
        """The writer's keyword options besides ``overwrite``; None for ``**kwargs``."""
        return self._options("write")

    @property
    def read_options(self) -> tuple[str, ...] | None:
        """The reader's keyword options besides ``crs``; None for ``**kwargs``."""
        return self._options("read")

    def companions_for(self, mesh: Mesh) -> tuple[str, ...]:
        """Return the endings of the files written beside ``mesh``'s file.

        Parameters
        ----------
        mesh : Mesh
            The mesh to write, with the writer's default options.

        Returns
        -------
        tuple of str
            :attr:`companions`, then :attr:`region_companions` if a triangle of
            ``mesh`` has a region id other than its surface id.

        Examples
        --------
        >>> from coastmesh.io import mesh_format
        >>> m = Mesh([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]], [], [], 1, None,
        ...          regions=[20])
        >>> mesh_format("fort14").companions_for(m)
        ('.13',)
        """
        if (mesh.regions != mesh.surface_id).any():
            return self.companions + self.region_companions
        return self.companions

    @property
    def mode(self) -> str:
        """``"read and write"``, ``"write only"`` or ``"read only"``."""
        if self.read is None:
            return "write only"
        return "read only" if self.write is None else "read and write"

    def _options(self, role: str) -> tuple[str, ...] | None:
        function = getattr(self, role)
        if function is None:
            return ()
        return _keywords(function, self.name, role, *_ROLES[role])


def _keywords(
    function: Callable[..., Any], name: str, role: str, keyword: str, usage: str
) -> tuple[str, ...] | None:
    """Return the keyword options of a reader or writer besides ``keyword``.

    None if it takes ``**kwargs``; raises ValueError if it is not callable or
    takes no ``keyword``.
    """
    if not callable(function):
        raise ValueError(f"mesh format {name!r}: {role} is not callable")
    try:
        parameters = list(inspect.signature(function).parameters.values())
    except (TypeError, ValueError):
        raise ValueError(
            f"mesh format {name!r}: the signature of {role} cannot be inspected"
        ) from None
    if any(p.kind is p.VAR_KEYWORD for p in parameters):
        return None
    skip = 2 if role == "write" else 1
    found = [
        p.name
        for p in parameters[skip:]
        if p.kind in {p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY}
    ]
    if keyword not in found:
        raise ValueError(
            f"mesh format {name!r}: {role} takes no {keyword!r} keyword; "
            f"expected {usage}"
        )
    return tuple(k for k in found if k != keyword)
