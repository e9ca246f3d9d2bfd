"""Figures of the coast flanks and the backlash (tooth_contact = elastic, docs/model.md §3.6)
for README.md "Load reversal and rattle (elastic teeth)" and the FMU's documentation:

    source scripts/env.sh
    $VPY scripts/coast_figures.py            # uses target/fmu/GearedRotor.fmu
    $VPY scripts/coast_figures.py --fmu X.fmu

Runs through FMPy on the packaged .fmu (built with cargo run --release --bin package-fmu
when it is missing) the two runs of tests/test_coast_flank.py, from the static equilibrium
at 3000 rpm with the default pair and j_bn = 0.1 mm, communication step 0.1 ms,
tolerance 1e-8:

- reversal: T_load +100 -> -100 N m (ramp 20..25 ms), d_phi 0.05, law 1 with mu = 0;
  writes docs/figures/reversal.png (T_load; mesh_state; Fn and Fn_coast; TE and the drive
  gap);
- rattle: T_load 0, d_phi 0.01, omega1 = 314.159 (1 + 0.05 sin(2 pi 30 t)) set at every
  communication point, 0.1 s; writes docs/figures/rattle.png (omega1 and omega2 i;
  mesh_state; Fn and Fn_coast; impacts).

and prints the numbers the README quotes.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))
from helpers import coast_cases  # noqa: E402
from helpers.coast_cases import OMEGA1, omega1_rattle, t_load_reversal  # noqa: E402
from helpers.fmu_harness import FMU_PATH, FMI2_OK, FmuPackage, build_fmu  # noqa: E402
from helpers.gear_theory import inv  # noqa: E402

FIG = ROOT / "docs" / "figures"
H = 1e-4
TOLERANCE = 1e-8
NAMES = ["mesh_state", "Fn", "Fn_coast", "TE", "gap", "impacts", "omega2", "mesh_stiffness",
         "u1.x", "u1.y", "u2.x", "u2.y"]


def simulate(pkg: FmuPackage, params: dict, inputs, n: int):
    """n communication steps from the static equilibrium with elastic teeth
    (`helpers.coast_cases.simulate`, the tests' driver); `inputs(t)` set before each
    doStep. Returns the trajectory (with the inputs as set), the calculated parameters and
    the CPU time; exits on any status other than OK."""
    tr, cal, statuses, above_ok, cpu = coast_cases.simulate(
        pkg, "coast_figures", params, inputs, n, h=H, tolerance=TOLERANCE, record=NAMES,
        calculated=coast_cases.CALCULATED + ["z1", "z2"])
    bad = [k for k, status in enumerate(statuses) if status != FMI2_OK]
    if bad:
        sys.exit(f"doStep at {bad[0] * H:.4f} s returned {statuses[bad[0]]}:\n"
                 + "\n".join(above_ok))
    if above_ok:
        sys.exit("\n".join(above_ok))
    # The input held over each step, sampled with the state at its start (the last sample
    # repeats the last input).
    u = [inputs(k * H) for k in range(n)] + [inputs((n - 1) * H)]
    for name in u[0]:
        tr.data[name] = np.array([x[name] for x in u])
    return tr, cal, cpu


def reversal(pkg: FmuPackage) -> Path:
    d_phi = 0.05
    tr, cal, cpu = simulate(pkg, {"T_load": 100.0, "d_phi": d_phi, "mu": 0.0, "friction_law": 1,
                                  "omega1": OMEGA1}, lambda t: {"T_load": t_load_reversal(t)}, 600)
    ms, ms_t = tr["mesh_state"], tr.t * 1e3
    r_sum, cos_bb = cal["r_b1"] + cal["r_b2"], math.cos(cal["beta_b"])
    tail = tr.t > 0.05 + 1e-9
    fc = np.mean(tr["Fn_coast"][tail])
    fc_static = (100.0 - d_phi * np.mean(tr["omega2"][tail])) / (cal["r_b2"] * cos_bb)
    dx = cal["a_w"] + tr["u2.x"][-1] - tr["u1.x"][-1]
    dy = tr["u2.y"][-1] - tr["u1.y"][-1]
    alpha = math.acos(r_sum / math.hypot(dx, dy))
    play = cal["j_bn"] / cos_bb + 2.0 * r_sum * (inv(alpha) - inv(cal["alpha_wt"]))
    t_free = ms_t[np.argmax(ms == 0)]
    t_coast = ms_t[np.argmax(ms == -1)]
    print(f"reversal: free flight {t_free:.1f} ms, coast contact {t_coast:.1f} ms, impacts "
          f"{tr['impacts'][-1]}; Fn at 0: {tr['Fn'][0]:.1f} N; mean Fn_coast 50-60 ms {fc:.1f} N "
          f"(static {fc_static:.1f} N); drive gap at 60 ms {tr['gap'][-1] * 1e6:.2f} um, play "
          f"{play * 1e6:.2f} um (j_bn / cos beta_b = {cal['j_bn'] / cos_bb * 1e6:.2f} um); TE "
          f"{tr['TE'][0] * 1e6:.2f} -> {tr['TE'][-1] * 1e6:.2f} um; CPU {cpu:.2f} s")

    fig, axes = plt.subplots(4, 1, figsize=(9, 9), sharex=True)
    axes[0].plot(ms_t, tr["T_load"], color="k")
    axes[0].set_ylabel("T_load [N m]")
    axes[1].step(ms_t, ms, where="post", color="C2")
    axes[1].set_yticks([-1, 0, 1], ["-1 coast", "0 free", "1 drive"])
    axes[1].set_ylabel("mesh_state")
    axes[2].plot(ms_t, tr["Fn"], label="Fn (drive flanks)")
    axes[2].plot(ms_t, tr["Fn_coast"], label="Fn_coast (coast flanks)")
    axes[2].axhline(fc_static, color="C1", ls=":", lw=1,
                    label=f"static coast force {fc_static:.0f} N")
    axes[2].set_ylabel("force [N]")
    axes[2].legend(fontsize=8, loc="center right")
    axes[3].plot(ms_t, tr["TE"] * 1e6, label="TE")
    axes[3].plot(ms_t, tr["gap"] * 1e6, label="drive gap (gap)")
    axes[3].axhline(play * 1e6, color="C1", ls=":", lw=1, label=f"play at the end {play * 1e6:.1f} um")
    axes[3].set_ylabel("[um]")
    axes[3].set_xlabel("time [ms]")
    axes[3].legend(fontsize=8, loc="center right")
    for ax in axes:
        ax.grid(alpha=0.3)
        ax.axvspan(20, 25, color="0.9", zorder=0)
    fig.suptitle("Load reversal through the backlash: elastic teeth, j_bn = 0.1 mm, 3000 rpm,\n"
                 "d_phi = 0.05 N m s/rad, mu = 0 (grey: the T_load ramp)", fontsize=10)
    fig.tight_layout()
    p = FIG / "reversal.png"
    fig.savefig(p, dpi=90)
    plt.close(fig)
    return p


def rattle(pkg: FmuPackage) -> Path:
    n = 1000
    tr, cal, cpu = simulate(pkg, {"T_load": 0.0, "d_phi": 0.01, "omega1": OMEGA1},
                            lambda t: {"omega1": omega1_rattle(t)}, n)
    ms, ms_t, imp = tr["mesh_state"], tr.t * 1e3, tr["impacts"]
    onset = (ms[1:] != 0) & (ms[1:] != ms[:-1])
    drive, coast = int(np.sum(onset & (ms[1:] == 1))), int(np.sum(onset & (ms[1:] == -1)))
    t_sim = n * H
    print(f"rattle: {imp[-1]} impacts in {t_sim:.1f} s ({imp[-1] / t_sim:.0f} per second; seen at "
          f"the communication points: {drive} onsets on the drive, {coast} on the coast flanks); "
          f"time in drive/free/coast contact {np.mean(ms == 1):.0%}/{np.mean(ms == 0):.0%}/"
          f"{np.mean(ms == -1):.0%}; max Fn {tr['Fn'].max():.0f} N, max Fn_coast "
          f"{tr['Fn_coast'].max():.0f} N (mean Fn while the drive flanks touch "
          f"{tr['Fn'][ms == 1].mean():.0f} N); CPU {cpu / t_sim:.2f} s per simulated second")

    ratio = cal["z1"] / cal["z2"]
    fig, axes = plt.subplots(4, 1, figsize=(9, 9), sharex=True)
    axes[0].plot(ms_t, tr["omega1"], color="k", label="omega1 (input)")
    axes[0].plot(ms_t, tr["omega2"] / ratio, color="C0", lw=0.8, label="omega2 z2/z1")
    axes[0].set_ylabel("[rad/s]")
    axes[0].legend(fontsize=8, loc="upper right")
    axes[1].step(ms_t, ms, where="post", color="C2", lw=0.8)
    axes[1].set_yticks([-1, 0, 1], ["-1 coast", "0 free", "1 drive"])
    axes[1].set_ylabel("mesh_state")
    axes[2].plot(ms_t, tr["Fn"], lw=0.8, label="Fn (drive flanks)")
    axes[2].plot(ms_t, tr["Fn_coast"], lw=0.8, label="Fn_coast (coast flanks)")
    axes[2].set_ylabel("force [N]")
    axes[2].legend(fontsize=8, loc="upper right")
    axes[3].step(ms_t, imp, where="post", color="C3")
    axes[3].set_ylabel("impacts")
    axes[3].set_xlabel("time [ms]")
    for ax in axes:
        ax.grid(alpha=0.3)
    fig.suptitle("Rattle: no load, d_phi = 0.01 N m s/rad, omega1 = 3000 rpm +-5 % at 30 Hz\n"
                 f"(elastic teeth, j_bn = 0.1 mm): {imp[-1] / t_sim:.0f} impacts per second",
                 fontsize=10)
    fig.tight_layout()
    p = FIG / "rattle.png"
    fig.savefig(p, dpi=90)
    plt.close(fig)
    return p


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--fmu", type=Path, default=None, help="the .fmu (FMI 2.0) to run")
    args = ap.parse_args()
    fmu = args.fmu or FMU_PATH
    if args.fmu is None and not fmu.is_file():
        fmu = build_fmu(ROOT)
    pkg = FmuPackage(fmu)
    FIG.mkdir(parents=True, exist_ok=True)
    for p in (reversal(pkg), rattle(pkg)):
        print(f"wrote {p.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
