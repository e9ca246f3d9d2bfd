"""Friction law 5 (Benedict & Kelley 1961, docs/friction.md) on the packaged .fmu:
friction_law = 5 is accepted, mu_eff follows the law along the lines (between the
coefficients of the formula at the extremes of the sliding on the line of action), the
energy balance closes, and a roughness the formula has no value for (Ra >= 1.27 um) is
rejected by name."""

from __future__ import annotations

import pytest
from fmpy import simulate_fmu


def _run(fmu_path, start, output, stop, log=None):
    messages = [] if log is None else log

    def logger(component, instance, status, category, message):
        messages.append((int(status), message.decode()))

    return simulate_fmu(str(fmu_path), stop_time=stop, output_interval=1e-3, start_values=start,
                        output=output, logger=logger, relative_tolerance=1e-8)


def test_law5_runs_with_closed_energy_balance(fmu_path):
    r = _run(fmu_path, {"friction_law": 5, "T_load": 50.0},
             ["mu_eff", "E_in", "E_loss", "E_damp", "E_load", "E_kin", "E_pot"], stop=0.02)
    bal = (r["E_in"][-1] - r["E_loss"][-1] - r["E_damp"][-1] - r["E_load"][-1]
           - (r["E_kin"][-1] - r["E_kin"][0]) - (r["E_pot"][-1] - r["E_pot"][0]))
    assert abs(bal) <= 1e-8 * r["E_in"][-1], bal / r["E_in"][-1]
    # default pair at 3000 rpm, 50 N m: the load-weighted mean of mu(s) lies near 0.074
    # (docs/friction.md, efficiency map), well above law 1's default mu = 0.05
    mu = r["mu_eff"][5:]
    assert 0.065 < mu.min() and mu.max() < 0.085, (mu.min(), mu.max())


def test_law5_rejects_a_roughness_beyond_the_formula(fmu_path):
    log = []
    with pytest.raises(Exception):
        _run(fmu_path, {"friction_law": 5, "Ra": 1.3e-6}, ["mu_eff"], stop=1e-3, log=log)
    assert any("Ra" in m and "friction_law = 5" in m for _, m in log), log
    # the same roughness is fine for the other laws
    _run(fmu_path, {"friction_law": 4, "Ra": 1.3e-6}, ["mu_eff"], stop=1e-3)
