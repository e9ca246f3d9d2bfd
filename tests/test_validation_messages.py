"""Through FMI: a refused gear pair fails fmi2ExitInitializationMode and the logged
message names the parameter that repairs it with its limit (docs/model.md §2). The
limits are checked in Rust (tests/gear_geometry_advice.rs); here the issue's case is
run through FMPy: z1 = 10 with the other defaults was blamed on x2 before, which
cannot repair it."""

from __future__ import annotations

import pytest
from fmpy import simulate_fmu


def messages_of(fmu_path, start_values):
    log = []

    def logger(component, instance, status, category, message):
        log.append(message.decode() if isinstance(message, bytes) else str(message))

    with pytest.raises(Exception):
        simulate_fmu(str(fmu_path), stop_time=1e-3, start_values=start_values, logger=logger,
                     validate=False)
    return "\n".join(log)


def test_small_pinion_names_z1_and_its_limit(fmu_path):
    text = messages_of(fmu_path, {"z1": 10})
    assert "parameter z1 = 10" in text, text
    assert "z1 >= 13" in text and "x1 >= 0.2002" in text and "h_aP <= 0.7653" in text, text
    assert "x2, z2 alone cannot" in text, text


def test_twelve_teeth_refused_thirteen_accepted(fmu_path):
    assert "z1 >= 13" in messages_of(fmu_path, {"z1": 12})
    res = simulate_fmu(str(fmu_path), stop_time=1e-3, start_values={"z1": 13}, validate=False)
    assert res["time"][-1] == pytest.approx(1e-3)


def test_narrow_helical_face_names_b(fmu_path):
    text = messages_of(fmu_path, {"a_w_set": 74.5e-3, "b": 1e-3})
    assert "parameter b = 0.001" in text and "b >= 0.006166" in text, text
