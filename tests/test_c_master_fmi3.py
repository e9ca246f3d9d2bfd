"""The minimal C master for FMI 3.0 (examples/c/minimal_master_fmi3.c) compiles, runs the
extracted GearedRotor-fmi3.fmu through dlopen and plain fmi3* calls, and gets what FMPy
gets for the same case through the FMI 2.0 .fmu (the two are bit-identical through FMPy,
test_fmi3.py). It reads the instantiation token and the value references from
modelDescription.xml by name (none is written into the source)."""

from __future__ import annotations

import io
import re
import shutil
import subprocess
import zipfile
from pathlib import Path

import numpy as np
import pytest
from fmpy import simulate_fmu

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "examples" / "c" / "minimal_master_fmi3.c"


def test_value_references_come_from_the_model_description():
    src = SRC.read_text()
    assert not re.findall(r"\b\d+ /\* (?:mu|T1|Fn) \*/", src)
    for name in ("mu", "T1", "Fn"):
        assert f'value_reference(xml, "{name}")' in src
    assert 'attribute(root, "instantiationToken"' in src


def _build_and_extract(fmu3_path, tmp_path):
    zipfile.ZipFile(fmu3_path).extractall(tmp_path / "fmu")
    exe = tmp_path / "minimal_master_fmi3"
    subprocess.run(["cc", "-std=c99", "-Wall", "-Werror", str(SRC), "-o", str(exe), "-ldl"],
                   check=True)
    return exe


@pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler")
def test_c_master_runs_and_agrees_with_fmpy(fmu2_path, fmu3_path, tmp_path):
    exe = _build_and_extract(fmu3_path, tmp_path)
    out = subprocess.run([str(exe), str(tmp_path / "fmu"), "0.1"], check=True,
                         capture_output=True, text=True).stdout
    c = np.genfromtxt(io.StringIO(out), delimiter=",", names=True)
    assert len(c) == 100
    py = simulate_fmu(str(fmu2_path), stop_time=0.01, output_interval=1e-4,
                      start_values={"mu": 0.1}, output=["T1", "Fn"], validate=False)
    for n in ("T1", "Fn"):
        np.testing.assert_allclose(c[n], py[n][1:], rtol=1e-9, atol=0)


@pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler")
def test_c_master_without_events_ignores_early_return(fmu3_path, tmp_path):
    """With earlyReturnAllowed and nothing leaving the validity, no step returns early and
    the results are those without it, to the bit."""
    exe = _build_and_extract(fmu3_path, tmp_path)
    run = lambda *a: subprocess.run([str(exe), str(tmp_path / "fmu"), "0.1", *a],
                                    check=True, capture_output=True, text=True)
    plain, early = run(), run("early")
    assert "early return" not in early.stderr
    assert plain.stdout == early.stdout
