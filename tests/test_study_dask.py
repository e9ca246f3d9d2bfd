"""gearstudy on dask.distributed (LocalCluster, 2 worker processes): the same rows as a serial
loop, a failing point is a row with its error, an interrupted study resumes without rerunning
finished points. Short runs (a few ms simulated per point) keep this cheap."""

from __future__ import annotations

import math
import os

import numpy as np
import pytest

from gearstudy import load_study, point_key, read_results, study_from_dict, sweep
from gearstudy.runner import RUN_LOG_ENV, PointRunner, prepare_settings

SHORT_WINDOW = {"transient": "2 ms", "periods": 2, "samples_per_period": 8, "n_orders": 2}
VOLATILE = {"cpu_s", "worker"}  # the CPU a point took and where it ran


@pytest.fixture(scope="module")
def run_log(tmp_path_factory):
    path = tmp_path_factory.mktemp("runlog") / "runs.log"
    old = os.environ.get(RUN_LOG_ENV)
    os.environ[RUN_LOG_ENV] = str(path)  # inherited by the worker processes started below
    yield path
    if old is None:
        os.environ.pop(RUN_LOG_ENV, None)
    else:
        os.environ[RUN_LOG_ENV] = old


@pytest.fixture(scope="module")
def client(run_log):
    from distributed import Client

    from gearstudy.engine import local_cluster

    cluster = local_cluster(2)  # the cluster sweep starts by itself, with 2 workers
    c = Client(cluster)
    yield c
    c.close()
    cluster.close()


def _runs(run_log) -> list[str]:
    if not run_log.exists():
        return []
    return [line.split()[0] for line in run_log.read_text().splitlines()]


def _study(fmu_path, **designs):
    return study_from_dict({"fixed": {"T_load": 20.0}, **designs, "window": SHORT_WINDOW},
                           fmu=fmu_path)


def _same(a, b) -> bool:
    """Bitwise equality, NaN equal to NaN."""
    if isinstance(a, float) and isinstance(b, float):
        return a == b or (math.isnan(a) and math.isnan(b))
    return a == b


def test_eight_points_on_two_workers_equal_a_serial_loop_bit_for_bit(client, fmu_path, tmp_path):
    study = _study(fmu_path, grid={"omega1": ["2000 rpm", "3500 rpm"], "mu": [0.02, 0.08],
                                   "beta": ["10 deg", "20 deg"]})
    assert len(study.points) == 8
    summary = sweep(study, out=tmp_path / "r", client=client, progress=False)
    assert summary.ran == 8 and summary.failed == 0
    assert summary.chunk_size < 8  # spread over both workers
    rows = read_results(tmp_path / "r").to_pylist()
    assert len({r["worker"] for r in rows}) == 2, "both workers should have taken chunks"
    # the serial loop: a fresh instance per point, no Dask, no reuse
    settings = prepare_settings(study.settings(), study.catalog)
    for i, p in enumerate(study.points):
        runner = PointRunner(fmu_path)
        try:
            ref = runner.run(p, settings, index=i, key=point_key(p))
        finally:
            runner.close()
        got = rows[i]
        assert got["status"] == "OK" and ref["status"] == "OK", (got["message"], ref["message"])
        assert set(got) == set(ref)
        diff = [c for c in ref if c not in VOLATILE and not _same(got[c], ref[c])]
        assert not diff, f"point {i}: columns differ: {diff}"
        assert np.isfinite(got["efficiency"]) and 0.9 < got["efficiency"] < 1.0


def test_an_invalid_point_is_a_row_with_its_error_and_the_others_run(client, fmu_path, tmp_path):
    study = _study(fmu_path, list={"mu": [0.05, -1.0, 0.02, 0.1, 0.05], "z1": [27, 27, 3, 25, 27],
                                   "omega1": ["3000 rpm"] * 4 + [0.0]})
    summary = sweep(study, out=tmp_path / "r", client=client, progress=False)
    rows = read_results(tmp_path / "r").to_pylist()
    assert [r["point"] for r in rows] == [0, 1, 2, 3, 4]
    assert summary.failed == 3
    bad_mu, bad_z1 = rows[1], rows[2]
    assert bad_mu["status"] == "Error" and "mu" in bad_mu["message"], bad_mu["message"]
    assert bad_z1["status"] == "Error" and "z1" in bad_z1["message"], bad_z1["message"]
    assert math.isnan(bad_mu["efficiency"]) and math.isnan(bad_z1["TE.mean"])
    # a point the study tool itself cannot reduce: no speed, no mesh period
    assert rows[4]["status"] == "Error" and "omega1" in rows[4]["message"], rows[4]["message"]
    for r in (rows[0], rows[3]):
        assert r["status"] == "OK", r["message"]
        assert 0.9 < r["efficiency"] < 1.0
    # the failed points did not spoil the reused instances: point 3 (after the z1 = 3 error on
    # whichever worker) equals a fresh run
    settings = prepare_settings(study.settings(), study.catalog)
    runner = PointRunner(fmu_path)
    try:
        ref = runner.run(study.points[3], settings, index=3, key=point_key(study.points[3]))
    finally:
        runner.close()
    assert all(_same(rows[3][c], ref[c]) for c in ref if c not in VOLATILE)


def test_an_interrupted_study_resumes_and_skips_finished_points(client, fmu_path, tmp_path, run_log):
    study_file = tmp_path / "resume.toml"
    study_file.write_text(
        '[fixed]\nT_load = 20.0\n'
        '[grid]\nomega1 = ["1500 rpm", "2500 rpm", "3500 rpm"]\nmu = [0.03, 0.06]\n'
        '[window]\ntransient = "2 ms"\nperiods = 2\nsamples_per_period = 8\nn_orders = 2\n'
    )
    out = tmp_path / "r"
    if run_log.exists():
        run_log.unlink()
    # "interrupted": the first call stops after 2 of 6 points ...
    first = sweep(study_file, out=out, client=client, fmu=fmu_path, max_points=2, progress=False)
    assert first.ran == 2 and first.skipped == 0  # (skipped counted the cut points once)
    runs1 = _runs(run_log)
    assert len(runs1) == 2
    # ... and leaves a half-written part behind, as a killed writer would
    (out / "rows" / ".part-killed.parquet.tmp").write_bytes(b"PAR1 truncated")
    second = sweep(study_file, out=out, client=client, fmu=fmu_path, progress=False)
    assert (second.skipped, second.ran) == (2, 4)
    runs2 = _runs(run_log)[len(runs1):]
    assert len(runs2) == 4 and not set(runs2) & set(runs1), "finished points ran again"
    third = sweep(study_file, out=out, client=client, fmu=fmu_path, progress=False)
    assert third.ran == 0 and len(_runs(run_log)) == 6
    rows = read_results(out).to_pylist()
    study = load_study(study_file, fmu=fmu_path)
    assert [r["key"] for r in rows] == [point_key(p) for p in study.points]
    assert all(r["status"] == "OK" for r in rows)
    # a changed setting is refused instead of mixing rows
    study_file.write_text(study_file.read_text().replace("periods = 2", "periods = 3"))
    with pytest.raises(ValueError, match="other settings.*window"):
        sweep(study_file, out=out, client=client, fmu=fmu_path, progress=False)
