"""Meshing in parts on several processes: what it buys, stage by stage.

Builds a case in memory (nothing is written; with ``--output DIR``, runs it
end to end and writes its outputs there, as ``coastmesh run`` does) with
``--workers N`` worker processes and prints one JSON line: wall time, each
stage's time, the parts, triangles, the quality figures the decomposition must
not change, and the peak memory of this process and of the whole process tree
(this process and its workers together, sampled every 0.2 s with psutil). The
mesh is the same for any ``N`` (``[mesh] parts`` is taken from the case; ``--parts``
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
import threading
import time
import warnings

import psutil

import coastmesh


class TreeMemory:
    """The largest total resident memory of this process and its children."""

    def __init__(self, every: float = 0.2) -> None:
        self.peak, self.every = 0, every
        self.stop = threading.Event()
        self.thread = threading.Thread(target=self._watch, daemon=True)

    def _watch(self) -> None:
        me = psutil.Process()
        while not self.stop.is_set():
            total = 0
            for p in [me, *me.children(recursive=True)]:
                try:
                    total += p.memory_info().rss
                except psutil.Error:
                    pass  # a worker that just ended
            self.peak = max(self.peak, total)
            self.stop.wait(self.every)

    def __enter__(self) -> TreeMemory:
        self.thread.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop.set()
        self.thread.join()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("case")
    parser.add_argument("--workers", type=int, default=None)
    parser.add_argument("--parts", default=None, help='"auto" or a count')
    parser.add_argument("--output", default=None, help="write the outputs here")
    args = parser.parse_args()
    case = coastmesh.read_case(args.case)
    if args.parts is not None:
        parts = args.parts if args.parts == "auto" else int(args.parts)
        case = dataclasses.replace(
            case, mesh=dataclasses.replace(case.mesh, parts=parts)
        )
    started = time.perf_counter()
    with warnings.catch_warnings(), TreeMemory() as tree:
        warnings.simplefilter("ignore")
        if args.output is None:
            result = coastmesh.build_case(case, workers=args.workers)
        else:
            result = coastmesh.run_case(
                case, output=args.output, workers=args.workers, overwrite=True
            )
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
                "peak_tree_mb": round(tree.peak / 2**20),
                "cleanup": None
                if result.report.cleanup is None
                else result.report.cleanup.summary(),
            }
        )
    )


if __name__ == "__main__":
    main()
