"""The minimal C master of the README (examples/c/minimal_master.c) compiles, runs the
extracted .fmu through dlopen and plain fmi2* calls, and gets what FMPy gets for the
same case. Its hard-coded value references are checked against modelDescription.xml."""

from __future__ import annotations

import io
import re
import shutil
import subprocess
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

import numpy as np
import pytest
from fmpy import simulate_fmu

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "examples" / "c" / "minimal_master.c"


def test_value_references_match_the_model_description(fmu_path):
    md = ET.fromstring(zipfile.ZipFile(fmu_path).read("modelDescription.xml"))
    vrs = {sv.get("name"): int(sv.get("valueReference")) for sv in md.iter("ScalarVariable")}
    used = re.findall(r"(\d+) /\* (\w+) \*/", SRC.read_text())
    used = [(vr, n) for vr, n in used if not n.startswith("fmi2")]  # enum constants
    assert {n for _, n in used} >= {"mu", "T1", "Fn"}
    for vr, name in used:
        assert vrs[name] == int(vr), f"{name}: {vr} in the C example, {vrs[name]} in the XML"


@pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler")
def test_c_master_runs_and_agrees_with_fmpy(fmu_path, tmp_path):
    z = zipfile.ZipFile(fmu_path)
    z.extractall(tmp_path / "fmu")
    guid = ET.fromstring(z.read("modelDescription.xml")).get("guid")
    exe = tmp_path / "minimal_master"
    subprocess.run(["cc", "-std=c99", "-Wall", "-Werror", str(SRC), "-o", str(exe), "-ldl"],
                   check=True)
    out = subprocess.run([str(exe), str(tmp_path / "fmu"), guid, "0.1"], check=True,
                         capture_output=True, text=True).stdout
    c = np.genfromtxt(io.StringIO(out), delimiter=",", names=True)
    assert len(c) == 100
    py = simulate_fmu(str(fmu_path), stop_time=0.01, output_interval=1e-4, start_values={"mu": 0.1},
                      output=["T1", "Fn"], validate=False)
    # same FMU, same steps, same tolerance (the default experiment's): same numbers
    for n in ("T1", "Fn"):
        np.testing.assert_allclose(c[n], py[n][1:], rtol=1e-9, atol=0)
