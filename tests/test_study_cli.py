"""gearstudy's command line: `gearstudy sweep` (serial here, to keep it cheap), `plot` and
`table` on the same results; a bad study file is refused with a message and exit status 2."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from gearstudy import read_results

STUDY = """
[grid]
omega1 = ["2000 rpm", "4000 rpm"]
T_load = [10.0, 50.0]
[fixed]
mu = 0.04
[window]
transient = "2 ms"
periods = 2
samples_per_period = 8
n_orders = 2
"""


def _gearstudy() -> list[str]:
    exe = Path(sys.executable).with_name("gearstudy")
    return [str(exe)] if exe.exists() else [shutil.which("gearstudy") or "gearstudy"]


def test_sweep_plot_and_table_from_the_command_line(fmu_path, tmp_path):
    study = tmp_path / "s.toml"
    study.write_text(STUDY)
    out = tmp_path / "r"
    r = subprocess.run(_gearstudy() + ["sweep", str(study), "--out", str(out), "--fmu", str(fmu_path),
                                       "--serial", "--no-progress"],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    assert "4 points: 0 already done, 4 run (0 failed)" in r.stdout
    rows = read_results(out).to_pylist()
    assert [x["status"] for x in rows] == ["OK"] * 4
    r = subprocess.run(_gearstudy() + ["plot", str(out)], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    for name in ("efficiency_map.png", "loss_te.png", "orders_TE.png", "orders_Fn.png", "orders_T1.png"):
        png = out / name
        assert png.is_file() and png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", name
    r = subprocess.run(_gearstudy() + ["table", str(out), "efficiency", "--format", "{:.9f}"],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    assert lines[0].startswith("efficiency; columns: omega1 [rpm], rows: T_load [N.m]")
    assert lines[1].split() == ["2000", "4000"]  # rpm, converted back for display
    by = {(round(x["omega1"], 6), x["T_load"]): x["efficiency"] for x in rows}
    w2, w4 = sorted({k[0] for k in by})
    assert lines[2].split() == ["10", f"{by[(w2, 10.0)]:.9f}", f"{by[(w4, 10.0)]:.9f}"]


def test_a_bad_study_file_is_refused_with_a_message(fmu_path, tmp_path):
    study = tmp_path / "bad.toml"
    study.write_text('[grid]\nomega1 = ["3000 rps"]\n')
    r = subprocess.run(_gearstudy() + ["sweep", str(study), "--out", str(tmp_path / "r"),
                                       "--fmu", str(fmu_path), "--serial"],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 2
    assert "omega1" in r.stderr and "'rps'" in r.stderr and '"rpm"' in r.stderr, r.stderr
    assert not (tmp_path / "r").exists()
