"""What a first-time user hits (issue 25): the command-line tools end every mistake in the
input with a message that names the input and what to do, a non-zero exit status and no
Python traceback. Run as subprocesses, the way a user runs them.

Main job (scripts/main_job.py): a drive speed <= 0, a load that makes gear 2 drive gear 1,
an unknown name or Enumeration item, a bad option, a parameter the FMU refuses (the face
width b beyond the contact-line bound: the message gives the allowed b). A length without
unit that is implausible in SI is warned about.

gearstudy: a missing study file, a missing results folder, an unknown column of `table`, and
a rerun into a folder whose points (grid values) changed, which is refused unless
--overwrite.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
MAIN_JOB = REPO / "scripts" / "main_job.py"


def _main_job(fmu_path, tmp_path, *args) -> subprocess.CompletedProcess:
    cmd = [sys.executable, str(MAIN_JOB), "--fmu", str(fmu_path), "--no-periodic",
           "--out", str(tmp_path / "out"), *args]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=600)


def _gearstudy(*args) -> subprocess.CompletedProcess:
    exe = Path(sys.executable).with_name("gearstudy")
    cmd = [str(exe)] if exe.exists() else [shutil.which("gearstudy") or "gearstudy"]
    return subprocess.run(cmd + list(args), capture_output=True, text=True, timeout=600)


def _refused(r: subprocess.CompletedProcess, *words: str) -> None:
    text = r.stdout + r.stderr
    assert "Traceback" not in text, text
    assert r.returncode != 0, text
    for w in words:
        assert w in r.stderr, f"{w!r} not in: {r.stderr}"


@pytest.mark.parametrize("setting, words", [
    ("omega1=0", ["omega1 = 0 rad/s", "omega1=1500rpm"]),
    ("omega1=-1500rpm", ["omega1 = -157.08 rad/s", "-1500 rpm", "> 0"]),
    ("T_load=-200", ["T_load = -200 N m", "d_phi omega2", "T_load >= -103.4 N m"]),
    ("initialization=sleep", ["initialization", "rest (= 1)", "periodic (= 3)"]),
    ("muu=0.1", ["'muu'", "did you mean mu"]),
    ("mu=0.1rpm", ["unit 'rpm'", "mu"]),
    ("z2=0", ["z2 = 0", "at least 5 teeth"]),
    ("z1=0", ["z1 = 0", "at least 5 teeth"]),
    ("z2=1e30", ["z2 = 1e+30", "32-bit"]),
])
def test_main_job_refuses_bad_settings_by_name(fmu_path, tmp_path, setting, words):
    r = _main_job(fmu_path, tmp_path, "--set", setting)
    _refused(r, *words)
    assert r.returncode == 2


def test_main_job_refuses_bad_options(fmu_path, tmp_path):
    _refused(_main_job(fmu_path, tmp_path, "--stop-time", "-1"), "--stop-time")
    _refused(_main_job(fmu_path, tmp_path, "--output-interval", "0"), "--output-interval")
    r = subprocess.run([sys.executable, str(MAIN_JOB), "--fmu", str(tmp_path / "none.fmu")],
                       capture_output=True, text=True, timeout=600)
    _refused(r, "--fmu", "none.fmu")
    # a file that is not an FMU (found by review: zipfile.BadZipFile traceback)
    (tmp_path / "notanfmu.fmu").write_text("not a zip")
    r = subprocess.run([sys.executable, str(MAIN_JOB), "--fmu", str(tmp_path / "notanfmu.fmu")],
                       capture_output=True, text=True, timeout=600)
    _refused(r, "--fmu", "notanfmu.fmu", "not an FMU")
    _refused(_gearstudy("sweep", str(REPO / "examples" / "studies" / "efficiency_map.toml"),
                        "--fmu", str(tmp_path / "notanfmu.fmu"), "--out", str(tmp_path / "gs")),
             "notanfmu.fmu", "not an FMU")
    (tmp_path / "afile").write_text("")
    r = subprocess.run([sys.executable, str(MAIN_JOB), "--fmu", str(fmu_path), "--no-periodic",
                        "--out", str(tmp_path / "afile" / "out")], capture_output=True, text=True, timeout=600)
    _refused(r, "afile", "--out")


def test_main_job_reports_the_allowed_face_width(fmu_path, tmp_path):
    """b = 3000 mm on the default pair: the FMU refuses it; the message names b and the
    largest b the contact-line loop takes (eps_alpha + eps_beta <= 60)."""
    r = _main_job(fmu_path, tmp_path, "--set", "b=3000mm")
    _refused(r, "parameter b = 3", "b <= 1.0740e0 m (1074.0 mm)")
    assert r.returncode == 1


def test_enumeration_items_are_accepted_by_name(fmu_path, tmp_path):
    sys.path.insert(0, str(REPO / "scripts"))
    from case_values import parse_set, unitless_warning
    from fmpy import read_model_description

    md = read_model_description(str(fmu_path))
    assert parse_set(md, "initialization=rest") == ("initialization", 1)
    assert parse_set(md, "initialization=periodic") == ("initialization", 3)
    assert parse_set(md, "on_lift_off=discard") == ("on_lift_off", 2)
    assert parse_set(md, "initialization=2") == ("initialization", 2)
    # a unitless length or speed that is implausible in SI is warned about, with the unit
    assert "m_n=3mm" in unitless_warning(md, "m_n=3")
    assert "omega1=1800rpm" in unitless_warning(md, "omega1=1800")
    assert "beta=15deg" in unitless_warning(md, "beta=15")
    assert unitless_warning(md, "m_n=3mm") is None
    assert unitless_warning(md, "m_n=0.003") is None
    assert unitless_warning(md, "omega1=300") is None


def test_gearstudy_missing_inputs_get_messages(fmu_path, tmp_path):
    _refused(_gearstudy("sweep", str(tmp_path / "nothere.toml"), "--fmu", str(fmu_path), "--serial"),
             "study file", "nothere.toml", "does not exist")
    _refused(_gearstudy("plot", str(tmp_path / "noresults")), "noresults", "do not exist")
    _refused(_gearstudy("table", str(tmp_path / "noresults")), "noresults", "do not exist")
    bad = tmp_path / "kind.toml"
    bad.write_text('[grid]\nomega1 = ["2000 rpm"]\n[window]\nperiods = "ten"\n')
    _refused(_gearstudy("sweep", str(bad), "--fmu", str(fmu_path), "--serial"), "kind.toml", "ten")
    (tmp_path / "empty").mkdir()
    _refused(_gearstudy("table", str(tmp_path / "empty")), "empty", "holds no results")


STUDY = """
[grid]
omega1 = ["2000 rpm", "4000 rpm"]
T_load = [{t_load}, 50.0]
[fixed]
mu = 0.04
[window]
transient = "2 ms"
periods = 2
samples_per_period = 8
n_orders = 2
"""


def test_gearstudy_unknown_column_and_changed_grid(fmu_path, tmp_path):
    study = tmp_path / "s.toml"
    out = tmp_path / "r"
    study.write_text(STUDY.format(t_load=10.0))
    r = _gearstudy("sweep", str(study), "--out", str(out), "--fmu", str(fmu_path), "--serial", "--no-progress")
    assert r.returncode == 0, r.stderr
    assert "4 run (0 failed)" in r.stdout
    _refused(_gearstudy("table", str(out), "effciency"), "no column 'effciency'", "did you mean efficiency")
    _refused(_gearstudy("table", str(out), "efficiency", "--x", "omega"), "omega", "--x")
    _refused(_gearstudy("table", str(out), "status"), "'status' holds text", "efficiency")
    _refused(_gearstudy("plot", str(out), "--x", "omega"), "omega", "--x")
    # the grid's values changed (the names did not): refused, nothing run, the old rows kept
    study.write_text(STUDY.format(t_load=20.0))
    r = _gearstudy("sweep", str(study), "--out", str(out), "--fmu", str(fmu_path), "--serial", "--no-progress")
    _refused(r, "the points", "[grid]", "--overwrite")
    from gearstudy import read_results

    assert sorted(read_results(out).column("T_load").to_pylist()) == [10.0, 10.0, 50.0, 50.0]
    # --overwrite starts over with the new grid only
    r = _gearstudy("sweep", str(study), "--out", str(out), "--fmu", str(fmu_path), "--serial",
                   "--no-progress", "--overwrite")
    assert r.returncode == 0, r.stderr
    assert sorted(read_results(out).column("T_load").to_pylist()) == [20.0, 20.0, 50.0, 50.0]
    # the same grid again: nothing to run
    r = _gearstudy("sweep", str(study), "--out", str(out), "--fmu", str(fmu_path), "--serial", "--no-progress")
    assert r.returncode == 0 and "all done already" in r.stdout, r.stdout + r.stderr


def test_gearstudy_warns_about_bare_numbers_implausible_in_si(fmu_path, tmp_path):
    study = tmp_path / "bare.toml"
    study.write_text('[grid]\nomega1 = {start = 1000, stop = 2000, num = 2}\n[fixed]\nmu = 0.05\n'
                     '[window]\ntransient = "2 ms"\nperiods = 2\nsamples_per_period = 8\nn_orders = 2\n')
    r = _gearstudy("sweep", str(study), "--out", str(tmp_path / "r"), "--fmu", str(fmu_path), "--serial",
                   "--no-progress")
    assert r.returncode == 0, r.stderr
    assert "omega1 = 1000 has no unit, so it is 1000 rad/s" in r.stderr and '"1000 rpm"' in r.stderr, r.stderr
    assert "mu = " not in r.stderr  # dimensionless: nothing to say
