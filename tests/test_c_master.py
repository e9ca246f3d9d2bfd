"""The minimal C master of the README (examples/c/minimal_master.c) compiles, runs the
extracted .fmu through dlopen and plain fmi2* calls, and gets what FMPy gets for the
same case. It reads the GUID and the value references from modelDescription.xml by name
(none is written into the source)."""

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
SRC = ROOT / "examples" / "c" / "minimal_master.c"


def test_value_references_come_from_the_model_description():
    """No value reference is written into the example: it looks mu, T1 and Fn up by name
    in modelDescription.xml (and the GUID there too)."""
    src = SRC.read_text()
    assert not re.findall(r"\b\d+ /\* (?:mu|T1|Fn) \*/", src)
    for name in ("mu", "T1", "Fn"):
        assert f'value_reference(xml, "{name}")' in src
    assert 'attribute(root, "guid"' in src


@pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler")
def test_c_master_runs_and_agrees_with_fmpy(fmu_path, tmp_path):
    z = zipfile.ZipFile(fmu_path)
    z.extractall(tmp_path / "fmu")
    exe = tmp_path / "minimal_master"
    subprocess.run(["cc", "-std=c99", "-Wall", "-Werror", str(SRC), "-o", str(exe), "-ldl"],
                   check=True)
    out = subprocess.run([str(exe), str(tmp_path / "fmu"), "0.1"], check=True,
                         capture_output=True, text=True).stdout
    c = np.genfromtxt(io.StringIO(out), delimiter=",", names=True)
    assert len(c) == 100
    py = simulate_fmu(str(fmu_path), stop_time=0.01, output_interval=1e-4, start_values={"mu": 0.1},
                      output=["T1", "Fn"], validate=False)
    # same FMU, same steps, same tolerance (the default experiment's): same numbers
    for n in ("T1", "Fn"):
        np.testing.assert_allclose(c[n], py[n][1:], rtol=1e-9, atol=0)
