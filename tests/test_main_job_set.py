"""--set NAME=VALUE[unit] of the main job (scripts/case_values.py): conversions with the
units the .fmu declares, checked against independent conversions; bad names, units
and types give a message that says what to write."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import pytest
from fmpy import read_model_description

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "scripts"))
from case_values import SetError, parse_set  # noqa: E402


@pytest.fixture(scope="module")
def md(fmu_path):
    return read_model_description(str(fmu_path))


@pytest.mark.parametrize("text, name, want", [
    ("omega1=1500rpm", "omega1", 1500 * 2 * math.pi / 60),
    ("beta=15deg", "beta", math.radians(15)),
    ("beta = -15 deg", "beta", math.radians(-15)),
    ("mu=0.1", "mu", 0.1),
    ("k1.x=150N/um", "k1.x", 150e6),
    ("k2.z=80N/mm", "k2.z", 80e3),
    ("b=20mm", "b", 0.020),
    ("x1=0.25", "x1", 0.25),
    ("T_load=0.05kN.m", "T_load", 50.0),
    ("T_load=50N.m", "T_load", 50.0),
    ("a_w_set=75000µm", "a_w_set", 0.075),
    ("h_max=0.05ms", "h_max", 5e-5),
])
def test_values_are_converted_to_si(md, text, name, want):
    n, v = parse_set(md, text)
    assert n == name
    assert math.isclose(v, want, rel_tol=1e-12), (v, want)


def test_integers_stay_integers(md):
    assert parse_set(md, "z1=31") == ("z1", 31)
    with pytest.raises(SetError, match="whole number"):
        parse_set(md, "z1=31.5")


@pytest.mark.parametrize("text, words", [
    ("mu=0.1rpm", ["unit 'rpm'", "mu"]),
    ("omega1=3000rps", ["rad/s", "rpm"]),
    ("muu=0.1", ["no variable 'muu'", "mu"]),
    ("T1=5", ["output"]),
    ("omega1", ["NAME=VALUE"]),
])
def test_bad_settings_say_what_to_write(md, text, words):
    with pytest.raises(SetError) as e:
        parse_set(md, text)
    for w in words:
        assert w in str(e.value), str(e.value)


def test_steady_plan_uses_the_periodic_initialization_when_the_fmu_has_it():
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "scripts"))
    from main_job import PERIODIC_INIT, steady_plan

    with_init = {"mu", "omega1", "initialization"}
    assert steady_plan(with_init, {"mu": 0.1}) == ({"mu": 0.1, "initialization": PERIODIC_INIT}, True)
    # a user's choice wins: from rest, the transient is cut
    assert steady_plan(with_init, {"initialization": 1}) == ({"initialization": 1}, False)
    # an FMU without the parameter: nothing added, transient cut
    assert steady_plan({"mu", "omega1"}, {"mu": 0.1}) == ({"mu": 0.1}, False)
