"""The outputs of a case run: model formats, domain, size field, report, figures."""

from __future__ import annotations

import json
import resource
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import shapely
from pyproj import CRS

from coastmesh.case.config import CaseConfig
from coastmesh.types import Features

__all__ = ["CaseProducts", "build_report", "write_case_copy", "write_outputs"]


@dataclass(frozen=True, slots=True)
class CaseProducts:
    """What a case run made, for :func:`write_outputs`."""

    mesh: Any
    domain: Any
    size: Any
    regions: list[Any]
    walls: list[Any]
    crs: CRS
    quality: Any = None


def build_report(
    config: CaseConfig,
    *,
    crs: CRS,
    mesh_crs: CRS,
    output_crs: CRS,
    sets: dict[str, Any],
    stitch: Any,
    domain: Any,
    size: Any,
    mesh: Any,
    edges: dict[str, int],
    after: dict[str, Any],
    timings: dict[str, float],
) -> dict[str, Any]:
    """Collect the numbers of a run into a JSON-ready dict (``report.json``)."""

    def as_dict(value: Any) -> Any:
        return None if value is None else value.to_dict()

    return {
        "case": config.name,
        "source": str(config.source),
        "crs": crs.to_string(),
        "mesh_crs": mesh_crs.to_wkt()
        if mesh_crs.to_epsg() is None
        else mesh_crs.to_string(),
        "output_crs": output_crs.to_string(),
        "shoreline_sets": sets,
        "stitch": {
            "polygons": stitch.polygons,
            "sea_slivers_filled": stitch.sea_slivers_filled,
            "land_slivers_removed": stitch.land_slivers_removed,
        },
        "domain": {
            "land_polygons": domain.land_in,
            "land_repaired": domain.land_repaired,
            "land_overlaps_merged": domain.land_overlaps_merged,
            "sea_faces": domain.sea_faces,
            "islands": domain.holes,
            "islands_dropped": domain.holes_dropped,
            "boundary_vertices": domain.segments,
        },
        "size_field": {
            "shape": list(size.shape),
            "cell_m": float(size.x[1] - size.x[0]),
            "min_m": float(size.min()),
            "max_m": float(size.max()),
        },
        "mesh": {
            "nodes": len(mesh.points),
            "triangles": len(mesh.triangles),
            "boundary_edges": edges,
            "surface_id": mesh.surface_id,
        },
        "cleanup": as_dict(after["cleanup"]),
        "quality": as_dict(after["quality"]),
        "depth": as_dict(after["depth"]),
        "seconds": timings,
        # peak resident memory of this process so far (Linux reports KiB)
        "peak_memory_mb": round(
            resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, 1
        ),
    }


def write_outputs(
    config: CaseConfig, folder: Path, products: CaseProducts, report: dict[str, Any]
) -> list[str]:
    """Write every output of a case into ``folder``; return the file names.

    Parameters
    ----------
    config : CaseConfig
        The case.
    folder : pathlib.Path
        The (partial) output folder.
    products : CaseProducts
        What the run made.
    report : dict
        The run's report (:func:`build_report`), written as ``report.json`` and
        ``summary.txt`` with the file list added.

    Returns
    -------
    list of str
        File names relative to ``folder``, in the order written.
    """
    from coastmesh import __version__

    files = _write_models(config, folder, products.mesh)
    notes = {
        "coastmesh_version": __version__,
        "case": config.name,
        "case_file": str(config.source),
    }
    if config.outputs.domain:
        _write_domain(folder / "domain.gpkg", products, notes)
        files.append("domain.gpkg")
    if config.outputs.size_field:
        from coastmesh.io import write_raster

        write_raster(folder / "size.tif", products.size)
        files.append("size.tif")
    if products.quality is not None:
        products.quality.write(folder / "quality.json", folder / "quality.txt")
        files += ["quality.json", "quality.txt"]
    if config.outputs.figures:
        files += _write_figures(config, folder, products)
    write_case_copy(folder, config.source, config.text)
    files.append("case.toml")
    report = report | {"files": files, "coastmesh_version": __version__}
    (folder / "report.json").write_text(json.dumps(report, indent=2) + "\n")
    files.append("report.json")
    (folder / "summary.txt").write_text(_summary_text(report), encoding="utf-8")
    files.append("summary.txt")
    return files


def write_case_copy(folder: Path, source: Path, text: str) -> None:
    """Keep the case file as run, as ``case.toml``, saying where it came from."""
    from coastmesh import __version__

    header = (
        f"# A copy of {source.resolve()}, as run by coastmesh {__version__}.\n"
        "# Its relative paths are relative to that file, not to this copy.\n"
    )
    (folder / "case.toml").write_text(header + text, encoding="utf-8")


def _write_models(config: CaseConfig, folder: Path, mesh: Any) -> list[str]:
    """Write the mesh in each format of ``[output] formats``."""
    from coastmesh.io import write_mesh
    from coastmesh.io.writers import mesh_format

    files: list[str] = []
    taken: set[str] = set()
    for name in config.outputs.formats:
        fmt = mesh_format(name)
        suffix = fmt.extensions[0]
        filename = f"{config.name}{suffix}"
        if filename in taken:
            filename = f"{config.name}-{name}{suffix}"
        taken.add(filename)
        options = {}
        if config.outputs.positive and name in config.outputs.positive:
            options["positive"] = config.outputs.positive[name]
        write_mesh(folder / filename, mesh, format=name, **options)
        files.append(filename)
        if name == "selafin":  # the boundary-conditions file written with it
            files.append(f"{Path(filename).stem}.cli")
    return files


def _write_domain(path: Path, products: CaseProducts, notes: dict[str, str]) -> None:
    """Write the domain GeoPackage, with the untrimmed boundaries and the regions."""
    from coastmesh.io import write_domain

    walls, regions, crs = products.walls, products.regions, products.crs
    extra = {}
    if walls:
        extra["open_boundaries_untrimmed"] = Features(
            np.array([shapely.LineString(w.coords) for w in walls], dtype=object),
            crs,
            {
                "name": np.array([w.name for w in walls], dtype=object),
                "physical_id": np.array([w.physical_id for w in walls]),
            },
            np.arange(len(walls)),
            "<memory>",
        )
    used = [(n, i, r) for n, i, r in regions if r is not None]
    if used:
        extra["regions"] = Features(
            np.array([r for _, _, r in used], dtype=object),
            crs,
            {
                "shoreline_set": np.array([n for n, _, _ in used], dtype=object),
                "physical_id": np.array([i for _, i, _ in used]),
            },
            np.arange(len(used)),
            "<memory>",
        )
    write_domain(path, products.domain, metadata=notes, extra_layers=extra)


def _write_figures(
    config: CaseConfig, folder: Path, products: CaseProducts
) -> list[str]:
    """Draw the domain, mesh, size, quality and depth figures into figures/."""
    from coastmesh.plot import mesh as plot_mesh
    from coastmesh.plot import quality as plot_quality
    from coastmesh.plot import save_figure

    mesh, name = products.mesh, config.name
    names = {s.physical_id: s.name for s in products.domain.segments}
    figures = [
        (
            "domain",
            lambda: plot_mesh.domain_figure(products.domain, title=f"{name}: domain"),
        ),
        ("mesh", lambda: plot_mesh.mesh_figure(mesh, names=names, title=name)),
        (
            "size",
            lambda: plot_mesh.size_figure(products.size, title=f"{name}: element size"),
        ),
    ]
    if products.quality is not None:
        figures.append(
            (
                "quality",
                lambda: plot_quality.quality_figure(
                    mesh, products.quality, title=f"{name}: element quality"
                ),
            )
        )
    if "depth" in mesh.point_data:
        figures.append(
            ("depth", lambda: plot_quality.depth_figure(mesh, title=f"{name}: depth"))
        )
    if config.outputs.detail is not None:
        figures.append(
            (
                "mesh_mercator",
                lambda: plot_mesh.mercator_figure(
                    mesh, detail=config.outputs.detail, names=names, title=name
                ),
            )
        )
    (folder / "figures").mkdir()
    files = []
    for stem, draw in figures:
        save_figure(draw(), folder / "figures" / f"{stem}.png")
        files.append(f"figures/{stem}.png")
    return files


def _summary_text(report: dict[str, Any]) -> str:
    mesh = report["mesh"]
    lines = [
        f"coastmesh case {report['case']} ({report['source']})",
        f"mesh: {mesh['nodes']:,} nodes, {mesh['triangles']:,} triangles",
        "boundary edges by name (id): "
        + ", ".join(f"{k} {v}" for k, v in mesh["boundary_edges"].items()),
        f"surface id: {mesh['surface_id']}",
        "shoreline sets:",
    ]
    for name, r in report["shoreline_sets"].items():
        lines.append(
            f"  {name}: {r['kind']}, {r['polygons']} polygons "
            f"({r['polygons_below_min_area']} islands and {r['lakes_below_min_area']} "
            f"lakes below min_area dropped), {r['points_out']:,} points"
        )
    d = report["domain"]
    lines.append(
        f"domain: {d['islands']} islands ({d['islands_dropped']} dropped), "
        f"{d['land_repaired']} land polygons repaired, {d['land_overlaps_merged']} "
        "overlaps merged"
    )
    s = report["size_field"]
    lines.append(
        f"size field: {s['shape'][1]} x {s['shape'][0]} cells of {s['cell_m']:.0f} m, "
        f"{s['min_m']:.0f} to {s['max_m']:.0f} m"
    )
    if report.get("cleanup"):
        c = report["cleanup"]
        lines.append(
            f"cleanup: all-boundary triangles {c['boundary_triangles_before']} -> "
            f"{c['boundary_triangles_after']}, max valence {c['max_valence_before']} "
            f"-> {c['max_valence_after']}, min angle {c['min_angle_before']:.1f} -> "
            f"{c['min_angle_after']:.1f} deg"
        )
    if report.get("depth"):
        d = report["depth"]
        lines.append(
            f"depth: {d['min']:.1f} to {d['max']:.1f} m (positive down); "
            f"{d['nearest']} nodes from the nearest valid cell, "
            f"{d['below_min_depth']} raised to the minimum depth"
        )
    lines.append(
        "time (s): " + ", ".join(f"{k} {v}" for k, v in report["seconds"].items())
    )
    lines.append("files: " + ", ".join(report["files"]))
    return "\n".join(lines) + "\n"
