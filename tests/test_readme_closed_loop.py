"""The closed-loop step loop of README "Use it in your master" runs as printed (extracted
from the README between its marker and the end of the code block, the FMU path replaced by
the one under test) and does what its comments say: the PI loop holds the motor near its
reference speed, T1 carries the load torque through the ratio."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
MARKER = "<!-- readme-closed-loop:"


def readme_block() -> str:
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    start = text.index(MARKER)
    m = re.search(r"```python\n(.*?)```", text[start:], re.S)
    assert m, "no python block after the marker"
    return m.group(1)


def test_readme_closed_loop_runs(fmu_path, tmp_path):
    code = readme_block()
    assert code.count("\n") <= 30, "the example should stay short"
    assert '"target/fmu/GearedRotor.fmu"' in code
    code = code.replace('"target/fmu/GearedRotor.fmu"', repr(str(Path(fmu_path).resolve())))
    script = tmp_path / "loop.py"
    script.write_text(code)
    r = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=300,
                       cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    last = r.stdout.strip().splitlines()[-1]
    nums = [float(x) for x in re.findall(r"-?\d+\.\d+(?:e-?\d+)?", last)]
    w, t1, omega2, fn = nums[:4]
    assert abs(w - 300.0) < 1.0, last  # the speed loop holds the reference
    assert abs(t1 - 50.0 * 27 / 41) < 0.05 * 50.0 * 27 / 41 + 1.0, last  # T1 = T_load / u
    assert abs(omega2 - w * 27 / 41) < 0.01 * omega2, last
    assert fn > 0, last
