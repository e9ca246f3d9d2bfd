"""Session fixtures: build the .fmu once (cargo run --release --bin package-fmu)
and extract it once; every test instantiates from the extracted copy.

Environment:
  GEARED_ROTOR_FMU=path   use this .fmu instead of building one
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))

from helpers.fmu_harness import FmuPackage, build_fmu  # noqa: E402

from ctypes import byref  # noqa: E402

import fmpy  # noqa: E402
import fmpy.simulation  # noqa: E402
from fmpy.fmi1 import printLogMessage  # noqa: E402
from fmpy.fmi2 import fmi2CallbackFunctions, fmi2CallbackLoggerTYPE  # noqa: E402

# FMPy (0.3.x) routes the log messages of simulate_fmu(logger=...) and of FMU2Slave's default
# callbacks through one native proxy with a single global target: the logger registered last.
# simulate_fmu(logger=f) registers f's callback object, which lives only as long as that
# call; an FMU that logs afterwards through the default callbacks (simulate_fmu without a
# logger, FMU2Slave.instantiate() without callbacks, e.g. examples/drivetrain.py) then calls
# freed memory and the process dies (segmentation fault). Since fmi2ExitInitializationMode
# logs warnings (implausible inertias, law 3 outside its range), the tests re-register a
# default printer that lives for the whole session after every simulate_fmu call and after
# every test. (Applied at import, before the test modules import simulate_fmu.)
_DEFAULT_LOGGER = fmi2CallbackLoggerTYPE(printLogMessage)


def restore_default_fmpy_logger() -> None:
    try:
        from fmpy.logging import addLoggerProxy
    except Exception:  # no native proxy on this platform: nothing to restore
        return
    cb = fmi2CallbackFunctions()
    cb.logger = _DEFAULT_LOGGER
    addLoggerProxy(byref(cb))


_simulate_fmu = fmpy.simulate_fmu


def _simulate_fmu_then_restore(*args, **kwargs):
    try:
        return _simulate_fmu(*args, **kwargs)
    finally:
        if kwargs.get("logger") is not None:
            restore_default_fmpy_logger()


fmpy.simulate_fmu = _simulate_fmu_then_restore
fmpy.simulation.simulate_fmu = _simulate_fmu_then_restore


@pytest.fixture(autouse=True)
def _default_fmpy_logger():
    yield
    restore_default_fmpy_logger()


@pytest.fixture(scope="session")
def fmu_path() -> Path:
    given = os.environ.get("GEARED_ROTOR_FMU")
    if given:
        p = Path(given)
        assert p.is_file(), f"GEARED_ROTOR_FMU={given} does not exist"
        return p
    return build_fmu(quiet=True)


@pytest.fixture(scope="session")
def pkg(fmu_path: Path) -> FmuPackage:
    return FmuPackage(fmu_path)
