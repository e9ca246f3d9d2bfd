"""gearstudy's efficiency column against the analytic gear loss factor: with Coulomb friction
(constant mu) and rigid bearings the mean loss is mu P_in H_V (H_V: the FMU's calculated
parameter, the analytic loss factor of the pair), so the efficiency is 1 - mu H_V."""

from __future__ import annotations

import pytest

from gearstudy import read_results, study_from_dict, sweep

STIFF = {f"k{i}.{a}": "1e10 N/m" for i in (1, 2) for a in "xyz"}


def test_efficiency_equals_one_minus_mu_h_v_with_stiff_bearings(fmu_path, tmp_path):
    study = study_from_dict(
        {
            "fixed": {"mu": 0.05, **STIFF},
            "grid": {"omega1": ["2000 rpm", "3000 rpm"], "T_load": [10.0, 40.0]},
            "outputs": {"names": ["P_in", "P_loss", "T1", "H_V"], "orders": []},
            # the bearing modes decay in ~3 ms at 1e10 N/m; 20 ms leaves them at ~1e-3
            "window": {"transient": "20 ms", "periods": 10, "samples_per_period": 16},
        },
        fmu=fmu_path,
    )
    sweep(study, out=tmp_path / "r", serial=True, progress=False)
    rows = read_results(tmp_path / "r").to_pylist()
    assert len(rows) == 4
    for r in rows:
        assert r["status"] == "OK", r["message"]
        assert r["init"] in ("rest+cut", "periodic")
        h_v = r["H_V"]
        assert 0.05 < h_v < 0.5  # a loss factor of a usual pair (Niemann: ~0.1-0.2)
        assert r["efficiency"] == pytest.approx(1 - 0.05 * h_v, abs=1e-3)
        # tighter: the loss itself within 2 % of mu P_in H_V
        assert r["P_loss.mean"] == pytest.approx(0.05 * h_v * r["P_in.mean"], rel=0.02)
        assert r["efficiency"] == pytest.approx(1 - r["P_loss.mean"] / r["P_in.mean"], rel=1e-12)
        # the mean input power (from E_in over the window) is the driving torque times the
        # speed, averaged independently from the sampled T1 over whole mesh periods (T1 has
        # kinks where contact lines enter and leave: the rectangle rule over 16 samples per
        # period is good to ~3e-4 here)
        assert r["P_in.mean"] == pytest.approx(r["T1.mean"] * r["omega1"], rel=1e-3)


def test_the_window_starts_on_the_steady_state_the_fmu_offers(fmu_path, tmp_path):
    """Today's FMU starts from rest (no `initialization` parameter): the documented transient
    cut (100 ms) applies. Once the FMU offers initialization = periodic, the window starts at
    once."""
    study = study_from_dict({"fixed": {"T_load": 10.0},
                             "window": {"periods": 2, "samples_per_period": 8}}, fmu=fmu_path)
    sweep(study, out=tmp_path / "r", serial=True, progress=False)
    (row,) = read_results(tmp_path / "r").to_pylist()
    assert row["status"] == "OK", row["message"]
    if "initialization" in study.catalog:
        assert (row["init"], row["t_window"]) == ("periodic", 0.0)
    else:
        assert (row["init"], row["t_window"]) == ("rest+cut", 0.1)
