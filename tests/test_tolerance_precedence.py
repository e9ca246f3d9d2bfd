"""Which tolerance RADAU5 runs with under FMPy's simulate_fmu: the parameter `rtol`, unless
the master passes a tolerance to fmi2SetupExperiment (FMPy: relative_tolerance), which
wins. The model description declares no default tolerance, because simulate_fmu passes a
declared one on every call and `rtol` then had no effect (seen before: rtol 1e-3 and 1e-9
gave identical results)."""

from __future__ import annotations

import numpy as np
from fmpy import simulate_fmu


def run(pkg, **kw):
    r = simulate_fmu(str(pkg.fmu_path), stop_time=0.005, output_interval=1e-4, output=["T1", "TE"], **kw)
    return np.asarray(r["TE"])


def test_rtol_applies_unless_the_master_passes_a_tolerance(pkg):
    loose = run(pkg, start_values={"rtol": 1e-3})
    tight = run(pkg, start_values={"rtol": 1e-10})
    ref = np.ptp(tight)
    # rtol takes effect: a loose run differs from a tight one by far more than round-off.
    assert np.max(np.abs(loose - tight)) > 1e-6 * ref
    # A tolerance from the master overrides the parameter.
    a = run(pkg, start_values={"rtol": 1e-3}, relative_tolerance=1e-10)
    assert np.array_equal(a, tight)
    assert pkg.md.defaultExperiment.tolerance is None
