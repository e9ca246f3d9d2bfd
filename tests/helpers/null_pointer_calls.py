"""Run in a child process by test_f_misuse.py: call the FMU's C functions with
NULL pointers and other raw misuse that FMPy's wrappers cannot express, and
print the returned statuses as JSON. The test checks that this process exits
normally (no crash) and that every call returned fmi2Error.

usage: python null_pointer_calls.py FMU_PATH UNZIP_DIR
"""

from __future__ import annotations

import ctypes as C
import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from helpers.fmu_harness import FmuPackage  # noqa: E402


def main() -> None:
    pkg = FmuPackage(Path(sys.argv[1]), Path(sys.argv[2]))
    inst = pkg.instance("null-pointers", logging_on=True)
    inst.initialize()
    lib = inst.slave.dll
    c = C.c_void_p(inst.slave.component)
    vr = (C.c_uint * 1)(pkg.vr("T1"))
    val = (C.c_double * 1)()
    size = C.c_size_t(0)
    state = C.c_void_p()

    def f(name, restype, argtypes):
        fn = getattr(lib, name)
        fn.restype = restype
        fn.argtypes = argtypes
        return fn

    vp, dbl, sz, i = C.c_void_p, C.c_double, C.c_size_t, C.c_int
    statuses = {}
    statuses["DoStep(NULL component)"] = f("fmi2DoStep", i, [vp, dbl, dbl, i])(None, 0.0, 1e-4, 1)
    statuses["GetReal(NULL component)"] = f("fmi2GetReal", i, [vp, vp, sz, vp])(None, vr, 1, val)
    statuses["GetReal(NULL vr, nvr=1)"] = f("fmi2GetReal", i, [vp, vp, sz, vp])(c, None, 1, val)
    statuses["GetReal(NULL values)"] = f("fmi2GetReal", i, [vp, vp, sz, vp])(c, vr, 1, None)
    statuses["SetReal(NULL values)"] = f("fmi2SetReal", i, [vp, vp, sz, vp])(c, vr, 1, None)
    statuses["GetFMUstate(NULL out)"] = f("fmi2GetFMUstate", i, [vp, vp])(c, None)
    statuses["SetFMUstate(NULL state)"] = f("fmi2SetFMUstate", i, [vp, vp])(c, None)
    statuses["SerializedFMUstateSize(NULL state)"] = f(
        "fmi2SerializedFMUstateSize", i, [vp, vp, vp])(c, None, C.byref(size))
    statuses["DeSerializeFMUstate(NULL buffer)"] = f(
        "fmi2DeSerializeFMUstate", i, [vp, vp, sz, vp])(c, None, 16, C.byref(state))
    statuses["SetupExperiment(NULL component)"] = f(
        "fmi2SetupExperiment", i, [vp, i, dbl, dbl, i, dbl])(None, 0, 0.0, 0.0, 0, 0.0)
    statuses["SetDebugLogging(NULL categories, n=2)"] = f(
        "fmi2SetDebugLogging", i, [vp, i, sz, vp])(c, 1, 2, None)
    statuses["GetRealStatus(NULL out)"] = f("fmi2GetRealStatus", i, [vp, i, vp])(c, 2, None)
    f("fmi2FreeInstance", None, [vp])(None)  # must simply return
    # a normal step still works on the instance afterwards? (not required:
    # errors may move it to the error state) -- just free it
    f("fmi2FreeInstance", None, [vp])(c)
    messages = [r.message for r in inst.log]
    json.dump({"statuses": statuses, "messages": messages}, sys.stdout)


if __name__ == "__main__":
    main()
