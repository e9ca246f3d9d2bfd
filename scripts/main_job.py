#!/usr/bin/env python3
"""Main job: build GearedRotor.fmu, simulate the default gear pair through FMPy,
write out/results.csv and PNG plots (T1, lambda = Fn, TE over time; the orbits of
both gear centres in the x-y plane after the transient) and print a summary
over whole mesh periods after the transient: mean T1, mean P_loss, efficiency
1 - <P_loss>/<P_in>, the analytic loss factor H_V and mu*H_V. Then the paper's
Fig. 3: the periodic orbit by shooting (RADAU5) and by the 4th order harmonic
approach (`cargo run --release --bin periodic`), drawn to out/fig3.png.

usage: python scripts/main_job.py [--stop-time 0.1] [--output-interval 1e-5]
                                  [--transient 0.05] [--out out] [--no-build]
                                  [--no-periodic]
"""

from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "tests"))

from helpers.fmu_harness import FMU_PATH, build_fmu  # noqa: E402

RECORD = [
    "T1", "Fn", "TE", "omega1_filtered", "omega2", "P_in", "P_loss", "P_damp", "E_in", "E_loss",
    "contact_length", "pairs_in_contact", "contact_lost",
    "u1.x", "u1.y", "u1.z", "u2.x", "u2.y", "u2.z", "gap",
]


def window_mean(t: np.ndarray, y: np.ndarray, a: float, b: float) -> float:
    """Time average of the sampled y over [a, b] (trapezoid, ends interpolated)."""
    inside = (t > a) & (t < b)
    tt = np.concatenate([[a], t[inside], [b]])
    yy = np.concatenate([[np.interp(a, t, y)], y[inside], [np.interp(b, t, y)]])
    return float(np.sum(0.5 * (yy[1:] + yy[:-1]) * np.diff(tt)) / (b - a))


def plot(out: Path, t, res, a: float, b: float, t_m: float) -> list[Path]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    files = []
    ms = 1e3 * t
    for name, label, scale in [("T1", "T1 driving torque on gear 1 [N m]", 1.0),
                               ("Fn", "lambda = Fn normal contact force [kN]", 1e-3),
                               ("TE", "TE transmission error [um]", 1e6)]:
        fig, ax = plt.subplots(figsize=(8, 3.5))
        ax.plot(ms, scale * res[name], lw=0.8)
        ax.axvspan(1e3 * a, 1e3 * b, color="0.9", zorder=0, label="averaging window")
        ax.set_xlabel("t [ms]")
        ax.set_ylabel(label)
        ax.grid(True, lw=0.3)
        ax.legend(loc="best", fontsize=8)
        fig.tight_layout()
        f = out / f"{name}.png"
        fig.savefig(f, dpi=120)
        plt.close(fig)
        files.append(f)
    sel = t >= a
    last = t >= t[-1] - 3 * t_m - 1e-12
    fig, axes = plt.subplots(1, 2, figsize=(9, 4.2))
    for ax, j in zip(axes, (1, 2)):
        x, y = 1e6 * res[f"u{j}.x"], 1e6 * res[f"u{j}.y"]
        ax.plot(x[sel], y[sel], lw=0.6, color="0.75", label=f"t >= {1e3 * a:g} ms (decaying transient)")
        ax.plot(x[last], y[last], lw=1.4, color="C0", label="last 3 mesh periods")
        ax.legend(loc="best", fontsize=7)
        ax.set_title(f"centre of gear {j}")
        ax.set_xlabel(f"u{j}x [um]")
        ax.set_ylabel(f"u{j}y [um]")
        ax.set_aspect("equal", adjustable="datalim")
        ax.grid(True, lw=0.3)
    fig.tight_layout()
    f = out / "orbits.png"
    fig.savefig(f, dpi=120)
    plt.close(fig)
    files.append(f)
    return files


def periodic_fig3(out: Path) -> dict:
    """Runs the periodic-orbit binary (shooting + harmonic approach n = 1..12, issue 5),
    draws Fig. 3 of the paper from its CSVs and returns its JSON summary."""
    pdir = out / "periodic"
    cmd = ["cargo", "run", "--release", "--quiet", "--bin", "periodic", "--", "--out", str(pdir), "--json"]
    run = subprocess.run(cmd, cwd=REPO, check=True, capture_output=True, text=True)
    summary = json.loads(run.stdout.strip().splitlines()[-1])
    import matplotlib.pyplot as plt

    orbit = np.genfromtxt(pdir / "shooting_orbit.csv", delimiter=",", names=True)
    dots = np.genfromtxt(pdir / "harmonic_orbit_n4.csv", delimiter=",", names=True)
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.8))
    for ax, j, colour in ((axes[0], 1, "tab:red"), (axes[1], 2, "tab:blue")):
        x, y = f"u{j}x", f"u{j}y"
        ax.plot(np.append(orbit[x], orbit[x][0]) * 1e6, np.append(orbit[y], orbit[y][0]) * 1e6,
                color=colour, lw=1.5, label="RADAU5 (shooting)")
        ax.plot(dots[x] * 1e6, dots[y] * 1e6, "o", color=colour, ms=4, label="harmonic approach, n = 4")
        ax.set_xlabel(f"u{j}x [um]")
        ax.set_ylabel(f"u{j}y [um]")
        ax.set_title(f"gear {j}")
        ax.set_aspect("equal", adjustable="datalim")
        ax.grid(alpha=0.3)
        ax.xaxis.set_major_locator(plt.MaxNLocator(5))
        ax.legend(fontsize=8)
    fig.suptitle("Periodic orbit of the gear centres (Jehle & Fidlin, Fig. 3)")
    fig.tight_layout()
    fig.savefig(out / "fig3.png", dpi=120)
    plt.close(fig)
    return summary


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--stop-time", type=float, default=0.1)
    ap.add_argument("--output-interval", type=float, default=1e-5)
    ap.add_argument("--transient", type=float, default=0.05,
                    help="start of the averaging window [s] (bearing transients decay like exp(-150 t))")
    ap.add_argument("--out", type=Path, default=REPO / "out")
    ap.add_argument("--fmu", type=Path, default=None, help="use this .fmu (no build)")
    ap.add_argument("--no-build", action="store_true", help="use the existing target/fmu/GearedRotor.fmu")
    ap.add_argument("--no-periodic", action="store_true", help="skip the periodic orbit (Fig. 3)")
    args = ap.parse_args()

    from fmpy import read_model_description, simulate_fmu
    from fmpy.util import write_csv

    fmu = args.fmu or (FMU_PATH if args.no_build else build_fmu(REPO))
    md = read_model_description(str(fmu))
    start = {v.name: v.start for v in md.modelVariables if v.start is not None}
    omega1, z1, mu = float(start["omega1"]), int(start["z1"]), float(start["mu"])
    t_m = 2 * math.pi / (z1 * omega1)  # mesh period (model.md 9.9)

    cpu0 = time.process_time()
    res = simulate_fmu(str(fmu), stop_time=args.stop_time, output_interval=args.output_interval,
                       output=RECORD + ["H_V"])
    cpu = time.process_time() - cpu0
    t = res["time"]

    args.out.mkdir(parents=True, exist_ok=True)
    csv = args.out / "results.csv"
    write_csv(str(csv), res)

    n = int(math.floor((t[-1] - args.transient) / t_m + 1e-9))
    if n < 1:
        print("error: no whole mesh period after the transient; raise --stop-time", file=sys.stderr)
        return 2
    a, b = args.transient, args.transient + n * t_m
    # means of powers from the energy accumulators (integrated as states, exact
    # to solver tolerance), of T1 from the samples
    e = {k: np.interp([a, b], t, res[k]) for k in ("E_in", "E_loss")}
    p_in = (e["E_in"][1] - e["E_in"][0]) / (b - a)
    p_loss = (e["E_loss"][1] - e["E_loss"][0]) / (b - a)
    t1 = window_mean(t, res["T1"], a, b)
    fn = window_mean(t, res["Fn"], a, b)
    h_v = float(res["H_V"][-1])
    files = plot(args.out, t, res, a, b, t_m)

    print(f"GearedRotor.fmu, defaults, {args.stop_time:g} s through FMPy "
          f"(output interval {args.output_interval:g} s, CPU {cpu:.2f} s)")
    print(f"averaging window       : {1e3 * a:.3f} .. {1e3 * b:.3f} ms ({n} mesh periods of {1e6 * t_m:.2f} us)")
    print(f"mean T1                : {t1:.4f} N m")
    print(f"mean Fn (lambda)       : {fn:.2f} N")
    print(f"mean P_in              : {p_in:.3f} W")
    print(f"mean P_loss            : {p_loss:.4f} W")
    print(f"efficiency             : {1 - p_loss / p_in:.6f}  (1 - <P_loss>/<P_in>)")
    print(f"H_V (analytic)         : {h_v:.6f}")
    print(f"mu*H_V                 : {mu * h_v:.6f}  vs <P_loss>/<P_in> = {p_loss / p_in:.6f}")
    print(f"wrote {csv.relative_to(REPO) if csv.is_relative_to(REPO) else csv}, "
          + ", ".join(str(f.name) for f in files))
    if not args.no_periodic:
        ps = periodic_fig3(args.out)
        dev = {h["n"]: h["max_rel_dev"] for h in ps["hb"]}
        n_1pct = min((n for n, d in dev.items() if d < 0.01), default=None)
        print(f"periodic orbit (shooting): residual {ps['shooting_residual']:.2e}, "
              f"largest Floquet multiplier {ps['floquet_max_abs']:.4f}")
        print(f"harmonic approach vs shooting: n = 4 deviation {100 * dev[4]:.3f} % of the orbit size, "
              f"n = 12 {100 * dev[12]:.3f} %, below 1 % from n = {n_1pct}")
        print("wrote fig3.png, periodic/ (CSVs, fig3.svg)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
