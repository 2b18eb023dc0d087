"""Size terms as plug-ins: :class:`SizeTerm`, and the case a term sizes.

A size term is a table of ``[mesh_size]`` (its config class, with its keys) and
what it asks of the size field on a grid: :meth:`SizeTerm.sizes` gets the grid
(:class:`~coastmesh.sizing.grid.Grid`) and the case (:class:`SizeCase`) and
returns its sizes and its report (:class:`~coastmesh.sizing.combine.TermSizes`).
A term is registered by one line of :class:`~coastmesh.case.config.SizeConfig`,
its key of ``[mesh_size]`` (:func:`~coastmesh.case.config.sizes.term_key`), so a
new term is one module and that entry; :data:`coastmesh.case.config.TERMS` lists
them, in the order their sizes are applied. A term may read the sizes of terms
before it (:attr:`SizeTerm.reads`, :meth:`SizeCase.sizes_of`).
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Mapping
from collections.abc import Set as AbstractSet
from concurrent.futures import Future
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any, ClassVar, Generic, TypeVar, cast

import numpy as np
import shapely
from numpy.typing import NDArray

from coastmesh.sizing.bands import BandRunner
from coastmesh.sizing.combine import TermSizes
from coastmesh.sizing.grid import Grid
from coastmesh.types import Domain

if TYPE_CHECKING:
    import xarray as xr

    from coastmesh.case.config import (
        CaseConfig,
        NodeDepthConfig,
        RasterConfig,
        SizeConfig,
    )
    from coastmesh.depth import DepthSources
    from coastmesh.sizing.narrow import ChannelReport

__all__ = [
    "AnyTerm",
    "Closing",
    "Settings",
    "SizeCase",
    "SizeTables",
    "SizeTerm",
    "switched_on",
]


def switched_on(enabled: bool | None) -> bool:
    """Whether a term on by default (channels, Courant) is on.

    ``enabled`` as the case gives it; unset (None, a case built in Python
    without it), the term is on, in regional and global cases alike.

    Examples
    --------
    >>> switched_on(None), switched_on(True), switched_on(False)
    (True, True, False)
    """
    return True if enabled is None else bool(enabled)


@dataclass(frozen=True)
class Closing:
    """What was closed before the size field: narrow channels, slots.

    Attributes
    ----------
    channels : ChannelReport or None
        With ``narrow = "close"``: the narrow channels closed (their count and
        area), None if none was.
    slots : int
        With ``narrow = "keep"``: the slots narrower than ``h_min / 2`` closed.
    passes : int
        With ``narrow = "close"``: the times the domain was built again, each
        time without the narrow channels found (0: none was found).
    """

    channels: ChannelReport | None = None
    slots: int = 0
    passes: int = 0


@dataclass(frozen=True)
class SizeTables:
    """The tables size terms read, for a domain built in Python (no case file).

    A :class:`SizeCase` holds the whole :class:`~coastmesh.case.CaseConfig` of
    a case; one made by :func:`coastmesh.case.domain_size_field` holds these.
    """

    size: SizeConfig
    bathymetry: NodeDepthConfig | None = None


@dataclass(frozen=True, eq=False)
class SizeCase:
    """The case, as a size term sees it.

    Attributes
    ----------
    config : CaseConfig or SizeTables
        The case: a term reads its own table (``config.size.<key>``), and
        other tables it needs (``config.bathymetry``).
    domain : Domain
        The domain meshed: its boundary segments by name.
    floor : float
        The field's floor ``h_min`` (:func:`~coastmesh.case.config.floor`).
    read_depth : callable
        ``read_depth(part) -> raster``: reads a ``[bathymetry]``-like part's
        rasters as the case needs them (over the domain's box, or the world);
        :meth:`depth` reads each part once.
    runner : Runner, optional
        Where the distance terms run, in bands (a Dask cluster).
    closing : Closing
        What was closed before the size field.
    site_area : shapely geometry, optional
        The ``[[sites]]``, in the grid's CRS (:meth:`sites`).
    lines : mapping of str to shapely geometry
        Lines that gradations may name besides the domain's boundary
        segments (the outlines of ``[[farms]]``), in the domain's CRS.
    """

    config: CaseConfig | SizeTables
    domain: Domain
    floor: float
    read_depth: Callable[[RasterConfig], xr.DataArray | DepthSources]
    runner: BandRunner | None = None
    closing: Closing = field(default_factory=Closing)
    site_area: shapely.Geometry | None = None
    lines: Mapping[str, shapely.Geometry] = field(default_factory=dict)
    _read: dict[RasterConfig, xr.DataArray | DepthSources] = field(
        default_factory=dict, repr=False
    )
    _lock: threading.Lock = field(default_factory=threading.Lock, repr=False)
    _terms: Mapping[str, Future[TermSizes | None]] = field(
        default_factory=dict, repr=False
    )
    _reader: str = field(default="", repr=False)

    def reading(
        self, term: AnyTerm, sizes: Mapping[str, Future[TermSizes | None]]
    ) -> SizeCase:
        """Return the case as ``term`` sees it: with the fields it reads.

        ``sizes`` holds the terms' sizes by key, as they are computed; the case
        returned gives ``term`` those of its :attr:`SizeTerm.reads` alone
        (:meth:`sizes_of`).
        """
        return replace(self, _terms={k: sizes[k] for k in term.reads}, _reader=term.key)

    def sizes_of(self, key: str) -> TermSizes | None:
        """Return the sizes of the term ``key``, one the reading term declares.

        A term lists the terms it reads in :attr:`SizeTerm.reads`; they come
        before it in the registry, and this waits for their sizes (None: that
        term is off).

        Raises
        ------
        KeyError
            ``key`` is not among the reading term's :attr:`SizeTerm.reads`.
        """
        if key not in self._terms:
            raise KeyError(
                f"size term {self._reader or '?'!r} reads the field of {key!r} "
                f"but does not declare it: add {key!r} to its reads"
            )
        return self._terms[key].result()

    def sites(self, grid: Grid) -> NDArray[np.bool_] | None:
        """Return the grid's nodes inside a ``[[sites]]`` region; None without sites.

        None too where the grid places no areas
        (:meth:`~coastmesh.sizing.grid.Grid.nodes_in`: global cases have no
        sites yet).
        """
        if self.site_area is None:
            return None
        return grid.nodes_in(self.site_area)

    def depth(self, part: RasterConfig) -> xr.DataArray | DepthSources:
        """Return a part's rasters, read once however many terms ask."""
        with self._lock:
            if part not in self._read:
                self._read[part] = self.read_depth(part)
            return self._read[part]


#: A term's settings: its table's config (or None: off), or a tuple of them.
Settings = TypeVar("Settings")


class SizeTerm(Generic[Settings]):
    """A size term: its key in ``[mesh_size]``, its config, and its sizes.

    Generic over its settings (``SizeTerm[CourantConfig | None]``,
    ``SizeTerm[tuple[GradationConfig, ...]]``): :meth:`settings` reads them
    typed, and :meth:`smallest` and :meth:`check` take them so.

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
    reports : bool
        Whether the term has a report (``size_field.<key>`` in ``report.json``,
        null when the term is off).
    doc : str
        One line for the key reference.
    floors : bool
        Whether the term's :meth:`smallest` size is also the field's default
        floor (the gradations' ``h_min``); a term that is not may lower the
        floor where it applies (:attr:`TermSizes.floor`).
    on_by_default : bool
        Whether its config's ``enabled``, left unset by the case, is read as
        on (:func:`switched_on`); the case reader sets it so, for every such
        term, in the case it returns.
    reads : tuple of str
        The keys of the terms whose sizes it reads (:meth:`SizeCase.sizes_of`):
        terms registered before it, whose sizes are computed before its own.
    """

    key: ClassVar[str]
    config: ClassVar[type]
    many: ClassVar[bool] = False
    default: ClassVar[object] = None
    reports: ClassVar[bool] = False
    doc: ClassVar[str] = ""
    floors: ClassVar[bool] = False
    on_by_default: ClassVar[bool] = False
    reads: ClassVar[tuple[str, ...]] = ()

    def sizes(self, grid: Grid, case: SizeCase) -> TermSizes | None:
        """Return the term's sizes on ``grid``; None when it is off."""
        raise NotImplementedError(f"{type(self).__name__} has no sizes()")

    def check(
        self,
        settings: Settings,
        case: CaseConfig,
        *,
        label: str,
        lines: AbstractSet[str],
    ) -> None:
        """Check the term's config against the rest of the case, once all is read.

        ``case`` is the case as read (``case.bathymetry``, ...), ``lines`` the
        names gradations may grade from (shoreline sets, open boundaries,
        farms, structures). Raise :class:`ConfigError` naming
        ``label`` (the case file) and the key; by default nothing is checked.
        """

    def settings(self, case: SizeCase) -> Settings:
        """Return the term's config in ``case``: its table (or tables), or None."""
        return self.of(case.config.size)

    def of(self, size: SizeConfig) -> Settings:
        """Return the term's config in a ``[mesh_size]`` config."""
        # the SizeConfig field named as the term's key: term_key gave it the
        # type of this term's Settings, which getattr cannot carry
        return cast(Settings, getattr(size, self.key))

    def smallest(self, settings: Settings) -> float | None:
        """Return the smallest size the term asks for, given its config.

        The size grid is no coarser than the smallest of the terms'
        (:func:`~coastmesh.case.config.terms_smallest`); with :attr:`floors`,
        the field's default floor (``h_min`` unset) is too
        (:func:`~coastmesh.case.config.floor`). None: the term asks for no
        size of its own (its sizes follow the field's floor).
        """
        return None


#: A size term, whatever its settings: the element type of the registry.
AnyTerm = SizeTerm[Any]
