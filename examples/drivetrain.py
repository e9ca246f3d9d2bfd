"""A drivetrain built from two GearedRotor FMUs in an FMPy master.

    motor (inertia J_m, PI speed control)
      --omega1-->  stage 1 (z 27/41)  --omega2 -> omega1-->  stage 2 (z 23/61)  <-- T_load (step)
      <---T1-----                      <-------T1 -> T_load----

Causalities (docs/drivetrain.md): each stage takes a *speed* (omega1, the speed of its
driving gear) and a *torque* (T_load, on its driven gear), and gives back the torque on its
driving gear (T1) and the speed of its driven gear (omega2). So speeds flow downstream,
torques upstream:
- motor speed w_m            -> stage 1 omega1
- stage 1 omega2             -> stage 2 omega1
- stage 2 T1                 -> stage 1 T_load
- stage 1 T1                 -> the motor as its load torque
- the external load torque   -> stage 2 T_load

The master is explicit (Jacobi): at every communication point t_k it reads all outputs,
sets all inputs (held constant over the step) and advances the motor and both FMUs by H.
The motor and its PI controller are integrated by the master with the trapezoidal rule
(A-stable, and the shaft work T1_k (w_k + w_k+1) / 2 H it delivers is then exact for the
held torque).

Run: `.venv/bin/python examples/drivetrain.py [--H 1e-4] [--J-m 5e-3] [--out out/drivetrain]`
(builds target/fmu/GearedRotor.fmu first if it is missing). Writes drivetrain.png and
prints the power balance over a steady window.
"""

from __future__ import annotations

import argparse
import math
import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave

REPO = Path(__file__).resolve().parents[1]
FMU = REPO / "target" / "fmu" / "GearedRotor.fmu"


@dataclass
class Config:
    """Everything that defines a drivetrain run."""

    H: float = 1e-4  # communication step [s]
    t_end: float = 0.15  # [s]
    J_m: float = 5e-3  # motor inertia [kg m^2]
    filter_hz: float = 1000.0  # omega1_filter_frequency of both stages [Hz]
    w_ref: float = 314.159  # motor speed reference [rad/s]
    # PI speed controller, T_m = Kp e + Ki int e, e = w_ref - w_m: a double pole at 200 rad/s
    # for the motor plus the gearbox inertia seen at the motor (~4e-3 kg m^2 with J_m = 5e-3).
    Kp: float = 3.6
    Ki: float = 360.0
    T_load0: float = 20.0  # load torque on the output shaft before the step [N m]
    T_load1: float = 60.0  # after it
    t_step: float = 0.05  # [s]
    d_phi: float = 0.05  # rotational damper on each driven gear [N m s/rad]
    tolerance: float = 1e-8  # RADAU5 rtol of both stages
    initialization: int = 3  # periodic start of both stages (1 rest, 2 static equilibrium)
    stage1: dict = field(default_factory=lambda: {"z1": 27, "z2": 41})
    stage2: dict = field(default_factory=lambda: {"z1": 23, "z2": 61})


class Stage:
    """One GearedRotor instance with name-based access."""

    def __init__(self, unzip: str, md, name: str):
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        self.types = {v.name: v.type for v in md.modelVariables}
        self.messages: list[str] = []
        self.slave = FMU2Slave(guid=md.guid, unzipDirectory=unzip,
                               modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
        self.slave.instantiate()
        self.status = 0

    def set(self, values: dict) -> None:
        for k, v in values.items():
            if self.types[k] == "Real":
                self.slave.setReal([self.vr[k]], [float(v)])
            else:  # Integer and Enumeration
                self.slave.setInteger([self.vr[k]], [int(v)])

    def get(self, names: list[str]) -> list[float]:
        return self.slave.getReal([self.vr[n] for n in names])

    def step(self, t: float, h: float) -> int:
        try:
            self.status = int(self.slave.fmi2DoStep(self.slave.component, t, h, 1) or 0)
        except FMICallException as e:
            self.status = e.status
        return self.status

    def free(self) -> None:
        self.slave.freeInstance()


OUT = ["T1", "omega1_filtered", "omega2", "Fn", "P_loss", "P_damp", "TE",
       "E_in", "E_loss", "E_damp", "E_load", "E_kin", "E_pot"]


def ensure_fmu() -> Path:
    if not FMU.is_file():
        subprocess.run(["cargo", "run", "--release", "--quiet", "--bin", "package-fmu"], cwd=REPO, check=True)
    return FMU


def simulate(cfg: Config, fmu: Path | None = None, prescribed_speed=None) -> dict:
    """Runs the drivetrain; returns time series at the communication points ("t", "w_m",
    "T_m", "T_load", "shaft_work" and every name of OUT per stage as "s1.T1" etc.) and
    "failed": None or the reason the run stopped (FMU error, divergence).

    `prescribed_speed(k)`, if given, replaces the motor: the speed w_k is set at point k
    (open loop; used for the sampled response of the gearbox, `loop_spectral_radius`)."""
    fmu = fmu or ensure_fmu()
    md = read_model_description(str(fmu))
    unzip = extract(str(fmu))
    common = {"d_phi": cfg.d_phi, "omega1_filter_frequency": cfg.filter_hz,
              "initialization": cfg.initialization}
    s1 = Stage(unzip, md, "stage1")
    s2 = Stage(unzip, md, "stage2")
    rows: list[list[float]] = []
    failed = None
    try:
        # Consistent start: stage 2 at its input speed and the load, then stage 1 loaded by
        # stage 2's T1, then the PI integrator holding the motor torque at stage 1's T1.
        i1 = cfg.stage1["z2"] / cfg.stage1["z1"]
        for s, p, w, tl in ((s2, cfg.stage2, cfg.w_ref / i1, cfg.T_load0), (s1, cfg.stage1, cfg.w_ref, None)):
            s.slave.setupExperiment(tolerance=cfg.tolerance, startTime=0.0)
            if tl is None:
                tl = s2.get(["T1"])[0]
            s.set({**common, **p, "omega1": w, "T_load": tl})
            s.slave.enterInitializationMode()
            s.slave.exitInitializationMode()
        w_m = cfg.w_ref if prescribed_speed is None else prescribed_speed(0)
        integral = s1.get(["T1"])[0] / cfg.Ki  # T_m = Ki * integral at e = 0
        shaft_work = 0.0
        n = int(round(cfg.t_end / cfg.H))
        t = 0.0
        for k in range(n + 1):
            o1 = s1.get(OUT)
            o2 = s2.get(OUT)
            T_load = cfg.T_load0 if t < cfg.t_step - 1e-12 else cfg.T_load1
            T_m = cfg.Kp * (cfg.w_ref - w_m) + cfg.Ki * integral
            rows.append([t, w_m, T_m, T_load, shaft_work] + o1 + o2)
            if k == n:
                break
            if not all(map(math.isfinite, o1 + o2)) or abs(w_m - cfg.w_ref) > 0.5 * cfg.w_ref:
                failed = f"diverged at t = {t:.6f} s"
                break
            # inputs (held over the step): speeds downstream, torques upstream
            s1.set({"omega1": w_m, "T_load": o2[0]})
            s2.set({"omega1": o1[2], "T_load": T_load})
            # motor + PI, trapezoidal rule with the held T1 of stage 1:
            # J_m w' = Kp (w_ref - w) + Ki I - T1,  I' = w_ref - w
            T1 = o1[0]
            H, J = cfg.H, cfg.J_m
            a = J + 0.5 * H * cfg.Kp + 0.25 * H * H * cfg.Ki
            rhs = (J - 0.5 * H * cfg.Kp - 0.25 * H * H * cfg.Ki) * w_m + H * cfg.Ki * integral \
                + H * cfg.Kp * cfg.w_ref + 0.5 * H * H * cfg.Ki * cfg.w_ref - H * T1
            w_new = rhs / a if prescribed_speed is None else prescribed_speed(k + 1)
            integral += 0.5 * H * ((cfg.w_ref - w_m) + (cfg.w_ref - w_new))
            shaft_work += T1 * 0.5 * (w_m + w_new) * H
            for s in (s1, s2):
                if s.step(t, H) > 1:  # Discard or Error
                    failed = f"FMU status {s.status} at t = {t:.6f} s"
            if failed:
                break
            w_m = w_new
            t = (k + 1) * H
    finally:
        s1.free()
        s2.free()
    a = np.array(rows)
    res = {"t": a[:, 0], "w_m": a[:, 1], "T_m": a[:, 2], "T_load": a[:, 3], "shaft_work": a[:, 4],
           "failed": failed, "config": cfg}
    for j, name in enumerate(OUT):
        res["s1." + name] = a[:, 5 + j]
        res["s2." + name] = a[:, 5 + len(OUT) + j]
    return res


def gearbox_pulse_response(cfg: Config, fmu: Path | None = None, t_resp: float = 0.02,
                           delta: float = 0.01) -> np.ndarray:
    """The sampled response of the co-simulated gearbox (both stages, coupled at H as in
    `simulate`) at the motor interface: g[j] = dT1(t_j) / dw for a pulse of the motor speed
    held over the first step, j = 0..N (g[0] = 0: omega1 has no direct feedthrough).
    From two open-loop runs from the same start, one with a speed step of `delta` at t = 0
    (the difference of the step responses is the pulse response)."""
    n = int(round(t_resp / cfg.H))
    c = Config(**{**cfg.__dict__, "t_end": n * cfg.H, "t_step": 1.0})
    ref = simulate(c, fmu, prescribed_speed=lambda k: cfg.w_ref)
    stp = simulate(c, fmu, prescribed_speed=lambda k: cfg.w_ref + delta)
    step = (stp["s1.T1"] - ref["s1.T1"]) / delta
    return np.diff(step, prepend=0.0)


def loop_spectral_radius(cfg: Config, g: np.ndarray) -> float:
    """Spectral radius of the sampled loop motor + PI (trapezoidal, as in `simulate`) with
    the gearbox as the linear response g (`gearbox_pulse_response`): T1_k = sum_(j >= 1)
    g[j] w_(k-j). Below 1 the coupled co-simulation is stable; above 1 an oscillation grows
    by that factor per step. State: (w_k, I_k, w_(k-1), ..., w_(k-n))."""
    n = len(g) - 1
    H, J, Kp, Ki = cfg.H, cfg.J_m, cfg.Kp, cfg.Ki
    a = J + 0.5 * H * Kp + 0.25 * H * H * Ki
    m = np.zeros((n + 2, n + 2))
    # w_(k+1) = c0 w_k + (H Ki / a) I_k - (H / a) T1_k
    m[0, 0] = (J - 0.5 * H * Kp - 0.25 * H * H * Ki) / a
    m[0, 1] = H * Ki / a
    m[0, 2:] = -(H / a) * g[1:]
    # I_(k+1) = I_k - H/2 (w_k + w_(k+1))
    m[1] = -0.5 * H * m[0]
    m[1, 0] -= 0.5 * H
    m[1, 1] += 1.0
    # shift register: w_(k+1-1) = w_k, w_(k+1-j) = w_(k-(j-1))
    m[2, 0] = 1.0
    for i in range(3, n + 2):
        m[i, i - 1] = 1.0
    return float(max(abs(np.linalg.eigvals(m))))


def min_stable_inertia(cfg: Config, g: np.ndarray, grid=None) -> float:
    """Smallest motor inertia J_m of `grid` (default 1e-4 .. 0.1 kg m^2, 10 per decade)
    from which on every larger one gives `loop_spectral_radius` < 1 (the PI gains of `cfg`
    kept); inf if the largest is unstable. Stability need not be monotonic in J_m, so
    the grid is scanned instead of bisected."""
    grid = np.logspace(-4, -1, 31) if grid is None else grid
    best = math.inf
    for j in sorted(grid, reverse=True):
        if loop_spectral_radius(Config(**{**cfg.__dict__, "J_m": float(j)}), g) < 1.0:
            best = float(j)
        else:
            break
    return best


def stability_table(steps, filters, fmu: Path | None = None) -> list[tuple[float, float, float]]:
    """(filter_hz, H, smallest stable J_m) for the default gearbox and PI gains."""
    rows = []
    for fc in filters:
        for H in steps:
            cfg = Config(H=H, filter_hz=fc, tolerance=1e-6)
            g = gearbox_pulse_response(cfg, fmu)
            rows.append((fc, H, min_stable_inertia(cfg, g)))
    return rows


def power_balance(res: dict, t0: float, t1: float) -> dict:
    """Mean powers over [t0, t1] from the energy outputs (exact integrals inside each FMU)
    and the master's shaft work: motor shaft power = load power + friction and damper
    losses of both stages + d/dt of their kinetic and potential energy + residual."""
    t = res["t"]
    i0, i1 = int(np.argmin(abs(t - t0))), int(np.argmin(abs(t - t1)))
    dt = t[i1] - t[i0]

    def d(name: str) -> float:
        return (res[name][i1] - res[name][i0]) / dt

    b = {
        "motor (shaft)": d("shaft_work"),
        "load": d("s2.E_load"),
        "friction 1": d("s1.E_loss"), "friction 2": d("s2.E_loss"),
        "dampers 1": d("s1.E_damp"), "dampers 2": d("s2.E_damp"),
        "dE_kin+pot 1": d("s1.E_kin") + d("s1.E_pot"), "dE_kin+pot 2": d("s2.E_kin") + d("s2.E_pot"),
        # the two interfaces: what one side gives minus what the other receives
        "coupling motor/1": d("shaft_work") - d("s1.E_in"),
        "coupling 1/2": d("s1.E_load") - d("s2.E_in"),
    }
    out = b["load"] + sum(b[k] for k in ("friction 1", "friction 2", "dampers 1", "dampers 2",
                                         "dE_kin+pot 1", "dE_kin+pot 2"))
    b["residual"] = b["motor (shaft)"] - out
    b["residual / motor"] = b["residual"] / b["motor (shaft)"]
    return b


def plot(res: dict, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = res["t"] * 1e3
    fig, ax = plt.subplots(4, 1, figsize=(9, 11), sharex=True)
    ax[0].plot(t, res["w_m"], label="motor w_m")
    ax[0].plot(t, res["s1.omega2"], label="stage 1 omega2 = stage 2 input")
    ax[0].plot(t, res["s2.omega2"], label="stage 2 omega2 (output shaft)")
    ax[0].set_ylabel("speed [rad/s]")
    ax[1].plot(t, res["T_m"], label="motor T_m")
    ax[1].plot(t, res["s1.T1"], label="stage 1 T1")
    ax[1].plot(t, res["s2.T1"], label="stage 2 T1 = stage 1 T_load")
    ax[1].plot(t, res["T_load"], label="load T_load")
    ax[1].set_ylabel("torque [N m]")
    ax[2].plot(t, res["s1.Fn"], label="stage 1 Fn")
    ax[2].plot(t, res["s2.Fn"], label="stage 2 Fn")
    ax[2].set_ylabel("contact force [N]")
    ax[3].plot(t, res["s1.P_loss"], label="stage 1 friction")
    ax[3].plot(t, res["s2.P_loss"], label="stage 2 friction")
    ax[3].plot(t, res["s1.P_damp"] + res["s2.P_damp"], label="dampers (both)")
    ax[3].set_ylabel("loss [W]")
    ax[3].set_xlabel("t [ms]")
    for a in ax:
        a.legend(loc="best", fontsize=8)
        a.grid(True, alpha=0.3)
    cfg = res["config"]
    fig.suptitle(f"Drivetrain: H = {cfg.H:g} s, J_m = {cfg.J_m:g} kg m^2, filter {cfg.filter_hz:g} Hz")
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--H", type=float, default=Config.H)
    ap.add_argument("--J-m", type=float, default=Config.J_m)
    ap.add_argument("--filter-hz", type=float, default=Config.filter_hz)
    ap.add_argument("--t-end", type=float, default=Config.t_end)
    ap.add_argument("--out", type=Path, default=REPO / "out" / "drivetrain")
    ap.add_argument("--stability", action="store_true",
                    help="print the smallest stable motor inertia per H and filter frequency")
    a = ap.parse_args(argv)
    if a.stability:
        print("filter_hz  H [s]     smallest stable J_m [kg m^2] (sampled-loop spectral radius < 1)")
        for fc, H, j in stability_table([2.5e-5, 5e-5, 1e-4, 2e-4, 5e-4, 1e-3], [500.0, 1000.0, 2000.0]):
            print(f"{fc:8.0f}  {H:.1e}  {j:.3g}")
        return 0
    cfg = Config(H=a.H, J_m=a.J_m, filter_hz=a.filter_hz, t_end=a.t_end)
    res = simulate(cfg)
    if res["failed"]:
        print(f"run stopped: {res['failed']}")
    plot(res, a.out / "drivetrain.png")
    t_last = res["t"][-1]
    t0 = max(cfg.t_step + 0.06, t_last - 0.03) if t_last > cfg.t_step + 0.07 else 0.0
    print(f"power balance, mean over [{t0:.3f}, {t_last:.3f}] s (W):")
    for k, v in power_balance(res, t0, t_last).items():
        print(f"  {k:18s} {v: .6g}")
    print(f"plot: {a.out / 'drivetrain.png'}")
    return 1 if res["failed"] else 0


if __name__ == "__main__":
    sys.exit(main())
