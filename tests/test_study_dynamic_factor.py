"""The dynamic factor study (examples/studies/dynamic_factor.toml, docs/dynamic_factor.md) at a
reduced size: 3000-11000 rpm in steps of 500 rpm, swept up and down with each point started
from its neighbour's periodic orbit (gearstudy [continuation], the crate's `periodic --sweep`).

Checked against physics, not against the study's own numbers:
- the mesh natural frequency the study reports is (3.19) of docs/model.md, recomputed here from
  ISO 6336-1 (method B, written out in test_mesh_stiffness.py) and the involute geometry
  (helpers/gear_theory.py);
- the resonance peak lies within 0.85..1.15 of the speed where the mesh frequency z1 n / 60
  meets it. The band: the bearings (2e8 N/m, of the order of the mesh stiffness 3.6e8 N/m)
  raise the actual mesh mode above the free-centre closed form (the Floquet mesh mode of this
  pair is ~7 % higher), and the softening of the contact loss moves the peak down;
- far from resonance, where both sweeps find a stable periodic orbit with the flanks in
  contact all the time, the model is linear time-periodic with every Floquet multiplier inside
  the unit circle, so its periodic orbit is unique: the two sweeps must give the same max Fn;
- the resonance softens (free flight): the sweep down stays on the large orbit (flanks apart
  for over 30 % of the period) to a lower speed than the one where the sweep up reaches it,
  and the sweep up jumps (a step of more than the static force between neighbouring speeds).
"""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import pytest

from helpers.gear_theory import GearData, geometry
from test_mesh_stiffness import iso_6336_c_gamma

from gearstudy import study_from_dict, sweep
from gearstudy import continuation

ROOT = Path(__file__).resolve().parent.parent
STUDY = ROOT / "examples" / "studies" / "dynamic_factor.toml"
PROGRAM = ROOT / "target" / "release" / "periodic"

pytestmark = pytest.mark.skipif(not PROGRAM.is_file(), reason="cargo build --release --bin periodic")


def closed_form_resonance_rpm() -> tuple[float, float]:
    """(f_m in Hz, n1 in rpm where z1 n1 / 60 = f_m) of the study's pair (default pair of
    model.md §10 made spur), from (3.18)-(3.19) with the masses of §10."""
    g = GearData(beta=0.0)
    geo = geometry(g)
    c_gamma = iso_6336_c_gamma(g.z1, g.z2, g.alpha_n, g.beta, g.x1, g.x2, 1.25, geo.eps_alpha)
    m1, m2, j2 = 2.0, 4.0, 5e-3
    inv_m_eq = 1.0 / m1 + 1.0 / m2 + (geo.r_b2 * math.cos(geo.beta_b)) ** 2 / j2
    f_m = math.sqrt(c_gamma * g.b * inv_m_eq) / (2.0 * math.pi)
    return f_m, 60.0 * f_m / g.z1


@pytest.fixture(scope="module")
def result(fmu2_path, tmp_path_factory):
    with open(STUDY, "rb") as f:
        data = tomllib.load(f)
    data["continuation"]["values"] = {"start": "3000 rpm", "stop": "11000 rpm", "num": 17}
    study = study_from_dict(data, base=STUDY.parent, fmu=fmu2_path)
    out = tmp_path_factory.mktemp("dynamic_factor")
    summary = sweep(study, out=out, serial=True, progress=False)
    print(summary)
    return continuation.read(out)


BACKLASH = "backlash 0.1 mm"
NO_BACKLASH = "no backlash (j_bn = 0)"


def _curves(rows, series=BACKLASH):
    up = {round(r["rpm"]): r for r in rows if r["direction"] == "up" and r["series"] == series}
    down = {round(r["rpm"]): r for r in rows if r["direction"] == "down" and r["series"] == series}
    return up, down


def test_reported_mesh_frequency_is_the_closed_form(result):
    _, meta = result
    f_m, n_res = closed_form_resonance_rpm()
    print(f"f_m = {f_m:.3f} Hz, resonance at {n_res:.1f} rpm; study: {meta['closed_form_hz']:.3f} Hz")
    assert meta["closed_form_hz"] == pytest.approx(f_m, rel=1e-9)
    assert meta["resonance_rpm"] == pytest.approx(n_res, rel=1e-9)


def test_resonance_peak_lies_near_the_closed_form_speed(result):
    rows, _ = result
    _, n_res = closed_form_resonance_rpm()
    peak = max((r for r in rows if r["series"] == BACKLASH), key=lambda r: r["dynamic_factor"])
    print(f"peak {peak['dynamic_factor']:.3f} at {peak['rpm']:.0f} rpm ({peak['direction']}), "
          f"{peak['rpm'] / n_res:.3f} of the closed-form {n_res:.0f} rpm")
    assert 0.85 * n_res <= peak["rpm"] <= 1.15 * n_res
    assert peak["dynamic_factor"] > 3.0


def test_sweeps_coincide_where_the_flanks_stay_in_contact(result):
    rows, _ = result
    up, down = _curves(rows)
    assert sorted(up) == sorted(down)
    linear = [n for n in up if up[n]["periodic"] and down[n]["periodic"]
              and up[n]["free_flight"] == 0.0 and down[n]["free_flight"] == 0.0]
    _, n_res = closed_form_resonance_rpm()
    print("in contact throughout (both sweeps):", sorted(linear))
    assert sum(n < 0.8 * n_res for n in linear) >= 3 and sum(n > 1.2 * n_res for n in linear) >= 3
    for n in linear:
        assert up[n]["dynamic_factor"] == pytest.approx(down[n]["dynamic_factor"], rel=1e-5), n


def test_the_resonance_softens_with_a_jump_and_hysteresis(result):
    rows, _ = result
    up, down = _curves(rows)
    _, n_res = closed_form_resonance_rpm()
    speeds = sorted(up)
    near = [n for n in speeds if 0.7 * n_res <= n <= 1.3 * n_res]

    def onset(curve):
        """The lowest speed near resonance where the flanks separate for over 30 % of the
        period (the large orbit)."""
        return min((n for n in near if curve[n]["free_flight"] > 0.3), default=math.inf)

    jumps = [up[b]["dynamic_factor"] - up[a]["dynamic_factor"] for a, b in zip(speeds, speeds[1:])]
    gap = max(abs(up[n]["dynamic_factor"] - down[n]["dynamic_factor"]) for n in speeds)
    for n in near:
        print(f"{n} rpm: up {up[n]['dynamic_factor']:.3f} (free flight {up[n]['free_flight']:.2f}), "
              f"down {down[n]['dynamic_factor']:.3f} ({down[n]['free_flight']:.2f})")
    print(f"large orbit from {onset(up)} rpm up, {onset(down)} rpm down; largest step of the sweep "
          f"up {max(jumps):.2f}; largest up/down difference {gap:.2f} (in units of F_static)")
    # Softening: coming down, the sweep stays on the large orbit below the speed where the
    # sweep up reaches it.
    assert onset(down) < onset(up) < math.inf
    assert max(jumps) > 1.0
    assert gap > 1.0


def test_backlash_matters_only_where_the_flanks_part(result):
    """Where the drive flanks stay in contact all the time (no free flight in either series)
    the coast flanks never touch, so the backlash cannot matter: both series give the same
    orbit. Near the resonance the drive flanks part; without backlash the coast flanks take
    over at once and the response differs (docs/dynamic_factor.md)."""
    rows, _ = result
    differ = []
    for d in ("up", "down"):
        a = {round(r["rpm"]): r for r in rows if r["series"] == BACKLASH and r["direction"] == d}
        b = {round(r["rpm"]): r for r in rows if r["series"] == NO_BACKLASH and r["direction"] == d}
        assert sorted(a) == sorted(b)
        for n in a:
            x, y = a[n], b[n]
            if x["periodic"] and y["periodic"] and x["free_flight"] == 0.0 and y["free_flight"] == 0.0:
                assert x["dynamic_factor"] == pytest.approx(y["dynamic_factor"], rel=1e-6), (d, n)
            elif abs(x["dynamic_factor"] - y["dynamic_factor"]) > 0.1:
                differ.append((d, n))
    print("series differ at", differ)
    assert differ
