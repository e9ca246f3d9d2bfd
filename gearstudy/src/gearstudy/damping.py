"""Modal damping of a point's periodic orbit (docs/damping.md), as study columns.

The FMU simulates; the modal analysis (Floquet multipliers of the periodic orbit at constant
drive speed, each mode's frequency and damping ratio and what the friction adds) is the
crate's `periodic --damping` program. gearstudy calls it once per point with the point's
values in SI (a `--params` file: every FMU parameter, `omega1` and `T_load`; FMU settings such
as `initialization` are skipped with `--ignore-unknown`) and reads its JSON line. Why a program
and not FMU outputs: the analysis is a property of the parameter set at a constant speed, not
of a co-simulation run; as a program it costs nothing to runs that do not ask for it, leaves
the FMI interface (value references, model structure) unchanged, and is the same code and the
same numbers as `cargo run --release --bin periodic -- --damping`.

Columns, for the modes 1..n by increasing friction-free frequency: ``mode{i}.name`` (the states
that dominate the mode shape), ``mode{i}.f`` [Hz], ``mode{i}.zeta``, ``mode{i}.dzeta`` (zeta
minus zeta at mu = 0), and ``damping.shift`` (the largest move of an exponent from its
friction-free value, in units of pi / T_m; the branches are unambiguous below 1).
"""

from __future__ import annotations

import json
import os
import subprocess
import tempfile
from pathlib import Path

#: environment variable: the `periodic` program to use (overrides [damping] program)
PROGRAM_ENV = "GEARSTUDY_PERIODIC"
REPO_PROGRAM = Path("target") / "release" / "periodic"
FIELDS = (("f", "freq_hz"), ("zeta", "zeta"), ("dzeta", "dzeta"))
#: inputs the program takes besides the model parameters
INPUTS = ("omega1", "T_load")
#: above this move of an exponent (in pi / T_m) the branch resolution is doubtful (at 1 it fails)
SHIFT_WARN = 0.5


def columns(n_modes: int) -> list[tuple[str, str]]:
    cols = []
    for i in range(1, n_modes + 1):
        cols.append((f"mode{i}.name", "string"))
        cols += [(f"mode{i}.{c}", "float64") for c, _ in FIELDS]
    cols.append(("damping.shift", "float64"))
    return cols


def find_program(given: str | None, base: Path | None) -> Path:
    """The program: $GEARSTUDY_PERIODIC, else [damping] program (relative to the study file),
    else target/release/periodic of the repository around the working directory or the
    study file."""
    env = os.environ.get(PROGRAM_ENV)
    if env:
        return Path(env).resolve()
    if given:
        p = Path(given)
        if not p.is_absolute() and base is not None:
            p = base / p
        return p.resolve()
    for start in [Path.cwd()] + ([base.resolve()] if base else []):
        for d in [start, *start.parents]:
            if (d / REPO_PROGRAM).is_file():
                return (d / REPO_PROGRAM).resolve()
    return (Path.cwd() / REPO_PROGRAM).resolve()


def params_text(point: dict, catalog) -> str:
    """The point's values as `name = value` lines in SI (the FMU's values)."""
    lines = []
    for name, value in point.items():
        v = catalog.variables.get(name)
        if v is None or not (name in INPUTS or v.causality == "parameter"):
            continue
        lines.append(f"{name} = {float(value)!r}")
    return "\n".join(lines) + "\n"


def modal(point: dict, catalog, program: str, n_modes: int, warn=lambda msg: None,
          timeout: float = 600.0) -> dict:
    """The damping columns of one point; raises RuntimeError with the program's message;
    `warn(message)` when the branch resolution is doubtful (damping.shift > SHIFT_WARN)."""
    with tempfile.TemporaryDirectory(prefix="gearstudy-damping-") as d:
        pf = Path(d) / "point.txt"
        pf.write_text(params_text(point, catalog))
        proc = subprocess.run(
            [program, "--damping", "--json", "--ignore-unknown", "--params", str(pf), "--out", d],
            capture_output=True, text=True, timeout=timeout,
        )
    if proc.returncode != 0:
        msg = (proc.stderr.strip() or proc.stdout.strip()).splitlines()
        raise RuntimeError(msg[-1] if msg else f"exit status {proc.returncode}")
    data = json.loads(proc.stdout.strip().splitlines()[-1])
    out: dict = {"damping.shift": float(data["shift"])}
    if out["damping.shift"] > SHIFT_WARN:
        warn(f"damping: an exponent moved {out['damping.shift']:.2f} of pi/T_m from its "
             "friction-free value; the mode frequencies may be off by multiples of the mesh frequency")
    modes = data["modes"]
    for i in range(1, n_modes + 1):
        if i <= len(modes):
            m = modes[i - 1]
            out[f"mode{i}.name"] = m["name"]
            for c, key in FIELDS:
                out[f"mode{i}.{c}"] = float(m[key])
    return out
