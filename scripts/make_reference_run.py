"""Writes the reference run shipped in the .fmu (like the Modelica Reference FMUs'
<model>_in.csv / <model>_ref.csv): data/reference_run/GearedRotor_in.csv (the inputs)
and data/reference_run/GearedRotor_ref.csv (the outputs).

The case: the default pair from rest for 10 ms at 3000 rpm; the load torque T_load
ramps from 0 to 20 N m between 2 and 6 ms. Outputs every 0.1 ms.

Why the stored outputs are a reference and not just "what the code printed once":
they are computed at rtol = 1e-10 (fmi2SetupExperiment tolerance), four decades
tighter than the default 1e-6 the test (tests/test_reference_run.py) runs at, and this
script checks before writing that a run at rtol = 1e-11 agrees with them to a small
fraction of that test tolerance (the run is converged), and that the stored energies
close the energy balance of docs/model.md (9.1). Run once when the model changes on
purpose: .venv/bin/python scripts/make_reference_run.py
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from fmpy import simulate_fmu

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

from helpers.fmu_harness import build_fmu  # noqa: E402

OUT = ROOT / "data" / "reference_run"
STOP, INTERVAL = 0.01, 1e-4
OUTPUTS = [
    "T1", "Fn", "TE", "omega2", "P_in", "P_loss", "contact_length",
    "u1.x", "u1.y", "u1.z", "u2.x", "u2.y", "u2.z",
    "E_in", "E_loss", "E_damp", "E_load", "E_kin", "E_pot",
]
REF_RTOL = 1e-10


def inputs() -> np.ndarray:
    rows = [(0.0, 314.159, 0.0), (0.002, 314.159, 0.0), (0.006, 314.159, 20.0), (STOP, 314.159, 20.0)]
    return np.array(rows, dtype=[("time", float), ("omega1", float), ("T_load", float)])


def run(fmu: Path, rtol: float, inp: np.ndarray) -> np.ndarray:
    return simulate_fmu(
        str(fmu), stop_time=STOP, output_interval=INTERVAL, relative_tolerance=rtol,
        input=inp, output=OUTPUTS, validate=False,
    )


def write_csv(path: Path, arr: np.ndarray, digits: int) -> None:
    names = arr.dtype.names
    with path.open("w", encoding="utf-8") as f:
        f.write(",".join(f'"{n}"' for n in names) + "\n")
        for row in arr:
            f.write(",".join(f"{row[n]:.{digits}g}" for n in names) + "\n")


def main() -> None:
    fmu = build_fmu(quiet=True)
    inp = inputs()
    ref = run(fmu, REF_RTOL, inp)
    finer = run(fmu, REF_RTOL / 10, inp)
    for n in OUTPUTS:
        scale = max(np.max(np.abs(ref[n])), 1e-300)
        dev = np.max(np.abs(ref[n] - finer[n])) / scale
        print(f"{n:15s} max |ref - run at rtol {REF_RTOL / 10:g}| = {dev:.2e} of max |{n}|")
    e = ref
    lhs = e["E_in"] - e["E_loss"] - e["E_damp"] - e["E_load"]
    rhs = (e["E_kin"] - e["E_kin"][0]) + (e["E_pot"] - e["E_pot"][0])
    bal = np.max(np.abs(lhs - rhs)) / np.max(np.abs(e["E_in"]))
    print(f"energy balance (9.1): max residual {bal:.2e} of E_in")
    if bal > 1e-6:
        raise SystemExit("energy balance not closed: not writing a reference")
    OUT.mkdir(parents=True, exist_ok=True)
    write_csv(OUT / "GearedRotor_in.csv", inp, 17)
    write_csv(OUT / "GearedRotor_ref.csv", ref, 12)
    print(f"wrote {OUT / 'GearedRotor_in.csv'} and {OUT / 'GearedRotor_ref.csv'}")


if __name__ == "__main__":
    main()
