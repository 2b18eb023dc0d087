"""Meshing in parts on several threads: what it buys, stage by stage.

Builds a case in memory (nothing is written) with ``--workers N`` Gmsh threads
and prints one JSON line: wall time, each stage's time, the parts, triangles
and the quality figures the decomposition must not change. The mesh is the
same for any ``N`` (``[mesh] parts`` is taken from the case; ``--parts``
overrides it). Time two worker counts side by side with farm-bench::

    C=examples/nw_european_shelf/intermediate.toml
    farm-bench -n 3 --warmup 0 --timeout 1400 \\
        --vs "python benchmarks/bench_parallel.py $C --workers 1" -- \\
        python benchmarks/bench_parallel.py $C --workers 2
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import time
import warnings

import coastmesh


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("case")
    parser.add_argument("--workers", type=int, default=None)
    parser.add_argument("--parts", default=None, help='"auto" or a count')
    args = parser.parse_args()
    case = coastmesh.read_case(args.case)
    if args.parts is not None:
        parts = args.parts if args.parts == "auto" else int(args.parts)
        case = dataclasses.replace(
            case, mesh=dataclasses.replace(case.mesh, parts=parts)
        )
    started = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = coastmesh.build_case(case, workers=args.workers)
    q = result.report.quality
    print(
        json.dumps(
            {
                "case": result.name,
                "workers": args.workers,
                "parts": result.report.parts.to_dict(),
                "seconds": round(time.perf_counter() - started, 2),
                "stage_seconds": result.report.seconds,
                "triangles": q.triangles,
                "min_angle_p1": round(q.min_angle.p1, 2),
                "radius_ratio_min": round(q.radius_ratio.min, 3),
                "peak_memory_mb": result.report.peak_memory_mb,
                "cleanup": None
                if result.report.cleanup is None
                else result.report.cleanup.summary(),
            }
        )
    )


if __name__ == "__main__":
    main()
