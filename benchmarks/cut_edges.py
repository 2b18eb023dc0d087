"""Do the cuts show in the edge-length map? Edge length over target size, by place.

Builds a case (``--workers 2``, nothing written) and prints, for the edges on
the cuts between parts, within two target sizes of a cut, within two of the
coast (away from cuts) and five or more from any cut, the median and the 5th
and 95th percentiles of edge length over the target size (lengths in the
meshing CRS, the mean of the two nodes' sizes)::

    python benchmarks/cut_edges.py examples/nw_european_shelf/intermediate.toml
"""

from __future__ import annotations

import argparse
import warnings

import numpy as np
import shapely
from pyproj import Transformer

import coastmesh
from coastmesh.meshing import default_mesh_crs


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("case")
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = coastmesh.build_case(args.case, workers=args.workers)
    mesh, parts = result.mesh, result.report.parts
    if not parts.cuts:
        print("one part: no cuts")
        return
    to_map = Transformer.from_crs(mesh.crs, default_mesh_crs(result.domain), True)
    xy = np.column_stack(to_map.transform(*mesh.points.T))
    t = mesh.triangles
    edges = np.unique(
        np.sort(np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1),
        axis=0,
    )
    length = np.hypot(*(xy[edges[:, 0]] - xy[edges[:, 1]]).T)
    size = 0.5 * (mesh.point_data["size"][edges].sum(axis=1))
    ratio = length / size
    mid = shapely.points(0.5 * (xy[edges[:, 0]] + xy[edges[:, 1]]))
    cuts = shapely.MultiLineString(
        [np.column_stack(to_map.transform(*c.T)) for c in parts.cuts]
    )
    coast = shapely.MultiLineString([xy[e] for e in mesh.boundary_edges])
    to_cut, to_coast = shapely.distance(cuts, mid), shapely.distance(coast, mid)
    groups = {
        "on the cuts": to_cut < 1e-3 * size,
        "within 2 sizes of a cut": (to_cut < 2 * size) & (to_cut >= 1e-3 * size),
        "within 2 of the coast": (to_coast < 2 * size)
        & (to_coast >= 1e-3 * size)
        & (to_cut >= 5 * size),
        "5 or more from a cut": to_cut >= 5 * size,
    }
    print(f"{parts.parts} parts, {len(parts.cuts)} pieces of cuts")
    for name, chosen in groups.items():
        r = ratio[chosen]
        print(
            f"{name:24s} {chosen.sum():8d} edges, median {np.median(r):.3f}, "
            f"p5 {np.percentile(r, 5):.3f}, p95 {np.percentile(r, 95):.3f}"
        )


if __name__ == "__main__":
    main()
