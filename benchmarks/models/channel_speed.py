"""Is a strait's peak speed in a SCHISM or ADCIRC run the tide's, or the mesh's?

A tidal current through a strait is driven by the difference in sea level
between its two ends. Where friction holds it back (a long, shallow strait),
Manning's law for a wide channel gives the speed that head drives::

    u = sqrt(g h |eta_a - eta_b| / (L Cd)),   Cd = max(g n^2 / h^(1/3), Cd_min)

(``u = h^(2/3) sqrt(|eta_a - eta_b| / L) / n`` where the floor ``Cd_min`` does
not bite), with ``h`` the water depth at the node (depth plus elevation),
``L`` the distance between the two ends, ``n`` Manning's coefficient and
``Cd_min`` the smoke tests' floor on the drag (0.0025). Inertia only
lowers the speed below this, so a model speed of the same size, following
the head from one half-cycle to the next, is the tide's; a speed far above
it, or one that grows while the head does not, is a fault of the mesh or the
run. (The current lags the head, as a strait's flow does, so each half-cycle's
peak is compared, not each output.) The slope is the mean over ``L``: where
the strait narrows, the flow speeds up and the slope there is steeper, so the
node at a narrows can run somewhat faster than the estimate.

This reads SCHISM's ``outputs/out2d_1.nc`` (elevation and depth-averaged
velocity at every output), or ADCIRC's ``fort.14``, ``fort.63`` and ``fort.64``
(ASCII, full format, as the smoke test writes them: every 30 min), and
prints, for the node nearest ``--at``, the model's largest speed in each
half-cycle (between the slack waters) beside the estimate's::

    python benchmarks/models/channel_speed.py runs/models/intermediate/schism-now \\
        --at -3.029 58.642 --ends -3.47 58.72 -2.86 58.69

(the Pentland Firth's Inner Sound, between the Atlantic and the North Sea
ends of the Firth, on the NW shelf's intermediate mesh). An ADCIRC run folder
(with ``fort.63``) is read the same way; its 30 min outputs can miss a peak
by a little, so compare its half-cycles with ``maxvel.63`` too.
"""

from __future__ import annotations

import argparse
import itertools
from pathlib import Path

import numpy as np
import xarray as xr
from pyproj import Geod


def nearest(x: np.ndarray, y: np.ndarray, lon: float, lat: float) -> int:
    """The node nearest (lon, lat), by distance on the ellipsoid."""
    _, _, d = Geod(ellps="WGS84").inv(np.full_like(x, lon), np.full_like(y, lat), x, y)
    return int(np.argmin(d))


def read_schism(run: Path) -> tuple[np.ndarray, ...]:
    """x, y, depth, model hours, elevation and speed (time by node) of SCHISM."""
    with xr.open_dataset(run / "outputs" / "out2d_1.nc") as ds:
        x = ds["SCHISM_hgrid_node_x"].values
        y = ds["SCHISM_hgrid_node_y"].values
        eta = ds["elevation"].values
        speed = np.hypot(ds["depthAverageVelX"].values, ds["depthAverageVelY"].values)
        depth = ds["depth"].values
        hours = (ds["time"].values - ds["time"].values[0]) / np.timedelta64(1, "h")
        hours += hours[1] - hours[0] if len(hours) > 1 else 0.0
    return x, y, depth, hours, eta, speed


def _records(path: Path, columns: int) -> tuple[np.ndarray, np.ndarray]:
    """The times and values (time by node by column) of an ASCII full-format
    ADCIRC global output: a title line, a line of counts, then for each
    record a line "time step" and one line "node value..." per node."""
    with path.open() as f:
        f.readline()
        sets, nodes = (int(v) for v in f.readline().split()[:2])
        times, values = [], []
        for _ in range(sets):
            line = f.readline()
            if not line.strip():
                break
            block = np.loadtxt(f, max_rows=nodes, ndmin=2)
            if len(block) < nodes:  # a run still writing it
                break
            times.append(float(line.split()[0]))
            values.append(block[:, 1 : 1 + columns])
    data = np.asarray(values)
    data[data < -99998.0] = np.nan  # -99999: a dry node
    return np.asarray(times), data


def read_adcirc(run: Path) -> tuple[np.ndarray, ...]:
    """x, y, depth, model hours, elevation and speed (time by node) of ADCIRC."""
    with (run / "fort.14").open() as f:
        f.readline()
        _, nodes = (int(v) for v in f.readline().split()[:2])
        table = np.loadtxt(f, max_rows=nodes, ndmin=2)
    times, eta = _records(run / "fort.63", 1)
    _, uv = _records(run / "fort.64", 2)
    speed = np.hypot(uv[..., 0], uv[..., 1])
    x, y, depth = table[:, 1], table[:, 2], table[:, 3]
    return x, y, depth, times / 3600.0, eta[..., 0], speed


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument(
        "run", type=Path, help="a SCHISM run folder (with outputs/) or an ADCIRC one"
    )
    p.add_argument("--at", nargs=2, type=float, required=True, metavar=("LON", "LAT"))
    p.add_argument(
        "--ends",
        nargs=4,
        type=float,
        required=True,
        metavar=("LON_A", "LAT_A", "LON_B", "LAT_B"),
    )
    p.add_argument("--manning", type=float, default=0.025)
    p.add_argument(
        "--min-drag",
        type=float,
        default=0.0025,
        help="the floor on the drag coefficient (the smoke tests': 0.0025; 0: none)",
    )
    args = p.parse_args()
    read = read_adcirc if (args.run / "fort.63").exists() else read_schism
    x, y, depth, hours, eta, speed = read(args.run)
    eta, speed = np.nan_to_num(eta), np.nan_to_num(speed)
    k = nearest(x, y, *args.at)
    a = nearest(x, y, *args.ends[:2])
    b = nearest(x, y, *args.ends[2:])
    _, _, length = Geod(ellps="WGS84").inv(x[a], y[a], x[b], y[b])
    head = eta[:, a] - eta[:, b]
    h = depth[k] + eta[:, k]
    drag = np.maximum(9.81 * args.manning**2 / np.cbrt(h), args.min_drag)
    estimate = np.sqrt(9.81 * h * np.abs(head) / (length * drag))
    print(
        f"node {k + 1} at {x[k]:.4f}, {y[k]:.4f}, {depth[k]:.1f} m deep; ends: node "
        f"{a + 1} ({x[a]:.3f}, {y[a]:.3f}) and node {b + 1} ({x[b]:.3f}, "
        f"{y[b]:.3f}), {length / 1000:.1f} km apart; n = {args.manning:g}, "
        f"Cd >= {args.min_drag:g}"
    )
    # slack waters: the local minima of the speed; half-cycles lie between
    s = speed[:, k]
    slack = [0]
    slack += [i for i in range(1, len(s) - 1) if s[i] <= s[i - 1] and s[i] < s[i + 1]]
    slack.append(len(s))
    print(
        "| half-cycle (model h) | largest head (m) | largest speed (m/s) "
        "| Manning estimate (m/s) |"
    )
    print("|---|---:|---:|---:|")
    for lo, hi in itertools.pairwise(slack):
        j = lo + int(np.argmax(np.abs(head[lo:hi])))
        print(
            f"| {hours[lo]:.1f}-{hours[hi - 1]:.1f} | {head[j]:+.2f} "
            f"| {s[lo:hi].max():.2f} | {estimate[lo:hi].max():.2f} |"
        )


if __name__ == "__main__":
    main()
