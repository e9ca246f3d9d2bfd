"""(d) Rollback: get the FMU state at t1, step to t2, set the state, step to t2
again -> bit-identical outputs; serialise, continue in a fresh process ->
bit-identical; corrupted, truncated or foreign buffers -> fmi2Error with a log
message, never a crash."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from helpers.fmu_harness import FMI2_ERROR, Recorder, call_status

H = 1e-4
N1 = 100  # t1 = 10 ms (inside the bearing transient: every state is moving)
N2 = 100  # t2 = 20 ms
HELPER = Path(__file__).resolve().parent / "helpers" / "continue_from_state.py"


def _steps(inst, n, names):
    rec = Recorder(inst, names)
    for _ in range(n):
        inst.do_step(H, no_set_prior=False)
        rec.sample()
    return rec.trajectory()


def _assert_identical(a, b, names, label):
    bad = [n for n in names if not np.array_equal(a[n], b[n])]
    assert not bad, f"{label}: not bit-identical: {bad[:10]}"


@pytest.fixture(scope="module")
def rollback(pkg):
    """One instance: step to t1, take and serialise the state, step to t2
    (first pass), restore, step to t2 again (second pass)."""
    names = pkg.real_outputs + pkg.int_outputs + pkg.bool_outputs
    inst = pkg.instance("rollback")
    inst.initialize()
    for _ in range(N1):
        inst.do_step(H, no_set_prior=False)
    t1 = inst.time
    state = inst.slave.getFMUstate()
    blob = inst.slave.serializeFMUstate(state)
    first = _steps(inst, N2, names)
    inst.slave.setFMUstate(state)
    inst.time = t1
    second = _steps(inst, N2, names)
    # restore once more after a *different* continuation (longer steps)
    inst.slave.setFMUstate(state)
    inst.time = t1
    inst.do_step(7 * H, no_set_prior=False)
    inst.slave.setFMUstate(state)
    inst.time = t1
    third = _steps(inst, N2, names)
    inst.slave.freeFMUstate(state)
    inst.terminate_and_free()
    return names, t1, blob, first, second, third


def test_set_state_replays_bit_identically(rollback):
    names, _, _, first, second, third = rollback
    _assert_identical(first, second, names, "after setFMUstate")
    _assert_identical(first, third, names, "after setFMUstate following another continuation")


def test_serialized_state_continues_identically_in_fresh_process(pkg, rollback, tmp_path):
    names, t1, blob, first, _, _ = rollback
    state_file = tmp_path / "state.bin"
    state_file.write_bytes(blob)
    cp = subprocess.run(
        [sys.executable, str(HELPER), str(pkg.fmu_path), str(pkg.unzip_dir), str(state_file),
         float(t1).hex(), float(H).hex(), str(N2)],
        capture_output=True, text=True, timeout=600,
    )
    assert cp.returncode == 0, cp.stderr
    out = json.loads(cp.stdout)
    for n in pkg.real_outputs:
        got = np.array([float.fromhex(x) for x in out[n]])
        assert np.array_equal(got, first[n]), f"{n} differs after deserialisation in a fresh process"


def test_deserialize_into_other_instance_same_process(pkg, rollback):
    names, t1, blob, first, _, _ = rollback
    inst = pkg.instance("other")
    inst.initialize()
    state = inst.slave.deSerializeFMUstate(blob)
    inst.slave.setFMUstate(state)
    inst.slave.freeFMUstate(state)
    inst.time = t1
    again = _steps(inst, N2, names)
    inst.terminate_and_free()
    _assert_identical(first, again, names, "deserialised into another instance")


def _corruptions(blob: bytes) -> dict[str, bytes]:
    mid = len(blob) // 2
    flipped_mid = bytearray(blob)
    flipped_mid[mid] ^= 0xFF
    flipped_last = bytearray(blob)
    flipped_last[-1] ^= 0x01
    flipped_first = bytearray(blob)
    flipped_first[0] ^= 0x5A
    rng = np.random.default_rng(12345)
    return {
        "flipped-middle-byte": bytes(flipped_mid),
        "flipped-last-byte": bytes(flipped_last),
        "flipped-magic": bytes(flipped_first),
        "truncated": blob[: len(blob) - 9],
        "extended": blob + b"\x00" * 8,
        "random": rng.integers(0, 256, len(blob), dtype=np.uint8).tobytes(),
        "tiny": b"\x01\x02\x03",
    }


@pytest.mark.parametrize("kind", ["flipped-middle-byte", "flipped-last-byte", "flipped-magic",
                                  "truncated", "extended", "random", "tiny"])
def test_corrupted_buffer_is_rejected(pkg, rollback, kind):
    _, _, blob, _, _, _ = rollback
    bad = _corruptions(blob)[kind]
    inst = pkg.instance("corrupt", logging_on=True)
    inst.initialize()
    status = call_status(inst.slave.deSerializeFMUstate, bad)
    assert status == FMI2_ERROR, f"{kind}: status {status}"
    errors = [r for r in inst.log if r.status >= FMI2_ERROR]
    assert errors, f"{kind}: no error logged"
    assert any(pkg.fmi_name("fmi2DeSerializeFMUstate") in r.message for r in errors), inst.log_text()
    inst.free()
    # the process survives and a new instance still works
    ok = pkg.instance("after-corrupt")
    ok.initialize()
    ok.do_step(H)
    assert np.isfinite(ok.get1("T1"))
    ok.terminate_and_free()
