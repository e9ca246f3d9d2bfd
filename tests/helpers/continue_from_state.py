"""Run in a fresh Python process by test_d_rollback.py: instantiate the
extracted FMU, initialise with defaults, deserialise a saved FMU state, set it,
and continue with communication step H from t1 for n steps; print the outputs at
every communication point as JSON with float.hex() (bit-exact comparison).

usage: python continue_from_state.py FMU_PATH UNZIP_DIR STATE_FILE T1 H N
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from helpers.fmu_harness import FmuPackage, Recorder  # noqa: E402


def main() -> None:
    fmu_path, unzip_dir, state_file, t1, h, n = sys.argv[1:7]
    pkg = FmuPackage(Path(fmu_path), Path(unzip_dir))
    inst = pkg.instance("fresh-process")
    inst.initialize()
    blob = Path(state_file).read_bytes()
    state = inst.slave.deSerializeFMUstate(blob)
    inst.slave.setFMUstate(state)
    inst.slave.freeFMUstate(state)
    inst.time = float.fromhex(t1)
    rec = Recorder(inst, pkg.real_outputs)
    for _ in range(int(n)):
        inst.do_step(float.fromhex(h), no_set_prior=False)
        rec.sample()
    tr = rec.trajectory()
    out = {name: [float(x).hex() for x in tr[name]] for name in tr.names()}
    json.dump(out, sys.stdout)
    inst.terminate_and_free()


if __name__ == "__main__":
    main()
