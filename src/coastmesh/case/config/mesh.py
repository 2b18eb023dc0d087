"""``[mesh]``, ``[cleanup]``, ``[bathymetry]``, ``[output]`` and ``[run]``."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from coastmesh.case import schema
from coastmesh.case.schema import Check, key
from coastmesh.case.sources import UP_DOWN, RasterConfig
from coastmesh.depth import DEPTH_METHODS, LAND_TREATMENTS, OUTSIDE_RULES
from coastmesh.errors import ConfigError
from coastmesh.meshing.gmsh import ALGORITHMS

__all__ = [
    "CleanupConfig",
    "MeshConfig",
    "NodeDepthConfig",
    "OutputConfig",
    "RunConfig",
]


@dataclass(frozen=True)
class NodeDepthConfig(RasterConfig):
    """``[bathymetry]``: the depth written at the mesh nodes.

    One raster (``path``) or a stack (``sources``); see ``docs/case-files.md``
    for every key and :func:`coastmesh.depth.depth_at_nodes` for the method.
    """

    method: str = key(
        "bilinear",
        check=schema.choice(DEPTH_METHODS),
        doc='or `"mean"`: where the mesh is coarser than the raster, the mean of '
        "the valid cells within half the mean edge length of each node",
    )
    min_depth: float | None = key(
        None,
        check=schema.length(signed=True),
        unit="length",
        doc="a floor for dry-prone shallows: shallower nodes are set to this "
        '(e.g. `"5 m"` for a model without wetting and drying). Not the depth of '
        "a sea the raster cannot see: `land` gives those theirs",
    )
    max_slope: float | None = key(
        None,
        check=schema.positive,
        doc="the largest `|depth difference| / edge length` along any edge; "
        "deeper nodes are made shallower until it holds (a min-plus convolution "
        "over the mesh graph), so the coast keeps its depths",
    )
    window: int | None = key(
        None,
        check=schema.integer(2),
        doc="with `modes`: interpolate the PCA approximation of each raster (of "
        "the window read) instead (the paper's section II)",
    )
    modes: int | None = key(None, check=schema.integer(1), doc="see `window`")
    outside: str = key(
        "error",
        check=schema.choice(OUTSIDE_RULES),
        doc="nodes more than one cell diagonal beyond every raster's data: an "
        "error that names the rasters, the share of nodes each covers and where "
        'the gap is; or `"nearest"`: the nearest valid cell on the Earth, with a '
        "warning that counts them",
    )
    land: str | None = key(
        None,
        check=schema.choice(LAND_TREATMENTS),
        default_doc='`"wet"`; then more than half the nodes on land in the rasters '
        "is an error",
        doc="nodes beside or on land in the rasters (depth <= 0 m, common near "
        'the coast on coarse grids). `"wet"`: a node reads the wet cells alone '
        "(the bilinear weights of its four cells renormalised over the wet "
        "ones), so no sea node takes a land cell's value; a node with no wet "
        "cell around takes the nearest wet cell on the Earth, tapered to "
        "`min_depth` (if given) at the coast across the strip the raster calls "
        'land. `"min_depth"`: the depth floor; `"nearest_sea"`: the nearest wet '
        'cell; `"smooth"`: the nearest wet cell, then every depth within '
        "`land_distance` of the coast tapered linearly to `min_depth` at the "
        'coast; `"keep"`: the land heights as negative depths, for a model that '
        "wets and dries (no `min_depth`). Giving `land` accepts a raster that "
        "puts most nodes on land",
    )
    land_distance: float | None = key(
        None,
        check=schema.length(),
        unit="length",
        doc='the width of the `"smooth"` taper (e.g. `"2 km"`); needs `min_depth`',
    )

    def _validate(self, c: Check) -> NodeDepthConfig:
        if (self.window is None) != (self.modes is None):
            raise c.error(
                "window", "give window and modes together (PCA of the raster)"
            )
        if (
            self.modes is not None
            and self.window is not None
            and self.modes > self.window**2
        ):
            raise c.error("modes", f"= {self.modes} is more than window**2")
        if self.land == "keep" and self.min_depth is not None:
            raise c.error(
                "min_depth",
                "would raise the land heights that land = 'keep' keeps for wetting "
                "and drying: give one of the two",
            )
        if self.land == "smooth" and (
            self.min_depth is None or self.land_distance is None
        ):
            raise c.error(
                "land",
                "= 'smooth' tapers the depth to min_depth at the coast over "
                "land_distance: give both",
            )
        return super()._validate(c)


@dataclass(frozen=True)
class CleanupConfig:
    """``[cleanup]``: fixes after meshing (:mod:`coastmesh.meshing.cleanup`)."""

    enabled: bool = key(
        True,
        check=schema.boolean,
        doc="run the cleanup at all (and the holding of `[[mesh_size.fields]]` "
        "sizes after it)",
    )
    boundary_triangles: bool = key(
        True,
        check=schema.boolean,
        doc="remove triangles whose three nodes are all on the boundary (they "
        "destabilise SCHISM, ADCIRC and SWAN). Each is fixed by flipping an "
        "interior edge, by splitting that edge (a new node joined to both "
        "opposite corners), or by splitting the triangle at its centroid, "
        "whichever leaves the larger minimum angle. A triangle is left in place, "
        "and counted, if every option would drop below `min_angle / 2`",
    )
    max_valence: int | None = key(
        None,
        check=schema.integer(4),
        doc="the most triangles allowed at an interior node; edges are flipped "
        "away from busier nodes",
    )
    min_angle: float = key(
        20.0,
        check=schema.number,
        doc="triangles with a smaller minimum angle (degrees, on the Earth) are "
        "slivers; the edge opposite the widest angle is flipped, else split, when "
        "that helps",
    )
    smooth: bool = key(
        True,
        check=schema.boolean,
        doc="after the flips and splits, move interior nodes up the gradient of "
        "their smallest angle (boundary nodes stay; a move is kept only if no "
        "angle of its triangles falls below the node's old worst or the mesh's "
        "1st percentile)",
    )
    time_step: bool = key(
        True,
        check=schema.boolean,
        doc="with `[bathymetry]`: relieve the few elements that throttle an "
        "explicit model. An element whose stable time step `r_in / (sqrt(g d) + "
        "u)` is under 0.65 of the 1st-percentile element's loses its shortest "
        "edge that can go: the edge is collapsed when every new angle stays at "
        "least min(30 deg, the old smallest) and the local time step rises. "
        "A collapse moves no boundary node; one may go along the boundary (into "
        "its neighbour there) where it lies within 0.15 x the new edge's length "
        "of it, so the coast moves by at most that (15 m for a 100 m edge); an "
        "open boundary keeps its own nodes, and no boundary id loses its last "
        "edge. An element still throttling then has a node moved: one inside "
        "to where the smallest time step of its elements is largest, or a "
        "shoreline node slid once along its coast, within the same 0.15 x. "
        "Kept only if the mesh's time step rises and "
        "its minimum angle and 1st percentile do not fall; `report.json` has "
        "`time_step` with the counts and ratios before and after",
    )

    def _validate(self, c: Check) -> CleanupConfig:
        if not 0 < self.min_angle < 60:
            raise c.error(
                "min_angle", f"= {self.min_angle:g}: degrees between 0 and 60"
            )
        return self


def _parts(value: object, key: str) -> int | str:
    """``[mesh] parts``: "auto" or an integer >= 1."""
    if value == "auto":
        return value
    if isinstance(value, bool) or not isinstance(value, int) or value < 1:
        raise ConfigError(f'{key} = {value!r}: expected "auto" or an integer >= 1')
    return value


@dataclass(frozen=True)
class MeshConfig:
    """``[mesh]``: Gmsh's options, the CRSs, the parts the water is cut into."""

    crs: str | None = key(
        None,
        check=schema.crs,
        default_doc="UTM zone of the domain, or an oblique stereographic "
        "projection for domains wider than 6 deg",
        doc="the conformal projection meshed in; sizes are corrected by its "
        "scale factor",
    )
    output_crs: str | None = key(
        None,
        check=schema.crs,
        default_doc="the case CRS",
        doc="CRS of the written coordinates (the paper: EPSG:4326)",
    )
    seed: int = key(
        0,
        check=schema.integer(0),
        doc="Gmsh's random seed: the same input and seed give the same mesh",
    )
    algorithm: str = key(
        "frontal-delaunay",
        check=schema.choice(tuple(ALGORITHMS)),
        doc='or `"delaunay"`, `"meshadapt"`, `"automatic"`',
    )
    optimize: bool = key(True, check=schema.boolean, doc="Gmsh's Relocate2D smoothing")
    parts: int | str = key(
        "auto",
        check=_parts,
        doc="cut the water into this many parts of equal expected triangle count, "
        "each meshed alone, at once on the run's workers or on a Dask cluster "
        "(`[run]`). The boundary nodes are made once for the whole boundary and "
        "each cut is discretised once, so the parts share their nodes: one "
        "conforming mesh, no duplicate nodes; cuts are not boundaries and carry no "
        'id. `"auto"`: one part per 200,000 expected triangles, to the nearest '
        "power of two (1 to 64; a case of under 283,000 is one part). The mesh "
        "depends on the case and `parts` only, "
        "never on `--workers` or the cluster. Fewer parts are made where no clean "
        "cut exists (a number warns whenever a cut it asks for is not made, even "
        "if cutting a large part again brings the count back up); a part left "
        "over 1.5 times its share by a cut off balance is cut again. How cuts are "
        "chosen: [meshing.md](meshing.md)",
    )


def _address(value: object, key: str) -> str:
    """``[run] scheduler``: a Dask address such as "tcp://host:8786"."""
    text = schema.string(value, key)
    if "://" not in text and ":" not in text:
        raise ConfigError(
            f"{key} = {value!r}: expected a Dask scheduler address such as "
            '"tcp://10.0.0.5:8786"'
        )
    return text


@dataclass(frozen=True)
class RunConfig:
    """``[run]``: where the work runs (never what the mesh is)."""

    workers: int | None = key(
        None,
        check=schema.integer(1),
        default_doc="every core",
        doc="the cores the run may use: local worker processes the parts are "
        "meshed and cleaned on, and the figures drawn on, each started as soon as "
        "what it shows is made; and the threads of the PCA of the shorelines, the "
        "closing of narrow water and the size terms "
        "(`coastmesh run --workers N` overrides it). `1` keeps coastmesh's own work "
        "on one core. "
        "The outputs are the same for any number",
    )
    scheduler: str | None = key(
        None,
        check=_address,
        doc='the address of a Dask distributed scheduler, e.g. `"tcp://10.0.0.5:'
        '8786"`: the parts are meshed as tasks on its workers (`coastmesh run '
        "--scheduler` overrides it). Start one with `dask scheduler` and `dask "
        "worker tcp://HOST:8786 --nthreads 1` on each machine, with the same "
        "coastmesh installed. An address that does not answer within 20 s is an "
        "error before any work",
    )


def _listed(
    value: object, key: str, known: Sequence[str], unknown: str, what: str
) -> tuple[str, ...]:
    """Names from ``known``, each once: ``unknown`` says what a name is not."""
    names = schema.names(value, key)
    for k, n in enumerate(names):
        if n not in known:
            raise ConfigError(
                f"{key}[{k}] = {n!r}: {unknown}; known: {', '.join(known)}"
            )
    if len(set(names)) != len(names):
        raise ConfigError(f"{key} = {list(names)}: a {what} is listed twice")
    return names


def _formats(value: object, key: str) -> tuple[str, ...]:
    from coastmesh.io import mesh_formats

    return _listed(value, key, list(mesh_formats()), "unknown format", "format")


def _model_tests(value: object, key: str) -> tuple[str, ...]:
    from coastmesh.io.meshes.model_tests import MODEL_TESTS

    if isinstance(value, list | tuple) and not value:
        return ()
    return _listed(value, key, MODEL_TESTS, "no smoke test for this model", "model")


# options the case sets itself, and why
_CASE_OPTIONS = {
    "positive": "it is output.positive",
    "sphere_xyz": "it is output.sphere_xyz",
    "regions": "the case writes the region files whenever the mesh has regions",
}


def _writer_options(value: object, key: str) -> dict[str, dict[str, object]]:
    from coastmesh.io import mesh_formats

    if not isinstance(value, Mapping):
        raise ConfigError(
            f"{key} = {value!r}: expected a table of formats, e.g. "
            '{ fort14 = { land = "natural" } }'
        )
    known = mesh_formats()
    out = {}
    for name, table in value.items():
        if name not in known:
            raise ConfigError(
                f"{key}.{name}: unknown format; known: {', '.join(known)}"
            )
        if not isinstance(table, Mapping):
            raise ConfigError(f"{key}.{name} = {table!r}: expected a table of options")
        takes = set(known[name].options or ())
        for option in table:
            if option in _CASE_OPTIONS or option not in takes:
                offered = sorted(takes - set(_CASE_OPTIONS))
                why = _CASE_OPTIONS.get(option, "not an option of the writer")
                raise ConfigError(
                    f"{key}.{name}.{option}: {why}; the {name} writer's options "
                    f"here: {', '.join(offered) or 'none'}"
                )
        out[name] = dict(table)
    return out


def _signs(value: object, key: str) -> dict[str, str]:
    from coastmesh.io import mesh_formats

    if not isinstance(value, Mapping):
        raise ConfigError(
            f"{key} = {value!r}: expected a table, e.g. {{ mike = 'up' }}"
        )
    known = mesh_formats()
    for name, sign in value.items():
        if name not in known:
            raise ConfigError(
                f"{key}.{name}: unknown format; known: {', '.join(known)}"
            )
        if known[name].positive is None:
            signed = [n for n, f in known.items() if f.positive is not None]
            raise ConfigError(
                f"{key}.{name}: the {name} format writes no depth; formats with "
                f"a depth sign: {', '.join(signed)}"
            )
        schema.choice(UP_DOWN)(sign, f"{key}.{name}")
    return dict(value)


@dataclass(frozen=True)
class OutputConfig:
    """``[output]``: what :meth:`coastmesh.CaseResult.write` writes."""

    formats: tuple[str, ...] = key(
        ("msh2",),
        check=_formats,
        doc="mesh formats by name, listed in [formats.md](formats.md) and by "
        "`coastmesh formats`",
    )
    positive: Mapping[str, str] | None = key(
        None,
        check=_signs,
        default_doc="each format's own",
        doc='the depth sign per format, e.g. `{ mike = "down" }`',
    )
    domain: bool = key(
        True,
        check=schema.boolean,
        doc="`domain.gpkg` with the layers `domain`, `boundaries` (name, kind, id, "
        "geodesic length), `open_boundaries_untrimmed` and `regions`",
    )
    size_field: bool = key(
        True, check=schema.boolean, doc="`size.tif`, the size grid in metres"
    )
    figures: bool = key(
        True,
        check=schema.boolean,
        doc="`figures/`: the domain, the mesh, the size field, and what else the "
        "case has (channels, parts, quality, depth, time step)",
    )
    quality: bool = key(
        True,
        check=schema.boolean,
        doc="`quality.json` and `quality.txt`: angles, radius ratios, edge "
        "lengths against the size field, valences, all-boundary triangles",
    )
    detail: tuple[float, float, float, float] | None = key(
        None, check=schema.box, doc="a detail box for a Mercator mesh figure"
    )
    sphere_xyz: bool = key(
        False,
        check=schema.boolean,
        doc="write the nodes as x, y, z on the sphere (radius 6,371,008.8 m) in "
        "the formats that hold `sphere_xyz` (`coastmesh formats`), for Fluidity "
        "and Thetis meshes of the globe",
    )
    options: Mapping[str, Mapping[str, object]] | None = key(
        None,
        check=_writer_options,
        default_doc="each writer's defaults",
        doc="writer options per format, as `coastmesh.write_mesh` takes them, e.g. "
        '`{ fort14 = { land = "natural" } }` (ADCIRC\'s natural land types, '
        "IBTYPE 20/21, in place of the essential 0/1) or `{ msh2 = { binary = true "
        "} }`; `coastmesh formats` lists each writer's options",
    )
    model_test: tuple[str, ...] = key(
        (),
        check=_model_tests,
        default_doc="none",
        doc="smoke-test run folders, `model_test/adcirc/` and `model_test/schism/`: "
        "the mesh, an M2 tide of 0.5 m on every open boundary after a 6 h ramp, "
        "ADCIRC at the mesh's own `dt` and SCHISM at a step of its own rules, "
        "Manning friction, wetting and drying, ready to run "
        "([formats.md](formats.md#smoke-tests-run-the-model-on-the-mesh)); a "
        "smoke test, not a calibrated model; regional cases only",
    )
