"""The damping studies (docs/damping.md) at a reduced size: examples/studies/damping_mu.toml at
one speed and mu = 0, 0.05, and damping_laws.toml with laws 1 and 4 at one speed. The modal
columns come from the crate's `periodic --damping` (built by `cargo build --release`)."""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import pytest

from gearstudy import read_results, study_from_dict, sweep
from gearstudy.units import StudyError

ROOT = Path(__file__).resolve().parent.parent
STUDIES = ROOT / "examples" / "studies"
PROGRAM = ROOT / "target" / "release" / "periodic"

pytestmark = pytest.mark.skipif(not PROGRAM.is_file(), reason="cargo build --release --bin periodic")


def _reduced(name: str, grid: dict, fmu_path) -> object:
    with open(STUDIES / name, "rb") as f:
        data = tomllib.load(f)
    data["grid"].update(grid)
    data.pop("study", None)
    return study_from_dict(data, base=STUDIES, fmu=fmu_path)


def test_damping_against_mu_reduced(fmu_path, tmp_path):
    study = _reduced("damping_mu.toml", {"omega1": ["3000 rpm"], "mu": [0.0, 0.05]}, fmu_path)
    sweep(study, out=tmp_path / "r", serial=True, progress=False)
    rows = sorted(read_results(tmp_path / "r").to_pylist(), key=lambda r: r["mu"])
    assert len(rows) == 2
    free, rough = rows
    for r in rows:
        assert r["status"] == "OK", r["message"]
        assert 0.0 <= r["damping.shift"] < 1.0
        for i in range(1, 7):
            assert r[f"mode{i}.name"], f"mode {i} has no name"
            assert 500.0 < r[f"mode{i}.f"] < 2000.0
            assert 0.0 < r[f"mode{i}.zeta"] < 0.1
    # the friction-free point is its own reference: nothing added
    for i in range(1, 7):
        assert abs(free[f"mode{i}.dzeta"]) <= 1e-6 * free[f"mode{i}.zeta"]
    # mu = 0.05: the same modes (frequencies within 0.2 %), each more damped, the torsion
    # mode (the lowest) by 1e-2 (0.0260 -> 0.0376 measured)
    for i in range(1, 7):
        assert rough[f"mode{i}.f"] == pytest.approx(free[f"mode{i}.f"], rel=2e-3)
        assert rough[f"mode{i}.dzeta"] > 0.0
        assert rough[f"mode{i}.zeta"] - free[f"mode{i}.zeta"] == pytest.approx(rough[f"mode{i}.dzeta"],
                                                                             abs=1e-6)
    assert "torsion" in rough["mode1.name"]
    assert 0.005 < rough["mode1.dzeta"] < 0.02


def test_damping_for_the_friction_laws_reduced(fmu_path, tmp_path):
    study = _reduced("damping_laws.toml", {"omega1": ["6000 rpm"], "friction_law": [1, 4]}, fmu_path)
    sweep(study, out=tmp_path / "r", serial=True, progress=False)
    rows = sorted(read_results(tmp_path / "r").to_pylist(), key=lambda r: r["friction_law"])
    assert [r["friction_law"] for r in rows] == [1, 4]
    for r in rows:
        assert r["status"] in ("OK", "Warning"), r["message"]
        assert all(math.isfinite(r[f"mode{i}.zeta"]) for i in range(1, 7))
    # law 4's coefficient (mu_eff, the EHL law at the default oil) is below law 1's 0.05
    # and so is the damping it adds to the torsion mode
    assert rows[1]["mu_eff.mean"] < 0.05
    assert 0.0 < rows[1]["mode1.dzeta"] < rows[0]["mode1.dzeta"]


def test_a_missing_damping_program_is_a_message(fmu_path, tmp_path):
    with pytest.raises(StudyError, match="cargo build --release --bin periodic"):
        study_from_dict({"damping": {"program": str(tmp_path / "nothing")}}, fmu=fmu_path)


def test_a_doubtful_branch_marks_the_row(fmu_path, tmp_path, monkeypatch):
    """Above damping.SHIFT_WARN (0.5 of pi/T_m) the row carries a warning; forced here by
    lowering the threshold below the point's shift (0.03 at 3000 rpm, mu = 0.05)."""
    from gearstudy import damping

    monkeypatch.setattr(damping, "SHIFT_WARN", 0.0)
    study = _reduced("damping_mu.toml", {"omega1": ["3000 rpm"], "mu": [0.05]}, fmu_path)
    sweep(study, out=tmp_path / "r", serial=True, progress=False)
    (row,) = read_results(tmp_path / "r").to_pylist()
    assert row["status"] == "Warning"
    assert "damping: an exponent moved" in row["message"]
    assert 0.0 < row["damping.shift"] < 0.5
