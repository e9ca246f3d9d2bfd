"""gearstudy: values in display units are converted with the modelDescription's factors, and
the reductions over whole mesh periods recover known harmonics."""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
import zipfile

import numpy as np
import pytest

from gearstudy import Catalog, StudyError, study_from_dict
from gearstudy.reduce import mean_over_periods, order_amplitudes, peak_to_peak


@pytest.fixture(scope="module")
def catalog(fmu_path):
    return Catalog.from_fmu(fmu_path)


def _display_factor(fmu_path, unit, display):
    """The factor of a display unit, read from the .fmu's XML directly (not through FMPy)."""
    with zipfile.ZipFile(fmu_path) as z:
        root = ET.fromstring(z.read("modelDescription.xml"))
    for u in root.iter("Unit"):
        if u.get("name") == unit:
            for d in u.iter("DisplayUnit"):
                if d.get("name") == display:
                    return float(d.get("factor")), float(d.get("offset", "0"))
    raise AssertionError(f"{unit}/{display} not in the modelDescription")


def test_rpm_and_deg_convert_with_the_model_description_factors(catalog, fmu_path):
    # physics: 3000 rev/min = 3000 * 2 pi / 60 rad/s; 20 deg = 20 pi / 180 rad
    w = catalog.to_fmu_value("omega1", "3000 rpm")
    assert w == pytest.approx(100 * math.pi, rel=1e-15, abs=0)
    assert abs(w - 314.1592653589793) < 1e-12
    b = catalog.to_fmu_value("beta", "20 deg")
    assert b == pytest.approx(math.radians(20), rel=1e-15, abs=0)
    # and exactly (display - offset) / factor with the factors the XML declares
    f, o = _display_factor(fmu_path, "rad/s", "rpm")
    assert w == (3000 - o) / f
    f, o = _display_factor(fmu_path, "rad", "deg")
    assert b == (20 - o) / f
    # the variable's own unit and plain numbers pass unchanged; mm -> m
    assert catalog.to_fmu_value("omega1", "314.5 rad/s") == 314.5
    assert catalog.to_fmu_value("T_load", 12) == 12.0
    assert catalog.to_fmu_value("m_n", "2 mm") == pytest.approx(0.002, rel=1e-15)
    assert catalog.to_fmu_value("z1", 31) == 31 and isinstance(catalog.to_fmu_value("z1", 31), int)


def test_bad_values_name_the_variable_and_the_fix(catalog):
    with pytest.raises(StudyError, match=r"omega1.*'rps'.*\"rpm\""):
        catalog.to_fmu_value("omega1", "50 rps")
    with pytest.raises(StudyError, match=r"'omega'.*did you mean .*omega1"):
        catalog.to_fmu_value("omega", 1.0)
    with pytest.raises(StudyError, match=r"'T1' is a output"):
        catalog.to_fmu_value("T1", 1.0)
    with pytest.raises(StudyError, match=r"z1.*whole number"):
        catalog.to_fmu_value("z1", 27.5)


def test_study_designs(fmu_path):
    s = study_from_dict(
        {
            "fixed": {"T_load": 5, "mu": 0.02},
            "grid": {"omega1": ["1000 rpm", "2000 rpm"], "mu": [0.01, 0.03, 0.05]},
            "lhs": {"n": 4, "seed": 3, "x1": [-0.2, 0.4]},
        },
        fmu=fmu_path,
    )
    assert len(s.points) == 2 * 3 * 4
    assert s.varied == ["omega1", "mu", "x1"]
    assert all(p["T_load"] == 5.0 and p["mu"] in (0.01, 0.03, 0.05) for p in s.points)
    # Latin hypercube: one sample in each quarter of the range
    xs = sorted({p["x1"] for p in s.points})
    assert [int((x + 0.2) / 0.6 * 4) for x in xs] == [0, 1, 2, 3]
    with pytest.raises(StudyError, match=r"\[window\] unknown key.*'period'.*allowed.*'periods'"):
        study_from_dict({"window": {"period": 4}}, fmu=fmu_path)
    with pytest.raises(StudyError, match=r"\[list\].*equal lengths"):
        study_from_dict({"list": {"mu": [0.1, 0.2], "T_load": [1, 2, 3]}}, fmu=fmu_path)


def test_reductions_over_whole_periods_recover_known_harmonics():
    # y(t) = 3 + 0.5 cos(2 pi t/T) + 0.25 sin(4 pi t/T + 1) + 0.1 cos(6 pi t / T), 7 periods
    n, m = 7, 16
    t = np.arange(n * m + 1) / m
    y = 3 + 0.5 * np.cos(2 * np.pi * t) + 0.25 * np.sin(4 * np.pi * t + 1) + 0.1 * np.cos(6 * np.pi * t)
    assert mean_over_periods(y) == pytest.approx(3.0, abs=1e-14)
    amps = order_amplitudes(y, n, 4)
    assert amps == pytest.approx([0.5, 0.25, 0.1, 0.0], abs=1e-13)
    fine = np.linspace(0, 1, 100001)
    exact = 3 + 0.5 * np.cos(2 * np.pi * fine) + 0.25 * np.sin(4 * np.pi * fine + 1) + 0.1 * np.cos(6 * np.pi * fine)
    assert peak_to_peak(y) == pytest.approx(np.ptp(exact), rel=0.05)
