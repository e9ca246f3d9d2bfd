#!/usr/bin/env python3
"""Main job: build GearedRotor.fmu, simulate a gear pair through FMPy (the defaults,
or any parameter and input changed with --set NAME=VALUE[unit]), write out/results.csv
and the figures, and print a steady-state summary over whole mesh periods: mean T1, the load on gear 2
(T_load and the damper's T_damp = d_phi omega2), mean Fn, TE peak to peak, mean P_in,
P_loss and the damper power, efficiency 1 - <P_loss>/<P_in>, the friction coefficient the
law actually uses, the model's loss factor H_V and the standard's H_V_iso. Every figure
title names the case (pair, face width, speed, load with the damper's share, mu).

Mistakes in the input end with a message that names it and exit status 2 (an unknown
name or unit, omega1 <= 0, a load that would make gear 2 drive gear 1, ...); a value
without a unit that is implausible in SI (m_n=3 is 3 m) is warned about. When the start
on the periodic orbit fails, the run starts from rest and cuts a 0.1 s transient.

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
  python scripts/main_job.py --set d_phi=0 --set T_load=150 --set initialization=rest
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
from case_values import SetError, parse_set, unitless_warning  # noqa: E402

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


def case_title(v: dict, md=None, t_damp: float | None = None) -> str:
    """The case in one line: pair, helix, face width, speed, load (with the damper's share),
    friction."""
    beta = math.degrees(v["beta"])
    damper = ""
    if v.get("d_phi"):
        damper = f" + damper {t_damp:.3g} N m" if t_damp is not None else f" + damper d_phi = {v['d_phi']:g} N m s/rad"
    elif "d_phi" in v:
        damper = ", no damper"
    face = f"b = {1e3 * v['b']:g} mm, " if "b" in v else ""
    return (f"z1/z2 = {v['z1']}/{v['z2']}, m_n = {1e3 * v['m_n']:g} mm, beta = {beta:g} deg, {face}"
            f"{v['omega1'] * 30 / math.pi:g} rpm, T_load = {v['T_load']:g} N m{damper}, mu = {v['mu']:g}")


def wrap_title(text: str, width: int = 95) -> str:
    """Long titles over several lines (the figure is ~8 inches wide at fontsize 9), broken
    only after ", " or "; " so that no "name = value" is split."""
    import re

    lines, line = [], ""
    for part in re.split(r"(?<=[,;]) ", text):
        if line and len(line) + 1 + len(part) > width:
            lines.append(line)
            line = part
        else:
            line = f"{line} {part}" if line else part
    return "\n".join(lines + [line])


def plot(out: Path, t, res, a: float, b: float, t_m: float, title: str, steady_from_start: bool) -> list[Path]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    files = []
    title = wrap_title(title)
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
        # no offset text: it would sit on the title and hide the values of the ticks
        ax.ticklabel_format(axis="y", useOffset=False)
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
    fig.suptitle(f"Periodic orbit of the gear centres (Jehle & Fidlin, Fig. 3)\n{wrap_title(title, 110)}",
                 fontsize=10)
    fig.tight_layout()
    fig.savefig(out / "fig3.png", dpi=120)
    plt.close(fig)
    return summary, unused


class UserError(Exception):
    """A mistake in the command line or the case; the message names the input and what to do."""


def check_args(args) -> None:
    if args.stop_time is not None and not (args.stop_time > 0 and math.isfinite(args.stop_time)):
        raise UserError(f"--stop-time {args.stop_time:g}: give the end of the run in seconds, > 0")
    if not (args.output_interval > 0 and math.isfinite(args.output_interval)):
        raise UserError(f"--output-interval {args.output_interval:g}: give a step in seconds, > 0 "
                        "(e.g. 1e-5)")
    if not (args.transient >= 0 and math.isfinite(args.transient)):
        raise UserError(f"--transient {args.transient:g}: give the cut in seconds, >= 0")
    if args.fmu is not None and not args.fmu.is_file():
        raise UserError(f"--fmu {args.fmu}: no such file; build it with `cargo run --release --bin "
                        "package-fmu` or leave --fmu out")


def check_case(v: dict, sets: dict) -> list[str]:
    """Refuses a case the main job cannot evaluate (UserError naming the input) and returns
    warnings about the load: omega1 must be > 0 (the mesh period 2 pi / (z1 omega1) sets the
    window, and the model drives gear 1 in one sense); the net load on gear 2,
    T_load + d_phi omega2 (omega2 = omega1 z1/z2 in steady rotation), must not be negative
    (gear 2 would drive gear 1: the teeth lift off and 1 - P_loss/P_in means nothing)."""
    for z in ("z1", "z2"):
        if not v[z] >= 5:
            raise UserError(f"{z} = {v[z]:g}: a gear needs at least 5 teeth (the declared minimum of "
                            f"{z}); give e.g. --set {z}={27 if z == 'z1' else 41}")
    w1 = v["omega1"]
    if not (math.isfinite(w1) and w1 > 0):
        raise UserError(
            f"omega1 = {w1:g} rad/s ({w1 * 30 / math.pi:g} rpm): the main job needs a drive speed "
            "> 0 (the steady window is whole mesh periods 2 pi/(z1 omega1), and the model drives "
            "gear 1 in the positive sense only); give e.g. --set omega1=1500rpm")
    omega2 = w1 * v["z1"] / v["z2"]
    t_damp = v["d_phi"] * omega2
    net = v["T_load"] + t_damp
    if net < 0:
        raise UserError(
            f"T_load = {v['T_load']:g} N m: the load on gear 2, T_load + d_phi omega2 = "
            f"{v['T_load']:g} + {t_damp:.4g} = {net:.4g} N m, is negative, so gear 2 would drive "
            "gear 1: the teeth lift off (the model has one flank pair in contact) and the efficiency "
            f"1 - P_loss/P_in means nothing; give T_load >= {-t_damp:.4g} N m (a braking load is "
            "positive)")
    warnings = []
    if net == 0:
        warnings.append("T_load + d_phi omega2 = 0: no load on gear 2, the efficiency is not defined "
                        "(the tooth force only carries the inertia); give T_load > 0 or d_phi > 0")
    return warnings


def si_text(md, name: str, value) -> str:
    """A value with its unit for titles: in the display unit if the variable has one
    (b = 30 mm, omega1 = 1500 rpm), else the SI unit."""
    from case_values import display_units, unit_of

    var = next((x for x in md.modelVariables if x.name == name), None)
    if var is None or isinstance(value, bool) or var.type != "Real":
        return f"{name} = {value}"
    unit = unit_of(var)
    disp = var.declaredType.displayUnit if var.declaredType is not None else None
    table = display_units(md, unit)
    if disp and disp in table:
        f, o = table[disp]
        return f"{name} = {f * value + o:g} {disp}"
    return f"{name} = {value:g} {unit}".rstrip() if unit not in ("", "1") else f"{name} = {value:g}"


class FmuLog:
    """The FMU's log messages of a run, kept (printed by `show` once it is known which run
    counts)."""

    LABEL = ["OK", "WARNING", "DISCARD", "ERROR", "FATAL", "PENDING"]

    def __init__(self):
        self.messages: list[tuple[int, str]] = []

    def __call__(self, component, instance_name, status, category, message):
        text = (message or b"").decode("utf-8", "replace")
        self.messages.append((int(status), text))

    def errors(self) -> str:
        return " | ".join(m for s, m in self.messages if s >= 2)

    def show(self) -> None:
        for s, m in self.messages:
            if 0 < s < len(self.LABEL):
                print(f"[{self.LABEL[s]}] {m}", file=sys.stderr)


#: words of the FMU's message when the start on the periodic orbit failed (src/sim/init.rs);
#: a refused parameter is not among them and gets no second run
PERIODIC_FAILED = ("no periodic orbit", "periodic orbit is unstable")


def simulate(fmu, stop, interval, start_values, output):
    """simulate_fmu with the FMU's messages kept; returns (result or None, FmuLog)."""
    from fmpy import simulate_fmu

    log = FmuLog()
    try:
        res = simulate_fmu(str(fmu), stop_time=stop, output_interval=interval,
                           start_values=start_values, output=output, logger=log)
    except Exception as e:  # FMPy raises FMICallException; the FMU's message is in the log
        log.messages.append((3, f"{type(e).__name__}: {e}"))
        return None, log
    return res, log


# calculated parameters read with the run (present in FMUs of this repository)
CALCULATED = ["H_V", "H_V_iso", "m1_solid", "J1_solid", "m2_solid", "J2_solid"]
# the coefficient each friction law actually uses (docs/friction.md)
LAW_COEFFICIENT = {1: ("mu", "the parameter mu"), 2: ("mu_eff", "mu times the regularisation"),
                   3: ("mu_mz", "ISO/TR 14179-2 (Schlenk) at the load and speed"),
                   4: ("mu_eff", "load-weighted mean of the local EHL coefficient"),
                   5: ("mu_eff", "load-weighted mean of Benedict & Kelley's coefficient")}


def main() -> int:
    try:
        return run_main()
    except UserError as e:
        print(f"main job: error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("main job: interrupted", file=sys.stderr)
        return 130
    except OSError as e:  # e.g. --out not writable, a file in the way
        print(f"main job: error: {e.strerror or e} ({e.filename or ''}); check --out and --fmu",
              file=sys.stderr)
        return 2


def run_main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--set", action="append", default=[], metavar="NAME=VALUE[unit]",
                    help="set a parameter or input, e.g. omega1=1500rpm, beta=15deg, mu=0.1, "
                         "k1.x=150N/um, initialization=rest (units: the variable's unit or a "
                         "declared display unit; Enumerations by item name or number)")
    ap.add_argument("--stop-time", type=float, default=None,
                    help="end of the run [s] (default 0.15 from rest; 30 mesh periods on the periodic orbit)")
    ap.add_argument("--output-interval", type=float, default=1e-5)
    ap.add_argument("--transient", type=float, default=0.1,
                    help="start of the steady window [s] for a run from rest (default 0.1 s: "
                         "the TE of the start-up transient is at its steady value by ~80 ms)")
    ap.add_argument("--out", type=Path, default=REPO / "out")
    ap.add_argument("--fmu", type=Path, default=None, help="use this .fmu (no build)")
    ap.add_argument("--no-build", action="store_true", help="use the existing target/fmu/GearedRotor.fmu")
    ap.add_argument("--no-periodic", action="store_true", help="skip the periodic orbit (Fig. 3)")
    args = ap.parse_args()
    check_args(args)

    from fmpy import read_model_description
    from fmpy.util import write_csv

    if args.fmu:
        fmu = args.fmu
    elif args.no_build:
        fmu = FMU_PATH
        if not fmu.is_file():
            raise UserError(f"--no-build: {fmu} does not exist; run once without --no-build")
    else:
        try:
            fmu = build_fmu(REPO)
        except (subprocess.CalledProcessError, FileNotFoundError) as e:
            raise UserError(f"building the .fmu failed ({e}); cargo's messages are above") from None
    try:
        md = read_model_description(str(fmu))
    except Exception as e:  # a zip error, a missing or malformed modelDescription.xml
        raise UserError(f"--fmu {fmu}: not an FMU whose model description can be read ({e}); "
                        "give the .fmu the build writes (target/fmu/GearedRotor.fmu)") from None
    try:
        sets = dict(parse_set(md, s) for s in args.set)
    except SetError as e:
        raise UserError(str(e)) from None
    for s in args.set:
        w = unitless_warning(md, s)
        if w:
            print(f"main job: warning: {w}", file=sys.stderr)
    names = {v.name for v in md.modelVariables}
    start_values, steady_from_start = steady_plan(names, sets)

    def value(name):
        if name in sets:
            return sets[name]
        v = next(v for v in md.modelVariables if v.name == name)
        return int(v.start) if v.type in ("Integer", "Enumeration") else float(v.start)

    case = {n: value(n) for n in ("z1", "z2", "m_n", "beta", "b", "omega1", "T_load", "mu", "d_phi")}
    for w in check_case(case, sets):
        print(f"main job: warning: {w}", file=sys.stderr)
    law = value("friction_law") if "friction_law" in names else 1
    t_m = 2 * math.pi / (case["z1"] * case["omega1"])  # mesh period, docs/model.md (9.4)
    transient = 0.0 if steady_from_start else args.transient
    stop = args.stop_time or (30 * t_m if steady_from_start else max(0.15, transient + 30 * t_m))
    if not steady_from_start and stop - transient < t_m:
        raise UserError(f"--stop-time {stop:g} s: no whole mesh period ({1e3 * t_m:.3g} ms) after the "
                        f"transient cut --transient {transient:g} s; give --stop-time >= "
                        f"{transient + 10 * t_m:.4g}")
    output = RECORD + [n for n in ("T_damp", "P_damp_phi", "mu_eff", "mu_mz") if n in names]
    output += [n for n in CALCULATED if n in names]

    cpu0 = time.process_time()
    res, log = simulate(fmu, stop, args.output_interval, start_values, output)
    fallback = None
    if (res is None and steady_from_start and "initialization" not in sets
            and any(w in log.errors() for w in PERIODIC_FAILED)):
        # the start on the periodic orbit failed: a start from rest with a transient long
        # enough for the steady state (docs/studies.md) does not need the shooting
        fallback = log.errors()
        transient = max(args.transient, 0.1)
        stop = max(args.stop_time or 0.0, transient + 30 * t_m)
        print(f"main job: warning: the start on the periodic orbit failed ({fallback}); running "
              f"from rest instead and cutting the first {transient:g} s", file=sys.stderr)
        start_values = dict(start_values, initialization=1)
        steady_from_start = False
        res, log = simulate(fmu, stop, args.output_interval, start_values, output)
    log.show()
    if res is None:
        print(f"main job: error: the simulation of this case stopped: {log.errors()}\n"
              "  (the FMU's message names the parameter to change and its limit)", file=sys.stderr)
        return 1
    cpu = time.process_time() - cpu0
    t = res["time"]

    args.out.mkdir(parents=True, exist_ok=True)
    csv = args.out / "results.csv"
    write_csv(str(csv), res)

    n = int(math.floor((t[-1] - transient) / t_m + 1e-9))
    if n < 1:
        raise UserError("no whole mesh period after the transient; raise --stop-time")
    a, b = transient, transient + n * t_m
    # means of powers from the energy accumulators (integrated as states, exact
    # to solver tolerance), of T1 from the samples
    e = {k: np.interp([a, b], t, res[k]) for k in ("E_in", "E_loss")}
    p_in = (e["E_in"][1] - e["E_in"][0]) / (b - a)
    p_loss = (e["E_loss"][1] - e["E_loss"][0]) / (b - a)
    mean = {k: window_mean(t, res[k], a, b) for k in output if k in res.dtype.names
            and k not in CALCULATED and res[k].dtype.kind == "f"}
    win = (t >= a - 1e-12) & (t <= b + 1e-12)
    te_p2p = float(np.ptp(res["TE"][win]))
    h_v = float(res["H_V"][-1])
    h_v_iso = float(res["H_V_iso"][-1]) if "H_V_iso" in res.dtype.names else float("nan")
    t_damp = mean.get("T_damp", case["d_phi"] * mean["omega2"])
    p_damp_phi = mean.get("P_damp_phi", float("nan"))
    eff = 1 - p_loss / p_in if p_in > 0 else float("nan")

    title = case_title(case, md, t_damp)
    others = [si_text(md, k, v) for k, v in sets.items() if k not in case and k != "initialization"]
    if others:
        title += "; " + ", ".join(others)
    files = plot(args.out, t, res, a, b, t_m, title, steady_from_start)

    changed = ", ".join(si_text(md, k, v) for k, v in sets.items())
    print(f"GearedRotor.fmu, {changed or 'defaults'}; {stop:g} s through FMPy "
          f"(output interval {args.output_interval:g} s, CPU {cpu:.2f} s)")
    print(f"case                   : {title}")
    start_how = ("on the periodic orbit (initialization = 3)" if steady_from_start
                 else "from rest; transient cut" if "initialization" not in names
                 else f"with initialization = {start_values.get('initialization', value('initialization'))}; "
                      "transient cut")
    if fallback:
        start_how += " (fallback: the periodic start failed)"
    print(f"start                  : {start_how}")
    print(f"steady window          : {1e3 * a:.3f} .. {1e3 * b:.3f} ms ({n} mesh periods of {1e6 * t_m:.2f} {chr(0xb5)}s)")
    print(f"mean T1                : {mean['T1']:.4f} N m")
    print(f"load on gear 2         : T_load {case['T_load']:g} N m + damper T_damp = d_phi omega2 "
          f"{t_damp:.4f} N m (d_phi = {case['d_phi']:g} N m s/rad)")
    print(f"mean Fn (lambda)       : {mean['Fn']:.2f} N")
    print(f"T1 ripple (max - min)  : {np.ptp(res['T1'][win]):.4f} N m")
    print(f"TE peak to peak        : {1e6 * te_p2p:.4f} {MICRO}")
    print(f"mean P_in              : {p_in:.3f} W")
    print(f"mean P_loss (friction) : {p_loss:.4f} W")
    print(f"mean damper power      : {p_damp_phi:.3f} W (d_phi omega2^2; {100 * p_damp_phi / p_in:.2f} % of P_in)")
    print(f"efficiency             : {eff:.6f}  (1 - <P_loss>/<P_in>, the mesh only)")
    coef_name, coef_what = LAW_COEFFICIENT.get(law, ("mu", "mu"))
    coef = case["mu"] if coef_name == "mu" else mean.get(coef_name, float("nan"))
    print(f"friction law           : {law}; coefficient used {coef_name} = {coef:.5f} (mean; {coef_what})")
    print(f"H_V (model, analytic)  : {h_v:.6f}  load spread uniformly over the contact lines")
    print(f"H_V_iso (Ohlendorf)    : {h_v_iso:.6f}  the loss factor of ISO/TR 14179-2")
    print(f"{coef_name + '*H_V':<23}: {coef * h_v:.6f}  vs <P_loss>/<P_in> = {p_loss / p_in:.6f}")
    if law == 3:
        p_iso = coef * h_v_iso * p_in
        print(f"law 3, standard's loss : mu_mz H_V_iso P_in = {p_iso:.4f} W (efficiency {1 - p_iso / p_in:.6f}); "
              f"the model's: {p_loss:.4f} W (efficiency {eff:.6f})")
    print(f"wrote {csv.relative_to(REPO) if csv.is_relative_to(REPO) else csv}, "
          + ", ".join(str(f.name) for f in files))
    status = 0
    if not (0 < eff <= 1):
        print(f"main job: error: efficiency {eff:.6f} is outside (0, 1]: mean P_in = {p_in:.4g} W, "
              f"P_loss = {p_loss:.4g} W; the case does not transmit power from gear 1 to gear 2 "
              "(check T_load, d_phi and omega1)", file=sys.stderr)
        status = 1
    if not args.no_periodic:
        solid = {k: float(res[f"{k}_solid"][-1]) for k in ("m1", "J1", "m2", "J2")
                 if sets.get(k) == 0 and f"{k}_solid" in res.dtype.names}
        try:
            ps, unused = periodic_fig3(args.out, dict(sets, **solid), title)
        except subprocess.CalledProcessError as e:
            print(f"main job: error: the periodic orbit (Fig. 3) failed for this case:\n{e.stderr}",
                  file=sys.stderr)
            return 1
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
    return status


if __name__ == "__main__":
    sys.exit(main())
