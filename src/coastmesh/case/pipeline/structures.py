"""``[[structures]]``: land placed in the sea, cut out with a boundary id.

A pier, an artificial island, a lagoon wall: a polygon (lon/lat, or a vector
file in its own CRS) cut out of the domain as a hole, or as a notch where it
touches the coast (:func:`~coastmesh.geometry.domain_with_structures`). The
boundary edges on its outline carry its id and name (a land boundary, as a
shoreline set's), so gradations can name it in ``lines`` and every model
format writes it as land. The structures go first in the state's
``regions``, so a later closing of narrow water tags their edges the same,
and no closing drops them for their size.
"""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING

import shapely
from pyproj import CRS

from coastmesh.case.config import CaseConfig
from coastmesh.case.pipeline.places import file_place
from coastmesh.case.pipeline.state import DomainState
from coastmesh.errors import ConfigError
from coastmesh.geometry import domain_with_structures, reproject
from coastmesh.geometry.projection import sample_size
from coastmesh.types import SizeGrid

if TYPE_CHECKING:
    from coastmesh.meshing.gmsh import SphereSizeGrid

__all__ = ["check_structure_sizes", "read_structures", "with_structures"]

#: Least edges a structure's outline gets: fewer and its shape is lost.
MIN_EDGES = 8

_LONLAT = CRS.from_epsg(4326)


def with_structures(state: DomainState, config: CaseConfig) -> DomainState:
    """Return ``state`` with the case's structures cut out of its sea."""
    if not config.structures:
        return state
    structures = read_structures(config, state.domain.crs)
    try:
        domain, report = domain_with_structures(
            state.domain,
            structures,
            list(state.open_boundaries),
            state.report,
            shorelines=list(state.regions),
            seed=state.seed,
        )
    except ConfigError as exc:
        raise ConfigError(f"{config.label}: structures: {exc}") from None
    return replace(
        state,
        domain=domain,
        report=report,
        regions=(*structures, *state.regions),
        structures=tuple(structures),
    )


def read_structures(
    config: CaseConfig, crs: CRS
) -> list[tuple[str, int, shapely.Polygon]]:
    """Return (name, id, polygon) per structure, in ``crs``."""
    out = []
    for k, s in enumerate(config.structures):
        where = f"{config.label}: structures[{k}] ({s.name!r})"
        if s.polygon is not None:
            polygon = reproject(shapely.Polygon(s.polygon), _LONLAT, crs)
        else:
            assert s.path is not None  # _validate: a polygon or a path
            polygon = file_place(
                s.path, s.layer, crs, where, dimension=2, what="structure"
            )
        out.append((s.name, s.id, polygon))
    return out


def check_structure_sizes(
    state: DomainState, size: SizeGrid | SphereSizeGrid, label: str
) -> None:
    """Raise unless every structure's outline gets ``MIN_EDGES`` edges or more.

    The boundary is resampled at the size field: an outline shorter than
    ``MIN_EDGES`` elements of the size along it would lose its shape, and one
    under three would be dropped as a tiny island. The error names the
    structure and the size a gradation naming it must give.
    """
    for name, _, polygon in state.structures:
        ring = reproject(polygon.exterior, state.domain.crs, state.mesh_crs)
        ring = shapely.segmentize(ring, ring.length / 64)
        h = float(sample_size(size, shapely.get_coordinates(ring)).mean())
        if ring.length < MIN_EDGES * h * (1 - 1e-9):
            raise ConfigError(
                f"{label}: structures: {name!r}: its outline ({ring.length:,.0f} m) "
                f"would get {ring.length / h:.1f} edges of the {h:,.0f} m elements "
                f"around it (at least {MIN_EDGES} keep its shape); add a gradation "
                f"naming it, lines = [{name!r}], with h_min <= "
                f"{ring.length / MIN_EDGES:,.0f} m"
            )
