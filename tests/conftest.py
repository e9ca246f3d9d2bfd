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
