"""Session fixtures: build the .fmu files once (cargo run --release --bin package-fmu
writes GearedRotor.fmu, FMI 2.0, and GearedRotor-fmi3.fmu, FMI 3.0) and extract each
once; every test instantiates from the extracted copy.

The main FMPy tests run on both files: the modules in FMI3_MODULES are parametrised with
`fmi_version` ("fmi2" / "fmi3" in the test ids); `fmu_path` and `pkg` are the file of that
version (helpers/fmi3_compat.py gives the FMI 3.0 instance the FMI 2.0-shaped calls the
tests make). Tests of those modules that exercise what only FMI 2.0 has run on the 2.0
file only (FMI2_ONLY, with the reason). Every other module runs on the 2.0 file.

Environment:
  GEARED_ROTOR_FMU=path    use this .fmu instead of building one (FMI 2.0)
  GEARED_ROTOR_FMU3=path   the same for the FMI 3.0 .fmu
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


# Test modules that run on both .fmu files.
FMI3_MODULES = {
    "test_a_package",
    "test_b_physics",
    "test_g_input_step",
    "test_c_step_independence",
    "test_d_rollback",
    "test_e_instances",
    "test_h_events_discard",
    "test_initialization",
    "test_lift_off",
    "test_reference_run",
    "test_fmi3",
    "test_coast_flank",
}

# Tests of those modules that need an FMI 2.0 function (module::test -> reason).
FMI2_ONLY: dict[str, str] = {
    "test_a_package::test_archive_layout": "binaries/linux64 (3.0: test_fmi3::test_archive_layout)",
    "test_a_package::test_interface_names_types_causalities":
        "asserts fmiVersion 2.0 (3.0: test_fmi3::test_same_interface_as_fmi2)",
    "test_a_package::test_capabilities_declared":
        "FMI 2.0 capability flags (3.0: test_fmi3::test_capabilities_declared)",
}


def pytest_generate_tests(metafunc):
    if "fmi_version" not in metafunc.fixturenames:
        return
    module = metafunc.module.__name__.rsplit(".", 1)[-1]
    key = f"{module}::{metafunc.function.__name__}"
    both = module in FMI3_MODULES and key not in FMI2_ONLY
    versions = ["fmi2", "fmi3"] if both else ["fmi2"]
    metafunc.parametrize("fmi_version", versions, scope="session")


@pytest.fixture(scope="session")
def fmu2_path() -> Path:
    given = os.environ.get("GEARED_ROTOR_FMU")
    if given:
        p = Path(given)
        assert p.is_file(), f"GEARED_ROTOR_FMU={given} does not exist"
        return p
    return build_fmu(quiet=True)


@pytest.fixture(scope="session")
def fmu3_path(fmu2_path: Path) -> Path:
    given = os.environ.get("GEARED_ROTOR_FMU3")
    p = Path(given) if given else fmu2_path.with_name("GearedRotor-fmi3.fmu")
    assert p.is_file(), f"{p} does not exist (GEARED_ROTOR_FMU3, or package-fmu writes it)"
    return p


@pytest.fixture(scope="session")
def fmu_path(fmi_version: str, request) -> Path:
    name = "fmu3_path" if fmi_version == "fmi3" else "fmu2_path"
    return request.getfixturevalue(name)


@pytest.fixture(scope="session")
def pkg2(fmu2_path: Path) -> FmuPackage:
    return FmuPackage(fmu2_path)


@pytest.fixture(scope="session")
def pkg3(fmu3_path: Path) -> FmuPackage:
    return FmuPackage(fmu3_path)


@pytest.fixture(scope="session")
def pkg(fmi_version: str, request) -> FmuPackage:
    return request.getfixturevalue("pkg3" if fmi_version == "fmi3" else "pkg2")
