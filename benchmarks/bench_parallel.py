"""Meshing in parts on several processes: what it buys, stage by stage.

Builds a case in memory (nothing is written; with ``--output DIR``, runs it
end to end and writes its outputs there, as ``coastmesh run`` does) with
``--workers N`` worker processes and prints one JSON line: wall time, each
stage's time, the parts, triangles, the quality figures the decomposition must
not change, and the peak memory of this process and of the whole process tree
(this process and its workers together, sampled every 0.2 s with psutil). The
mesh is the same for any ``N`` (``[mesh] parts`` is taken from the case; ``--parts``
overrides it).

Time worker counts side by side with ``--compare``: each run is a process of
its own (this script again), the counts in turn (1, 2, 1, 2, ... for
``--compare 1,2``), so that a drift in the machine's speed falls on both
alike. Each run's wall time is measured from outside, from the start of its
process to its exit (imports included), and the ratio is taken pair by pair::

    C=examples/nw_european_shelf/fine.toml
    python benchmarks/bench_parallel.py $C --compare 1,2 --runs 2 --output /tmp/b

prints each run's JSON line (with ``wall_s``, the outside time), then a
table: per worker count the runs' wall times and their median, per pair the
ratio of the first count's time to the others', and the median ratio. With
``--output DIR`` each run writes its outputs to ``DIR/w<N>``, replaced by the
next run of that count.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import shutil
import statistics
import subprocess
import sys
import threading
import time
import warnings
from pathlib import Path

import psutil

import coastmesh
from coastmesh.cli.main import small_pages

small_pages()  # numpy's pages as `coastmesh run` has them (before numpy loads)


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
    parser.add_argument(
        "--compare",
        default=None,
        help="worker counts to run in turn, each in a process of its own: 1,2",
    )
    parser.add_argument("--runs", type=int, default=2, help="with --compare")
    args = parser.parse_args()
    if args.compare is not None:
        counts = [int(w) for w in args.compare.split(",")]
        compare(args.case, counts, args.runs, args.parts, args.output)
        return
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


def compare(
    case: str, counts: list[int], runs: int, parts: str | None, output: str | None
) -> None:
    """Run the case with each worker count in turn, ``runs`` times; print all."""
    walls: dict[int, list[float]] = {w: [] for w in counts}
    for _ in range(runs):
        for w in counts:
            command = [sys.executable, __file__, case, "--workers", str(w)]
            if parts is not None:
                command += ["--parts", parts]
            if output is not None:
                folder = Path(output) / f"w{w}"
                shutil.rmtree(folder, ignore_errors=True)
                command += ["--output", str(folder)]
            started = time.perf_counter()
            done = subprocess.run(command, check=False, capture_output=True, text=True)
            wall = time.perf_counter() - started
            if done.returncode != 0:
                sys.exit(f"{' '.join(command)} failed:\n{done.stderr[-2000:]}")
            line = json.loads(done.stdout.strip().splitlines()[-1])
            print(json.dumps({**line, "wall_s": round(wall, 2)}), flush=True)
            walls[w].append(wall)
    first = counts[0]
    print()
    print("| workers | wall s, each run | median |")
    print("|---|---|---:|")
    for w in counts:
        times = ", ".join(f"{t:.1f}" for t in walls[w])
        print(f"| {w} | {times} | {statistics.median(walls[w]):.1f} |")
    for w in counts[1:]:
        ratios = [a / b for a, b in zip(walls[first], walls[w], strict=True)]
        each = ", ".join(f"{r:.2f}" for r in ratios)
        print(
            f"\n{first} over {w} workers, pair by pair: {each}; "
            f"median {statistics.median(ratios):.2f}x; of the medians "
            f"{statistics.median(walls[first]) / statistics.median(walls[w]):.2f}x"
        )


if __name__ == "__main__":
    main()
