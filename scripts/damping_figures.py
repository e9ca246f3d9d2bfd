"""Figures and tables of docs/damping.md from the two damping studies.

    source scripts/env.sh
    $VPY scripts/damping_figures.py   # runs the studies (again, when the .fmu or the grid changed)

Runs (or resumes; reruns when the results are of another .fmu) examples/studies/damping_mu.toml and damping_laws.toml with gearstudy into
out/damping_mu and out/damping_laws, then writes docs/figures/damping_mu.png (damping ratio
and the part the friction adds, per mode, against mu, one line per speed),
docs/figures/damping_laws.png (the same per friction law) and prints the Markdown tables of
docs/damping.md. Mode columns: mode{i}.name/.f/.zeta/.dzeta (gearstudy/damping.py).
"""

from __future__ import annotations

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import gearstudy  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
FIG = ROOT / "docs" / "figures"
RPM = 30.0 / 3.141592653589793
N_MODES = 6
LAW_NAMES = {1: "1 Coulomb", 2: "2 regularised", 3: "3 ISO mean", 4: "4 local EHL", 5: "5 Benedict-Kelley"}


def rows_of(name: str) -> list[dict]:
    out = ROOT / "out" / name
    study = str(ROOT / "examples" / "studies" / f"{name}.toml")
    try:
        gearstudy.sweep(study, out=str(out), serial=True, progress=False)
    except gearstudy.StudyError as e:
        # results of another build (or grid) in the script's own folder: made again
        print(f"{name}: {e}; running it again", file=sys.stderr)
        gearstudy.sweep(study, out=str(out), serial=True, progress=False, overwrite=True)
    rows = gearstudy.read_results(str(out)).to_pylist()
    bad = [r for r in rows if r["status"] not in ("OK", "Warning") or r["mode1.zeta"] is None]
    if bad:
        sys.exit(f"{name}: {len(bad)} failed points, e.g. {bad[0]['message']}")
    return rows


def mode_names(rows: list[dict]) -> list[str]:
    """The name of each mode at the first point (the names follow the friction-free modes)."""
    return [rows[0][f"mode{i}.name"] for i in range(1, N_MODES + 1)]


def figure_mu(rows: list[dict]) -> Path:
    speeds = sorted({r["omega1"] for r in rows})
    names = mode_names(rows)
    fig, axes = plt.subplots(2, N_MODES, figsize=(18, 6.5), sharex=True)
    for i in range(1, N_MODES + 1):
        for w in speeds:
            pts = sorted((r["mu"], r[f"mode{i}.zeta"], r[f"mode{i}.dzeta"]) for r in rows
                         if r["omega1"] == w)
            mu = [p[0] for p in pts]
            axes[0, i - 1].plot(mu, [100 * p[1] for p in pts], "o-", ms=3, label=f"{w * RPM:.0f} rpm")
            axes[1, i - 1].plot(mu, [100 * p[2] for p in pts], "o-", ms=3, label=f"{w * RPM:.0f} rpm")
        f0 = next(r[f"mode{i}.f"] for r in rows if r["mu"] == 0.0)
        axes[0, i - 1].set_title(f"mode {i}: {names[i - 1]}\n{f0:.0f} Hz", fontsize=9)
        axes[1, i - 1].set_xlabel("mu (law 1)")
        axes[0, i - 1].grid(alpha=0.3)
        axes[1, i - 1].grid(alpha=0.3)
    axes[0, 0].set_ylabel("damping ratio zeta [%]")
    axes[1, 0].set_ylabel("added by friction, zeta - zeta(mu=0) [%]")
    axes[0, 0].legend(fontsize=8)
    fig.suptitle("Modal damping of the periodic orbit against mu - default pair, damper load "
                 "(d_phi = 0.5 N m s/rad, T_load = 0)")
    fig.tight_layout()
    p = FIG / "damping_mu.png"
    fig.savefig(p, dpi=90)
    return p


def figure_laws(rows: list[dict]) -> Path:
    speeds = sorted({r["omega1"] for r in rows})
    laws = sorted({r["friction_law"] for r in rows})
    names = mode_names(rows)
    fig, axes = plt.subplots(1, N_MODES, figsize=(18, 3.8), sharey=True)
    width = 0.8 / len(laws)
    for i in range(1, N_MODES + 1):
        ax = axes[i - 1]
        for j, law in enumerate(laws):
            vals = [next(r[f"mode{i}.dzeta"] for r in rows if r["omega1"] == w and r["friction_law"] == law)
                    for w in speeds]
            ax.bar([k + (j - (len(laws) - 1) / 2) * width for k in range(len(speeds))],
                   [100 * v for v in vals], width, label=LAW_NAMES.get(law, str(law)))
        ax.set_xticks(range(len(speeds)), [f"{w * RPM:.0f}" for w in speeds])
        ax.set_xlabel("rpm")
        ax.set_title(f"mode {i}: {names[i - 1]}", fontsize=9)
        ax.grid(alpha=0.3, axis="y")
    axes[0].set_ylabel("added by friction [% of critical]")
    axes[0].legend(fontsize=8, title="law")
    fig.suptitle("Damping ratio added by tooth friction, friction laws 1-4 at the default oil "
                 "(laws 1, 2: mu = 0.05)")
    fig.tight_layout()
    p = FIG / "damping_laws.png"
    fig.savefig(p, dpi=90)
    return p


def pct(v: float) -> str:
    """A damping ratio in % with three decimals; a zero that rounds from below prints +0.000."""
    return f"{100 * v:+.3f}" if abs(v) >= 5e-6 else "+0.000"


def tables(mu_rows: list[dict], law_rows: list[dict]) -> str:
    out = []
    names = mode_names(mu_rows)
    for w in sorted({r["omega1"] for r in mu_rows}):
        out.append(f"\n{w * RPM:.0f} rpm, law 1: zeta [%] (added by friction) per mode\n")
        out.append("| mu | " + " | ".join(f"{i} {names[i - 1]}" for i in range(1, N_MODES + 1)) + " |")
        out.append("|---" * (N_MODES + 1) + "|")
        for r in sorted((r for r in mu_rows if r["omega1"] == w), key=lambda r: r["mu"]):
            cells = [f"{100 * r[f'mode{i}.zeta']:.3f} ({pct(r[f'mode{i}.dzeta'])})"
                     for i in range(1, N_MODES + 1)]
            out.append(f"| {r['mu']:.2f} | " + " | ".join(cells) + " |")
        fr = [r for r in mu_rows if r["omega1"] == w and r["mu"] == 0.0][0]
        out.append("| f(μ=0) [Hz] | " + " | ".join(f"{fr[f'mode{i}.f']:.1f}" for i in range(1, N_MODES + 1)) + " |")
    out.append("\nFriction laws at the default oil: zeta [%] (added by friction) per mode\n")
    out.append("| rpm | law | mean coefficient | " + " | ".join(f"mode {i}" for i in range(1, N_MODES + 1)) + " |")
    out.append("|---" * (N_MODES + 3) + "|")
    for r in sorted(law_rows, key=lambda r: (r["omega1"], r["friction_law"])):
        mu = r.get("mu_eff.mean")
        cells = [f"{100 * r[f'mode{i}.zeta']:.3f} ({pct(r[f'mode{i}.dzeta'])})" for i in range(1, N_MODES + 1)]
        out.append(f"| {r['omega1'] * RPM:.0f} | {LAW_NAMES.get(r['friction_law'], r['friction_law'])} | "
                   f"{mu:.4f} | " + " | ".join(cells) + " |")
    return "\n".join(out)


def main() -> None:
    FIG.mkdir(parents=True, exist_ok=True)
    mu_rows, law_rows = rows_of("damping_mu"), rows_of("damping_laws")
    for p in (figure_mu(mu_rows), figure_laws(law_rows)):
        print(f"wrote {p.relative_to(ROOT)}")
    print(tables(mu_rows, law_rows))


if __name__ == "__main__":
    main()
