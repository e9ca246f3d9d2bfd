#!/usr/bin/env python3
"""Main job: build GearedRotor.fmu, simulate a gear pair through FMPy (the defaults,
or any parameter and input changed with --set NAME=VALUE[unit]), write out/results.csv
and the figures, and print a steady-state summary over whole mesh periods: mean T1,
mean Fn, mean P_loss, efficiency 1 - <P_loss>/<P_in>, the analytic loss factor H_V and
mu*H_V. Every figure title names the case (pair, speed, load, mu).

Figures in out/: T1.png, Fn.png, TE.png (over the whole run), steady.png (T1, Fn, TE
over the last mesh periods), spectrum.png (order spectrum of TE and Fn over the
steady window, in orders of the mesh frequency), orbits.png (the gear centres in the
x-y plane). Then the paper's Fig. 3: the periodic orbit by shooting (RADAU5) and by
the 4th order harmonic approach (`cargo run --release --bin periodic`), out/fig3.png.

Steady state: if the FMU has the parameter `initialization` (3 = start on the periodic
orbit), the run starts there and the whole run is steady; otherwise the run starts
from rest and the first --transient seconds are cut.

examples:
  python scripts/main_job.py --set omega1=1500rpm --set beta=15deg --set mu=0.1
  python scripts/main_job.py --set T_load=50 --set k1.x=150N/um --no-periodic
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

sys.path.insert(0, str(REPO / "scripts"))
from case_values import SetError, parse_set  # noqa: E402

MICRO = "\u00b5m"
PERIODIC_INIT = 3  # value of the Enumeration parameter `initialization`: periodic orbit

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


def steady_plan(names: set, sets: dict) -> tuple[dict, bool]:
    """Start values of the run and whether it starts on the periodic orbit: with the
    parameter `initialization` in the FMU (and not set by the user) the run starts on the
    periodic orbit (value 3); a user's value is kept; without it the run starts from rest
    and the transient is cut."""
    start_values = dict(sets)
    if "initialization" in names and "initialization" not in sets:
        start_values["initialization"] = PERIODIC_INIT
    return start_values, start_values.get("initialization") == PERIODIC_INIT


def case_title(v: dict) -> str:
    """The case in one line: pair, helix, speed, load, friction."""
    beta = math.degrees(v["beta"])
    return (f"z1/z2 = {v['z1']}/{v['z2']}, m_n = {1e3 * v['m_n']:g} mm, beta = {beta:g} deg, "
            f"{v['omega1'] * 30 / math.pi:g} rpm, T_load = {v['T_load']:g} N m, mu = {v['mu']:g}")


def plot(out: Path, t, res, a: float, b: float, t_m: float, title: str, steady_from_start: bool) -> list[Path]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    files = []
    ms = 1e3 * t
    series = [("T1", "T1 driving torque on gear 1 [N m]", 1.0),
              ("Fn", "Fn normal tooth force [kN]", 1e-3),
              ("TE", f"TE transmission error [{MICRO}]", 1e6)]
    for name, label, scale in series:
        fig, ax = plt.subplots(figsize=(8, 3.8))
        ax.plot(ms, scale * res[name], lw=0.8)
        ax.axvspan(1e3 * a, 1e3 * b, color="0.9", zorder=0, label="steady window (whole mesh periods)")
        ax.set_xlabel("t [ms]")
        ax.set_ylabel(label)
        ax.set_title(title, fontsize=9)
        ax.grid(True, lw=0.3)
        ax.legend(loc="best", fontsize=8)
        fig.tight_layout()
        f = out / f"{name}.png"
        fig.savefig(f, dpi=120)
        plt.close(fig)
        files.append(f)

    # steady state over the last few mesh periods, against time in mesh periods
    k = 4
    last = (t >= b - k * t_m - 1e-12) & (t <= b + 1e-12)
    fig, axes = plt.subplots(3, 1, figsize=(8, 7.5), sharex=True)
    for ax, (name, label, scale) in zip(axes, series):
        ax.plot((t[last] - (b - k * t_m)) / t_m, scale * res[name][last], lw=1.2)
        ax.ticklabel_format(axis="y", useOffset=False)
        ax.set_ylabel(label, fontsize=8)
        ax.grid(True, lw=0.3)
    axes[-1].set_xlabel(f"t / T_m (mesh period T_m = {1e6 * t_m:.1f} {chr(0xb5)}s), last {k} periods of the window")
    how = "run started on the periodic orbit" if steady_from_start else f"after the transient ({1e3 * a:g} ms)"
    axes[0].set_title(f"Steady state, {how}\n{title}", fontsize=9)
    fig.tight_layout()
    f = out / "steady.png"
    fig.savefig(f, dpi=120)
    plt.close(fig)
    files.append(f)

    # order spectrum over the steady window: resample whole periods uniformly
    n_per = max(1, int(round((b - a) / t_m)))
    m = 64 * n_per
    grid = a + (b - a) * np.arange(m) / m
    fig, axes = plt.subplots(2, 1, figsize=(8, 6))
    for ax, (name, label, scale) in zip(axes, [series[2], ("Fn", "Fn [N]", 1.0)]):
        y = scale * np.interp(grid, t, res[name])
        amp = np.abs(np.fft.rfft(y)) / m
        amp[1:] *= 2
        order = np.arange(len(amp)) / n_per
        keep = (order > 0) & (order <= 12)
        ax.vlines(order[keep], 0, amp[keep], lw=1.5)
        ax.set_xlim(0, 12.5)
        ax.set_xticks(range(0, 13))
        unit = MICRO if name == "TE" else "N"
        ax.set_ylabel(f"{name} amplitude [{unit}]")
        ax.grid(True, lw=0.3)
        ax.text(0.99, 0.9, f"mean {y.mean():.4g} {unit}", transform=ax.transAxes, ha="right", fontsize=8)
    axes[-1].set_xlabel(f"order (multiples of the mesh frequency {1 / t_m:.1f} Hz); "
                        f"window {n_per} mesh periods, resolution 1/{n_per} order")
    note = "" if steady_from_start else "; lines between the orders: the bearing vibration still decaying"
    axes[0].set_title(f"Order spectrum of TE and Fn (amplitudes; mean values in the corner{note})\n{title}",
                      fontsize=9)
    fig.tight_layout()
    f = out / "spectrum.png"
    fig.savefig(f, dpi=120)
    plt.close(fig)
    files.append(f)

    sel = t >= a
    last3 = t >= b - 3 * t_m - 1e-12
    fig, axes = plt.subplots(1, 2, figsize=(9, 4.6))
    for ax, j in zip(axes, (1, 2)):
        x, y = 1e6 * res[f"u{j}.x"], 1e6 * res[f"u{j}.y"]
        ax.plot(x[sel], y[sel], lw=0.6, color="0.75", label=f"t >= {1e3 * a:g} ms")
        ax.plot(x[last3], y[last3], lw=1.4, color="C0", label="last 3 mesh periods")
        ax.legend(loc="best", fontsize=7)
        ax.set_title(f"centre of gear {j}")
        ax.set_xlabel(f"u{j}x [{MICRO}]")
        ax.set_ylabel(f"u{j}y [{MICRO}]")
        ax.set_aspect("equal", adjustable="datalim")
        ax.grid(True, lw=0.3)
    fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    f = out / "orbits.png"
    fig.savefig(f, dpi=120)
    plt.close(fig)
    files.append(f)
    return files


# parameters the periodic binary takes in its --params file (src/bin/periodic.rs)
PERIODIC_PARAMS = {"z1", "z2", "m_n", "alpha_n", "beta", "b", "x1", "x2", "h_aP", "a_w_set", "psi0",
                   "m1", "J1", "m2", "J2", "d_phi", "mu", "omega1_filter_frequency"} | {
    f"{v}.{ax}" for v in ("k1", "d1", "k2", "d2") for ax in "xyz"}


def periodic_fig3(out: Path, sets: dict, title: str) -> tuple[dict, list[str]]:
    """Runs the periodic-orbit binary (shooting + harmonic approach n = 1..12) for the case,
    draws Fig. 3 of the paper from its CSVs and returns its JSON summary and the --set
    names it could not take."""
    pdir = out / "periodic"
    pdir.mkdir(parents=True, exist_ok=True)
    cmd = ["cargo", "run", "--release", "--quiet", "--bin", "periodic", "--", "--out", str(pdir), "--json"]
    unused = [k for k in sets if k not in PERIODIC_PARAMS and k != "omega1"]
    params = {k: v for k, v in sets.items() if k in PERIODIC_PARAMS}
    if params:
        f = pdir / "params.txt"
        f.write_text("".join(f"{k} = {float(v)!r}\n" for k, v in params.items()))
        cmd += ["--params", str(f)]
    if "omega1" in sets:
        cmd += ["--omega1", repr(float(sets["omega1"]))]
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
        ax.set_xlabel(f"u{j}x [{MICRO}]")
        ax.set_ylabel(f"u{j}y [{MICRO}]")
        ax.set_title(f"gear {j}")
        ax.set_aspect("equal", adjustable="datalim")
        ax.grid(alpha=0.3)
        ax.xaxis.set_major_locator(plt.MaxNLocator(5))
        ax.legend(fontsize=8)
    fig.suptitle(f"Periodic orbit of the gear centres (Jehle & Fidlin, Fig. 3)\n{title}", fontsize=10)
    fig.tight_layout()
    fig.savefig(out / "fig3.png", dpi=120)
    plt.close(fig)
    return summary, unused


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--set", action="append", default=[], metavar="NAME=VALUE[unit]",
                    help="set a parameter or input, e.g. omega1=1500rpm, beta=15deg, mu=0.1, "
                         "k1.x=150N/um (units: the variable's unit or a declared display unit)")
    ap.add_argument("--stop-time", type=float, default=None,
                    help="end of the run [s] (default 0.1 from rest; 30 mesh periods on the periodic orbit)")
    ap.add_argument("--output-interval", type=float, default=1e-5)
    ap.add_argument("--transient", type=float, default=0.05,
                    help="start of the steady window [s] for a run from rest "
                         "(bearing transients decay like exp(-150 t))")
    ap.add_argument("--out", type=Path, default=REPO / "out")
    ap.add_argument("--fmu", type=Path, default=None, help="use this .fmu (no build)")
    ap.add_argument("--no-build", action="store_true", help="use the existing target/fmu/GearedRotor.fmu")
    ap.add_argument("--no-periodic", action="store_true", help="skip the periodic orbit (Fig. 3)")
    args = ap.parse_args()

    from fmpy import read_model_description, simulate_fmu
    from fmpy.util import write_csv

    fmu = args.fmu or (FMU_PATH if args.no_build else build_fmu(REPO))
    md = read_model_description(str(fmu))
    try:
        sets = dict(parse_set(md, s) for s in args.set)
    except SetError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    names = {v.name for v in md.modelVariables}
    start_values, steady_from_start = steady_plan(names, sets)

    def value(name):
        if name in sets:
            return sets[name]
        v = next(v for v in md.modelVariables if v.name == name)
        return int(v.start) if v.type in ("Integer", "Enumeration") else float(v.start)

    case = {n: value(n) for n in ("z1", "z2", "m_n", "beta", "omega1", "T_load", "mu")}
    title = case_title(case)
    others = [f"{k} = {v:g}" for k, v in sets.items() if k not in case and not isinstance(v, bool)]
    if others:
        title += "; " + ", ".join(others)
    t_m = 2 * math.pi / (case["z1"] * case["omega1"])  # mesh period, docs/model.md (9.4)
    stop = args.stop_time or (30 * t_m if steady_from_start else 0.1)
    transient = 0.0 if steady_from_start else args.transient

    cpu0 = time.process_time()
    try:
        res = simulate_fmu(str(fmu), stop_time=stop, output_interval=args.output_interval,
                           start_values=start_values, output=RECORD + ["H_V"])
    except Exception as e:  # FMPy raises FMICallException; the FMU's message is logged above
        print(f"error: the simulation of this case stopped ({e}); the FMU's message above says "
              "why and which parameter to change", file=sys.stderr)
        return 1
    cpu = time.process_time() - cpu0
    t = res["time"]

    args.out.mkdir(parents=True, exist_ok=True)
    csv = args.out / "results.csv"
    write_csv(str(csv), res)

    n = int(math.floor((t[-1] - transient) / t_m + 1e-9))
    if n < 1:
        print("error: no whole mesh period after the transient; raise --stop-time", file=sys.stderr)
        return 2
    a, b = transient, transient + n * t_m
    # means of powers from the energy accumulators (integrated as states, exact
    # to solver tolerance), of T1 from the samples
    e = {k: np.interp([a, b], t, res[k]) for k in ("E_in", "E_loss")}
    p_in = (e["E_in"][1] - e["E_in"][0]) / (b - a)
    p_loss = (e["E_loss"][1] - e["E_loss"][0]) / (b - a)
    t1 = window_mean(t, res["T1"], a, b)
    fn = window_mean(t, res["Fn"], a, b)
    h_v = float(res["H_V"][-1])
    files = plot(args.out, t, res, a, b, t_m, title, steady_from_start)

    changed = ", ".join(f"{k} = {v:g}" if not isinstance(v, bool) else f"{k} = {v}" for k, v in sets.items())
    print(f"GearedRotor.fmu, {changed or 'defaults'}; {stop:g} s through FMPy "
          f"(output interval {args.output_interval:g} s, CPU {cpu:.2f} s)")
    print(f"case                   : {title}")
    start_how = ("on the periodic orbit (initialization = 3)" if steady_from_start
                 else "from rest; transient cut" if "initialization" not in names
                 else f"with initialization = {value('initialization')}; transient cut")
    print(f"start                  : {start_how}")
    print(f"steady window          : {1e3 * a:.3f} .. {1e3 * b:.3f} ms ({n} mesh periods of {1e6 * t_m:.2f} {chr(0xb5)}s)")
    print(f"mean T1                : {t1:.4f} N m")
    print(f"mean Fn (lambda)       : {fn:.2f} N")
    print(f"T1 ripple (max - min)  : {np.ptp(res['T1'][(t >= a) & (t <= b)]):.4f} N m")
    print(f"mean P_in              : {p_in:.3f} W")
    print(f"mean P_loss            : {p_loss:.4f} W")
    print(f"efficiency             : {1 - p_loss / p_in:.6f}  (1 - <P_loss>/<P_in>)")
    print(f"H_V (analytic)         : {h_v:.6f}")
    print(f"mu*H_V                 : {case['mu'] * h_v:.6f}  vs <P_loss>/<P_in> = {p_loss / p_in:.6f}")
    print(f"wrote {csv.relative_to(REPO) if csv.is_relative_to(REPO) else csv}, "
          + ", ".join(str(f.name) for f in files))
    if not args.no_periodic:
        ps, unused = periodic_fig3(args.out, sets, title)
        if unused:
            print(f"periodic orbit (Fig. 3): without {', '.join(unused)} (the periodic binary "
                  "does not take them)")
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
