"""A tidal site in the mesh: ``[[farms]]`` and ``[[turbines]]`` as regions and nodes.

:func:`site_features` reads the farms and turbines of a case into the meshing
CRS and checks them against the sea: each farm is one polygon of sea, farms do
not overlap, a turbine stands in the sea (in its farm, if it names one), its
footprint does not cross a farm's outline, and no two turbines are closer than
their ``spacing``. Each error names the farm or turbine. The mesh stage then
meshes each farm and footprint as a region of its own
(:class:`~coastmesh.meshing.parts.inner.Inner`) and sizes it through a patch
of the size grid (:func:`~coastmesh.sizing.patches.site_patch`): the farm's
``h`` inside it, the turbines' ``h`` over their footprints (or, for a node,
over a disc of diameter ``D``), graded at the field's ``rate``.

A disc footprint is the regular polygon of ``ceil(pi D / h)`` sides (at least
8) inscribed in the circle of diameter ``D``: its vertices are mesh nodes, so
the region's area is the polygon's. A square footprint has side ``D``, one pair
of sides across ``bearing``.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TypedDict

import numpy as np
import shapely
import shapely.affinity
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.case.config import CaseConfig, RotorLength, TurbinesConfig
from coastmesh.case.pipeline.lines import SiteLine, line_coords, read_lines
from coastmesh.case.pipeline.places import file_place
from coastmesh.case.pipeline.state import DomainState
from coastmesh.errors import ConfigError, InputDataError, MeshingError
from coastmesh.geometry import reproject
from coastmesh.geometry.earth import reproject_points
from coastmesh.io.vectors.vector import read_features
from coastmesh.meshing.parts.inner import Inner
from coastmesh.sizing.patches import site_patch, with_patches
from coastmesh.types import Domain, Mesh, SizeGrid

__all__ = [
    "SiteFeatures",
    "Turbine",
    "check_clearance",
    "site_features",
    "turbine_nodes",
    "with_site_sizes",
    "write_turbines",
]

_LONLAT = CRS.from_epsg(4326)

#: A farm of a site: (name, id, polygon in the meshing CRS, h or None).
SiteFarm = tuple[str, int, shapely.Polygon, float | None]
#: A turbine's footprint: (the turbine's name, id, polygon in the meshing CRS).
Footprint = tuple[str, int, shapely.Polygon]
#: A turbine as read: (name, lon/lat or None, xy, its CRS, diameter or None).
Position = tuple[
    str, tuple[float, float] | None, tuple[float, float], CRS, float | None
]


@dataclass(frozen=True)
class Turbine:
    """One turbine, in the meshing CRS."""

    name: str
    group: str
    xy: tuple[float, float]
    lonlat: tuple[float, float] | None  # as given; None if given in another CRS
    diameter: float
    h: float
    footprint: str
    region: int | None  # the footprint's id; None for a node
    farm: str | None
    clearance: float = 0.0  # the shallowest water it may stand in, metres


@dataclass(frozen=True)
class SiteFeatures:
    """The farms, turbines and lines of a case, in the meshing CRS, checked.

    ``farms`` are (name, id, polygon, h or None); ``footprints`` (turbine
    name, id, polygon); ``turbines`` every turbine; ``wakes`` (source, band,
    h); ``lines`` (name, id, line, h or None).
    """

    farms: tuple[SiteFarm, ...]
    footprints: tuple[Footprint, ...]
    turbines: tuple[Turbine, ...]
    crs: CRS
    #: (the source's name, the band, its size): ``[[wakes]]``
    wakes: tuple[tuple[str, shapely.Polygon, float], ...] = ()
    #: (name, id, line, h or None): ``[[lines]]``
    lines: tuple[SiteLine, ...] = ()

    def __bool__(self) -> bool:
        return bool(self.farms or self.turbines or self.lines)

    def inner(self) -> Inner:
        """Return the regions, nodes and lines the mesher must hold."""
        regions = [(p, pid, name) for name, pid, p, _ in self.farms]
        regions += [(p, pid, name) for name, pid, p in self.footprints]
        nodes = [t.xy for t in self.turbines if t.footprint == "node"]
        return Inner(
            tuple(regions),
            np.array(nodes, dtype=np.float64).reshape(-1, 2),
            crs=self.crs,
            lines=line_coords(self.lines),
        )

    def sizes(
        self, x: NDArray[np.float64], y: NDArray[np.float64], rate: float
    ) -> NDArray[np.float64]:
        """Return the site's sizes at points, growing at ``rate`` away from it.

        The farm's ``h`` inside it and ``h + rate d`` at a distance ``d`` from
        it; a turbine's ``h`` within ``D / 2 + h`` of it, growing the same
        beyond; ``inf`` where the site asks for nothing (a farm without ``h``).
        """
        h = np.full(np.shape(x), np.inf)
        points = None
        for _, _, polygon, size in self.farms:
            if size is None:
                continue
            if points is None:
                points = shapely.points(x, y)
            h = np.minimum(h, size + rate * shapely.distance(polygon, points))
        for t in self.turbines:
            d = np.hypot(x - t.xy[0], y - t.xy[1]) - (t.diameter / 2 + t.h)
            h = np.minimum(h, t.h + rate * np.maximum(d, 0.0))
        for _, band, size in self.wakes:
            if points is None:
                points = shapely.points(x, y)
            h = np.minimum(h, size + rate * shapely.distance(band, points))
        for *_, line, size in self.lines:
            if size is None:
                continue
            if points is None:
                points = shapely.points(x, y)
            h = np.minimum(h, size + rate * shapely.distance(line, points))
        return h

    def smallest(self) -> float:
        """Return the smallest size the site asks for (inf if none)."""
        given = [h for *_, h in self.farms if h is not None]
        given += [t.h for t in self.turbines] + [h for *_, h in self.wakes]
        given += [h for *_, h in self.lines if h is not None]
        return min(given, default=math.inf)

    def box(self) -> tuple[float, float, float, float]:
        """Return the bounds of the farms and the turbines' footprints."""
        geoms = [p for _, _, p, _ in self.farms] + [
            shapely.Point(t.xy).buffer(t.diameter) for t in self.turbines
        ]
        geoms += [band for _, band, _ in self.wakes]
        geoms += [line for *_, line, h in self.lines if h is not None]
        return tuple(shapely.total_bounds(geoms).tolist())


def site_features(config: CaseConfig, state: DomainState) -> SiteFeatures:
    """Read and check the case's farms, turbines and lines, in the meshing CRS."""
    return site_features_in(config, state.domain, state.mesh_crs)


def site_features_in(config: CaseConfig, domain: Domain, crs: CRS) -> SiteFeatures:
    """Read and check the case's farms, turbines and lines in ``domain``, in ``crs``.

    Each must lie in the domain's water (a patch's hole, for ``coastmesh patch``).
    """
    sea = reproject(domain.polygon, domain.crs, crs)
    shapely.prepare(sea)
    farms = tuple(_farms(config, crs, sea))
    turbines, footprints = _turbines(config, crs, sea, farms)
    _check_footprint_ids(config, footprints)
    wakes = tuple(_wakes(config, farms, turbines))
    outlines = [(n, p) for n, _, p, _ in farms] + [(n, p) for n, _, p in footprints]
    lines = read_lines(config, crs, sea, outlines)
    return SiteFeatures(farms, tuple(footprints), tuple(turbines), crs, wakes, lines)


def _wakes(
    config: CaseConfig, farms: Sequence[SiteFarm], turbines: Sequence[Turbine]
) -> Iterator[tuple[str, shapely.Polygon, float]]:
    """Yield (source, band, h) per ``[[wakes]]``, in the meshing CRS.

    The band is the source swept ``length`` along the axis (the convex hull of
    the source and its copies moved there): a farm's polygon, or the discs
    of diameter ``D`` of a group's turbines. Shares of ``D`` are of the
    group's rotors, or of the largest rotor standing in a farm.
    """
    for k, w in enumerate(config.wakes):
        where = f"{config.label}: wakes[{k}] (of {w.of!r})"
        group = [t for t in turbines if t.group == w.of]
        farm = next((f for f in farms if f[0] == w.of), None)
        if farm is not None:
            source = farm[2]
            group = [t for t in turbines if t.farm == w.of]
        else:
            source = shapely.union_all(
                [shapely.Point(t.xy).buffer(t.diameter / 2, 16) for t in group]
            )
        diameter = max((t.diameter for t in group), default=None)
        h: float | None
        try:
            length = w.length.metres(_needs(diameter, w.length, "length"))
            if w.h is not None:
                h = w.h.metres(_needs(diameter, w.h, "h"))
            elif farm is not None:  # a farm's wake: the farm's size
                h = farm[3]
            else:  # a group's wake: half a rotor
                assert diameter is not None  # a turbine group has a turbine
                h = diameter / 2
        except ValueError as exc:
            raise ConfigError(f"{where}: {exc}") from None
        if h is None:
            raise ConfigError(f"{where}: give h: the farm has no h to take")
        turn = math.radians(w.bearing)
        step = np.array([math.sin(turn), math.cos(turn)]) * length
        ends = {"both": (step, -step), "flood": (step,), "ebb": (-step,)}[w.sides]
        moved = [shapely.affinity.translate(source, *end) for end in ends]
        yield w.of, shapely.union_all([source, *moved]).convex_hull, float(h)


def _needs(diameter: float | None, value: RotorLength, key: str) -> float:
    """Return the diameter a share of D needs; raise if there is none."""
    if value.per_d and diameter is None:
        raise ValueError(
            f"{key} = {value}: a share of D, but the source has no turbines to "
            "give D; give a length"
        )
    return diameter or 0.0


def _check_footprint_ids(config: CaseConfig, footprints: Sequence[Footprint]) -> None:
    """Raise if a footprint's id is another's, a farm's or a boundary's.

    The case file's check sees the ids of inline turbines; those of turbines
    read from a file are known only here.
    """
    taken = {s.physical_id: f"shoreline set {s.name!r}" for s in config.sets}
    taken |= {b.physical_id: f"open boundary {b.name!r}" for b in config.boundaries}
    taken[config.domain.surface_id] = "the domain's surface"
    taken |= {f.id: f"farm {f.name!r}" for f in config.farms}
    for name, pid, _ in footprints:
        if pid in taken:
            raise ConfigError(
                f"{config.label}: the footprint of turbine {name!r} has id {pid}, "
                f"which is the id of {taken[pid]}; every footprint needs its own id"
            )
        taken[pid] = f"the footprint of turbine {name!r}"


def with_site_sizes(
    size: SizeGrid, site: SiteFeatures, rate: float | None, label: str
) -> SizeGrid:
    """Return the size grid with a patch at the site's sizes; as it is without.

    The sizes grow at ``rate`` away from the site: raise without one.
    """
    smallest = site.smallest()
    if not site or not math.isfinite(smallest):
        return size
    if rate is None:
        raise ConfigError(
            f"{label}: mesh_size.rate = false: the sizes of the farms, turbines "
            "and lines grow at the rate away from them; give a rate"
        )
    levels = site_patch(
        size,
        site.box(),
        lambda x, y: site.sizes(x, y, rate),
        smallest=smallest,
        rate=rate,
    )
    return with_patches(size, levels)


def _farms(config: CaseConfig, crs: CRS, sea: shapely.Geometry) -> Iterator[SiteFarm]:
    """Yield (name, id, polygon, h) per farm, in ``crs``; each in the sea."""
    seen: list[tuple[str, shapely.Polygon]] = []
    for k, f in enumerate(config.farms):
        where = f"{config.label}: farms[{k}] ({f.name!r})"
        if f.polygon is not None:
            polygon = reproject(shapely.Polygon(f.polygon), _LONLAT, crs)
        else:
            assert f.path is not None  # _validate: a polygon or a path
            polygon = file_place(f.path, f.layer, crs, where, dimension=2, what="farm")
        if not polygon.is_valid or polygon.area <= 0:
            reason = shapely.is_valid_reason(polygon)
            raise ConfigError(f"{where}: the polygon is not valid ({reason})")
        outside = polygon.difference(sea).area
        if outside > 1e-6 * polygon.area:
            raise ConfigError(
                f"{where}: {outside / polygon.area:.1%} of the farm "
                f"({outside / 1e6:,.4f} km2) lies on land or outside the domain; "
                "a farm must lie in the sea that is meshed"
            )
        gap = sea.boundary.distance(polygon)
        if gap <= 0:
            raise ConfigError(
                f"{where}: the farm's outline touches the domain's boundary (the "
                "coast or an open boundary); keep it inside the sea, at least an "
                "element of the coast's size away"
            )
        for name, other in seen:
            if polygon.intersection(other).area > 0 or polygon.touches(other):
                raise ConfigError(f"{where}: the farm overlaps farm {name!r}")
        seen.append((f.name, polygon))
        yield f.name, f.id, shapely.Polygon(polygon.exterior.coords), f.h


def _turbines(
    config: CaseConfig, crs: CRS, sea: shapely.Geometry, farms: Sequence[SiteFarm]
) -> tuple[list[Turbine], list[Footprint]]:
    """Return the turbines and their footprints, checked."""
    by_name = {name: polygon for name, _, polygon, _ in farms}
    turbines: list[Turbine] = []
    footprints: list[Footprint] = []
    for k, group in enumerate(config.turbines):
        where = f"{config.label}: turbines[{k}] ({group.name!r})"
        rows = _positions(group, where)
        for n, (name, lonlat, xy_src, src, diameter) in enumerate(rows):
            d = diameter if diameter is not None else group.diameter
            if d is None or not d > 0:
                raise ConfigError(f"{where}: turbine {name!r} has no diameter")
            xy = tuple(reproject_points(np.array([xy_src]), src, crs)[0].tolist())
            h = group.h.metres(d)
            region = None
            if group.footprint != "node":
                region = group.ids[n] if group.ids else (group.id or 0) + n
            shape = _footprint(group.footprint, xy, d, h, group.bearing)
            _check_resolvable(name, where, shape, h, sea)
            _check_place(name, where, shape, sea, by_name, group.farm)
            turbine = Turbine(
                name,
                group.name,
                xy,
                lonlat,
                d,
                h,
                group.footprint,
                region,
                group.farm,
                group.clearance.metres(d),
            )
            turbines.append(turbine)
            if region is not None:
                footprints.append((name, region, shape))
            _check_spacing(turbine, turbines[:-1], group.spacing.metres(d), where)
    return turbines, footprints


def _positions(group: TurbinesConfig, where: str) -> Iterator[Position]:
    """Yield (name, lon/lat or None, xy, its CRS, diameter or None) per turbine."""
    if group.positions is not None:
        for n, (lon, lat) in enumerate(group.positions):
            yield f"{group.name}_{n + 1}", (lon, lat), (lon, lat), _LONLAT, None
        return
    assert group.path is not None  # _validate: positions or a path
    path = Path(group.path)
    if path.suffix.lower() in (".csv", ".txt"):
        yield from _csv_positions(path, group, where)
        return
    features = read_features(path, layer=group.layer)
    src = features.crs or _LONLAT
    names = features.fields.get("name") if features.fields else None
    sizes = features.fields.get("diameter") if features.fields else None
    for n, geom in enumerate(features.geometry):
        if geom is None or geom.geom_type != "Point":
            raise InputDataError(
                f"{where}: feature {n} of {path} is not a point", path=str(path)
            )
        name = str(names[n]) if names is not None else f"{group.name}_{n + 1}"
        d = float(sizes[n]) if sizes is not None else None
        yield name, None, (geom.x, geom.y), src, d


def _csv_positions(path: Path, group: TurbinesConfig, where: str) -> Iterator[Position]:
    """Yield the turbines of a CSV of ``name, x, y[, diameter]``."""
    src = CRS.from_user_input(group.crs) if group.crs else _LONLAT
    if not path.exists():
        raise InputDataError(f"{where}: no such file", path=str(path))
    with path.open(newline="") as fh:
        reader = csv.DictReader(fh)
        missing = {"x", "y"} - set(reader.fieldnames or ())
        if missing:
            raise InputDataError(
                f"{where}: the CSV has no column {sorted(missing)[0]!r}; it needs "
                "name, x, y and optionally diameter",
                path=str(path),
            )
        for n, row in enumerate(reader):
            name = row.get("name") or f"{group.name}_{n + 1}"
            try:
                xy = (float(row["x"]), float(row["y"]))
                d = float(row["diameter"]) if row.get("diameter") else None
            except ValueError:
                raise InputDataError(
                    f"{where}: row {n + 2} ({name!r}) has a value that is not a "
                    f"number: {row}",
                    path=str(path),
                ) from None
            lonlat = xy if src.is_geographic else None
            yield name, lonlat, xy, src, d


def _footprint(
    kind: str, xy: tuple[float, float], diameter: float, h: float, bearing: float
) -> shapely.Polygon:
    """Return a turbine's footprint polygon in the meshing CRS."""
    cx, cy = xy
    if kind == "square":
        half = diameter / 2
        corners = np.array([[-half, -half], [half, -half], [half, half], [-half, half]])
        turn = math.radians(-bearing)  # clockwise from north
        rot = np.array(
            [[math.cos(turn), -math.sin(turn)], [math.sin(turn), math.cos(turn)]]
        )
        return shapely.Polygon(corners @ rot.T + [cx, cy])
    sides = max(8, math.ceil(math.pi * diameter / h))
    t = np.linspace(0.0, 2 * math.pi, sides, endpoint=False)
    ring = np.column_stack(
        [cx + diameter / 2 * np.cos(t), cy + diameter / 2 * np.sin(t)]
    )
    return shapely.Polygon(ring)


#: The smallest element, as a share of the domain's extent, that the mesher is
#: asked for: Gmsh merges points closer than ``Geometry.Tolerance`` (1e-8 of
#: the model's size), and coastmesh keeps a hundredfold margin above it.
MIN_SHARE = 1e-6


def _check_resolvable(
    name: str, where: str, shape: shapely.Polygon, h: float, sea: shapely.Geometry
) -> None:
    """Raise if the footprint's sides or ``h`` are under what Gmsh can place."""
    x0, y0, x1, y1 = sea.bounds
    least = MIN_SHARE * max(x1 - x0, y1 - y0)
    sides = np.linalg.norm(np.diff(np.asarray(shape.exterior.coords), axis=0), axis=1)
    smallest = min(h, float(sides.min()))
    if smallest < least:
        raise ConfigError(
            f"{where}: turbine {name!r}: its footprint needs elements of "
            f"{smallest:.3g} m, smaller than the smallest element Gmsh can place "
            f"in a domain {max(x1 - x0, y1 - y0) / 1000:,.0f} km wide ({least:.3g} "
            "m, a millionth of it); give a larger h or diameter"
        )


def _check_place(
    name: str,
    where: str,
    shape: shapely.Polygon,
    sea: shapely.Geometry,
    farms: Mapping[str, shapely.Polygon],
    farm: str | None,
) -> None:
    """Raise unless the footprint is in the sea (and in its farm), across no outline."""
    if not sea.contains(shape):
        raise ConfigError(
            f"{where}: turbine {name!r} (its footprint of diameter D) is not in "
            "the sea that is meshed"
        )
    if farm is not None and not farms[farm].contains(shape):
        raise ConfigError(
            f"{where}: turbine {name!r} is not inside its farm {farm!r} (its "
            "footprint must lie wholly inside the farm's outline)"
        )
    for other, polygon in farms.items():
        if polygon.boundary.intersects(shape):
            raise ConfigError(
                f"{where}: the footprint of turbine {name!r} crosses the outline "
                f"of farm {other!r}"
            )


def _check_spacing(
    turbine: Turbine, others: Sequence[Turbine], spacing: float, where: str
) -> None:
    """Raise if ``turbine`` is closer than ``spacing`` to one of ``others``."""
    for other in others:
        gap = math.hypot(turbine.xy[0] - other.xy[0], turbine.xy[1] - other.xy[1])
        both = turbine.footprint != "node" and other.footprint != "node"
        touching = (turbine.diameter + other.diameter) / 2 if both else 0.0
        if gap < max(spacing, touching):
            raise ConfigError(
                f"{where}: turbines {other.name!r} and {turbine.name!r} are "
                f"{gap:,.1f} m apart, closer than the spacing {spacing:,.1f} m"
            )


def turbine_nodes(site: SiteFeatures, mesh: Mesh) -> NDArray[np.int64]:
    """Return the node of each turbine of ``site`` in ``mesh`` (its nearest).

    Raises
    ------
    MeshingError
        If a turbine's nearest node is more than 1 mm from it (a node turbine:
        its node is at its place) or farther than its footprint (a footprint).
    """
    if not site.turbines:
        return np.empty(0, dtype=np.int64)
    xy = np.array([t.xy for t in site.turbines])
    at = reproject_points(xy, site.crs, mesh.crs) if mesh.crs is not None else xy
    out = []
    for t, (x, y) in zip(site.turbines, at, strict=True):
        gap = np.hypot(mesh.points[:, 0] - x, mesh.points[:, 1] - y)
        k = int(np.argmin(gap))
        if t.footprint == "node":
            local = np.asarray(
                reproject_points(mesh.points[k : k + 1], mesh.crs, site.crs)
                if mesh.crs is not None
                else mesh.points[k : k + 1]
            )[0]
            off = math.hypot(local[0] - t.xy[0], local[1] - t.xy[1])
            if off > 1e-3:
                raise MeshingError(
                    f"turbine {t.name!r}: its node is {off:.4f} m from its place"
                )
        out.append(k)
    return np.array(out, dtype=np.int64)


def check_clearance(site: SiteFeatures, mesh: Mesh) -> None:
    """Raise if a turbine stands in water shallower than its ``clearance``.

    The depth at the turbine's node (the nearest node of a footprint), as the
    mesh has it (``point_data["depth"]``, positive down).
    """
    depth = mesh.point_data.get("depth")
    if depth is None or not site.turbines:
        return
    for t, node in zip(site.turbines, turbine_nodes(site, mesh), strict=True):
        here = float(depth[node])
        if here < t.clearance:
            raise ConfigError(
                f"turbine {t.name!r} ({t.group}) stands in {here:.1f} m of water, "
                f"shallower than its clearance of {t.clearance:.1f} m "
                "([[turbines]] clearance, default D)"
            )


class TurbineRow(TypedDict):
    """A row of ``turbines.csv`` (:func:`turbine_rows`), as it is written."""

    name: str
    group: str
    lon: str
    lat: str
    x: str
    y: str
    node: int
    node_x: str
    node_y: str
    region: int
    diameter_m: str
    size_m: str
    element_size_m: str
    depth_m: str


#: The columns of ``turbines.csv``.
TURBINE_COLUMNS = (
    "name",
    "group",
    "lon",
    "lat",
    "x",
    "y",
    "node",
    "node_x",
    "node_y",
    "region",
    "diameter_m",
    "size_m",
    "element_size_m",
    "depth_m",
)


def turbine_rows(site: SiteFeatures, mesh: Mesh) -> list[TurbineRow]:
    """Return a row per turbine: where it is and what the mesh has there.

    ``lon``, ``lat`` are the turbine's place (as the case gives it, if in
    lon/lat) and ``x``, ``y`` the same place in the mesh's (output) CRS;
    ``node`` is the index of its node (the nearest node of a footprint, whose
    centre is the turbine) and ``node_x``, ``node_y`` that node's place in the
    mesh's CRS (a node turbine's, within 1 mm of its own). ``region`` is the
    physical id of its footprint or of the triangles at its node, ``size_m``
    the size asked, ``element_size_m`` the mean length of the mesh edges at
    its node (metres, in the meshing CRS), ``depth_m`` the depth there (empty
    without one).
    """
    nodes = turbine_nodes(site, mesh)
    places = np.array([t.xy for t in site.turbines])
    lonlat = reproject_points(places, site.crs, _LONLAT)
    for k, t in enumerate(site.turbines):
        if t.lonlat is not None:  # given in lon/lat: as given, not round-tripped
            lonlat[k] = t.lonlat
    placed = reproject_points(lonlat, _LONLAT, mesh.crs) if mesh.crs else places
    plane = (
        reproject_points(mesh.points, mesh.crs, site.crs) if mesh.crs else mesh.points
    )
    depth = mesh.point_data.get("depth")
    rows: list[TurbineRow] = []
    for t, node, (lon, lat), (x, y) in zip(
        site.turbines, nodes, lonlat, placed, strict=True
    ):
        at = np.flatnonzero((mesh.triangles == node).any(axis=1))
        neighbours = np.setdiff1d(np.unique(mesh.triangles[at]), [node])
        lengths = np.hypot(*(plane[neighbours] - plane[node]).T)
        regions = np.unique(mesh.regions[at])
        region = t.region if t.region is not None else int(regions.min())
        rows.append(
            {
                "name": t.name,
                "group": t.group,
                "lon": f"{lon:.8f}",
                "lat": f"{lat:.8f}",
                "x": repr(float(x)),
                "y": repr(float(y)),
                "node": int(node),
                "node_x": repr(float(mesh.points[node, 0])),
                "node_y": repr(float(mesh.points[node, 1])),
                "region": region,
                "diameter_m": f"{t.diameter:g}",
                "size_m": f"{t.h:g}",
                "element_size_m": f"{lengths.mean():.3f}",
                "depth_m": "" if depth is None else f"{float(depth[node]):.3f}",
            }
        )
    return rows


def write_turbines(path: Path, site: SiteFeatures, mesh: Mesh) -> None:
    """Write ``turbines.csv``: one row per turbine (:func:`turbine_rows`)."""
    with Path(path).open("w", newline="", encoding="utf-8") as fh:
        writer = csv.DictWriter(fh, fieldnames=TURBINE_COLUMNS)
        writer.writeheader()
        writer.writerows(turbine_rows(site, mesh))
