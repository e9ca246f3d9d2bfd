"""A study point whose start on the periodic orbit fails falls back to a start from rest and
cuts `[window] fallback_transient` (default 100 ms); its row says so (init, status Warning,
message) and carries figures instead of NaN.

Two ways to make the periodic start fail:
- forced: the instance's fmi2ExitInitializationMode fails, with the FMU's own wording of a
  failed shooting ("no periodic orbit: ..."), whenever the point asks for initialization =
  periodic. This does not depend on which cases the FMU's shooting can do.
- a real case: d_phi = 0 with T_load = 100 N m on the default pair, where the FMU's shooting
  reports a spurious unstable orbit at the time of writing (a fix is on its way; after it
  the point simply starts on the orbit, and the test accepts either).
"""

from __future__ import annotations

import math

import pytest
from fmpy.fmi1 import FMICallException

import gearstudy
from gearstudy import runner as runner_mod
from gearstudy.study import study_from_dict

STUDY = {
    "grid": {"omega1": ["3000 rpm"], "T_load": [10.0, 100.0]},
    "window": {"periods": 3, "samples_per_period": 16, "n_orders": 2, "fallback_transient": "100 ms"},
}


@pytest.fixture
def forced_failure(monkeypatch):
    """exitInitializationMode fails like a failed shooting when initialization = 3 was set."""
    original_set = runner_mod.PointRunner._set
    original_ready = runner_mod.PointRunner._ready

    def _set(self, values):
        self._wants_periodic = int(values.get(runner_mod.INITIALIZATION, 0)) == runner_mod.PERIODIC
        return original_set(self, values)

    def _ready(self):
        s = original_ready(self)
        if not getattr(s, "_forced", False):
            exit_init = s.exitInitializationMode

            def failing_exit():
                if getattr(self, "_wants_periodic", False):
                    self._logger(None, b"", 3, b"logStatusError",
                                 b"fmi2ExitInitializationMode: initialization: no periodic orbit: "
                                 b"forced by the test; use initialization = rest or static_equilibrium")
                    raise FMICallException("fmi2ExitInitializationMode", 3)
                return exit_init()

            s.exitInitializationMode = failing_exit
            s._forced = True
        return s

    monkeypatch.setattr(runner_mod.PointRunner, "_set", _set)
    monkeypatch.setattr(runner_mod.PointRunner, "_ready", _ready)


def _rows(fmu_path, tmp_path, data):
    study = study_from_dict(data, fmu=fmu_path)
    gearstudy.sweep(study, out=tmp_path / "r", serial=True, progress=False)
    return gearstudy.read_results(tmp_path / "r").to_pylist()


def test_forced_periodic_failure_falls_back_to_rest(fmu_path, tmp_path, forced_failure):
    rows = _rows(fmu_path, tmp_path, STUDY)
    assert len(rows) == 2
    for r in rows:
        assert r["init"] == "rest+cut (periodic start failed)", r
        assert r["status"] == "Warning", r
        assert "no periodic orbit" in r["message"] and "started from rest" in r["message"], r
        assert math.isclose(r["t_window"], 0.1), r
        assert 0.99 < r["efficiency"] < 1.0, r
        assert math.isfinite(r["TE.p2p"]) and r["TE.p2p"] > 0, r


def test_forced_failure_with_the_fallback_matches_a_start_from_rest(fmu_path, tmp_path, forced_failure):
    """The fallback row equals a point that asks for a start from rest with the same cut."""
    rows = _rows(fmu_path, tmp_path, STUDY)
    rest = dict(STUDY, fixed={"initialization": 1}, window=dict(STUDY["window"], transient="100 ms"))
    ref = _rows(fmu_path, tmp_path / "rest", rest)
    for a, b in zip(rows, ref):
        assert b["init"] == "rest+cut" and b["status"] == "OK"
        assert a["efficiency"] == b["efficiency"]
        assert a["T1.mean"] == b["T1.mean"]


def test_a_point_the_fmu_refuses_gets_no_fallback(fmu_path, tmp_path):
    """A refused parameter (z1 = 3) is an error row: starting from rest cannot help."""
    data = {"grid": {"z1": [3]}, "window": STUDY["window"]}
    (row,) = _rows(fmu_path, tmp_path, data)
    assert row["status"] == "Error" and "z1" in row["message"], row
    assert row["init"] is None


def test_damper_off_point_gives_figures(fmu_path, tmp_path):
    """d_phi = 0, T_load = 100 N m: started on the orbit, or (while the FMU's shooting
    refuses it) from rest through the fallback; figures either way."""
    data = {"grid": {"T_load": [100.0]}, "fixed": {"d_phi": 0.0}, "window": STUDY["window"]}
    (row,) = _rows(fmu_path, tmp_path, data)
    assert row["init"] in ("periodic", "rest+cut (periodic start failed)"), row
    assert row["status"] in ("OK", "Warning"), row
    assert 0.99 < row["efficiency"] < 1.0, row
    # the load is T_load alone: T1 = T_load z1/z2 / efficiency, within the inertia ripple
    assert math.isclose(row["T1.mean"], 100.0 * 27 / 41 / row["efficiency"], rel_tol=1e-3), row
