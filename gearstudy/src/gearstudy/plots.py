"""Pictures of a results directory (matplotlib, Agg):

- ``efficiency_map*.png``: contours of the efficiency over two varied inputs, one panel per
  value combination of the other varied variables (e.g. per mu);
- ``loss_te.png``: mean loss power and transmission-error peak-to-peak against one input, the
  other varied variables as curves;
- ``orders_<output>.png``: a Campbell-style picture, the mesh-order amplitudes against speed.

Axes are in each variable's display unit (from the results' schema metadata), except that
every plot shows the efficiency in % and lengths (TE, its orders) in um. Every figure names
the study and the values all its points share, and the damper's load (T_damp) when it was
recorded; failed points are marked with a red x.
"""

from __future__ import annotations

import itertools
import json
from pathlib import Path

import numpy as np

from .results import read_results

SPEED = "omega1"
PREFERRED_AXES = ("omega1", "T_load")
MAX_CURVES = 12


def _display(table, col):
    md = table.schema.metadata or {}
    disp = json.loads(md.get(b"display", b"{}")).get(col)
    units = json.loads(md.get(b"units", b"{}"))
    if disp:
        name, factor, offset = disp
        return name, (lambda x, f=factor, o=offset: np.asarray(x) * f + o)
    return units.get(col, ""), (lambda x: np.asarray(x))


#: the same unit for a quantity in every plot: efficiency in %, lengths (TE, gap, centre
#: displacements; their SI unit m) in um
_LENGTH_UM = ("um", 1e6)


def _plot_unit(table, col):
    """(unit, conversion) of a column in the plots: % for the efficiency, um for every
    length-valued output column (TE.p2p, TE.order1, ...), else the display unit."""
    if col == "efficiency":
        return "%", (lambda x: 100.0 * np.asarray(x))
    units = json.loads((table.schema.metadata or {}).get(b"units", b"{}"))
    md = table.schema.metadata or {}
    varied = json.loads(md.get(b"varied", b"[]"))
    if units.get(col) == "m" and col not in varied and "." in col:
        name, f = _LENGTH_UM
        return name, (lambda x, f=f: np.asarray(x) * f)
    return _display(table, col)


def _label(table, col):
    unit, _ = _plot_unit(table, col)
    return f"{col} [{unit}]" if unit and unit != "1" else col


def _case_line(table, results) -> str:
    """The case of a study for the figure titles: its name, the values every point shares
    (set by [fixed] or constant), and the damper's load when T_damp was recorded."""
    md = table.schema.metadata or {}
    name = (md.get(b"study", b"") or b"").decode()
    varied = set(json.loads(md.get(b"varied", b"[]")))
    settings = Path(results) / "settings.json"
    names = []
    if settings.is_file():
        names = json.loads(settings.read_text()).get("variables", [])
    shared = []
    for c in names:
        if c in varied or c not in table.column_names:
            continue
        vals = set(table.column(c).to_pylist())
        if len(vals) == 1:
            shared.append(_fmt(table, c, vals.pop()))
    line = f"study {name}" + (": " + ", ".join(shared) if shared else "")
    if "d_phi" not in names:
        line += "; d_phi at the FMU default"
    if "T_damp.mean" in table.column_names:
        td = np.asarray(table.column("T_damp.mean").to_pylist(), dtype=float)
        td = td[np.isfinite(td)]
        if td.size and td.max() > 0:
            line += (f"; load on gear 2 = T_load + damper T_damp ({td.min():.3g} .. {td.max():.3g} N m)")
    elif "d_phi" not in names or "T_damp" not in table.column_names:
        line += "; the damper d_phi omega2 loads gear 2 besides T_load"
    return line


def _wrap(text: str, width: int) -> str:
    import textwrap

    return "\n".join(textwrap.wrap(text, width=width, break_long_words=False))


def _varied(table) -> list[str]:
    md = table.schema.metadata or {}
    varied = json.loads(md.get(b"varied", b"[]"))
    return [c for c in varied if len(set(table.column(c).to_pylist())) > 1]


def _fmt(table, col, value):
    unit, conv = _display(table, col)
    v = float(conv(value))
    return f"{col} = {v:g}" + (f" {unit}" if unit and unit != "1" else "")


def plot_results(results, out_dir=None, x: str | None = None, y: str | None = None) -> list[Path]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    full = read_results(results)
    ok = np.array([s in ("OK", "Warning") for s in full.column("status").to_pylist()], dtype=bool)
    table = full.filter(ok)
    failed = full.filter(~ok)
    case = _case_line(full, results if Path(results).is_dir() else Path(results).parent)
    out_dir = Path(out_dir) if out_dir else (Path(results) if Path(results).is_dir() else Path(results).parent)
    out_dir.mkdir(parents=True, exist_ok=True)
    written: list[Path] = []
    if table.num_rows == 0:
        return written
    from .results import require_column

    for c, opt in ((x, "--x"), (y, "--y")):
        if c is not None:
            require_column(table, c, f"variable for {opt}")
    varied = _varied(table)
    axes = [c for c in PREFERRED_AXES if c in varied] + [c for c in varied if c not in PREFERRED_AXES]
    x = x or (axes[0] if axes else None)
    y = y or next((c for c in axes if c != x), None)
    numeric = [c for c in table.column_names if table.schema.field(c).type in (_pa().float64(), _pa().int64())]
    cols = {c: np.asarray(table.column(c).to_pylist(), dtype=float) for c in numeric}
    bad = {c: np.asarray(failed.column(c).to_pylist(), dtype=float) for c in numeric
           if c in (x, y) or c in varied}
    n_failed = failed.num_rows
    failed_note = f"; x: {n_failed} failed point(s)" if n_failed else ""

    # 1. efficiency map over (x, y), one panel per combination of the others
    if x and y and "efficiency" in cols:
        others = [c for c in varied if c not in (x, y)]
        combos = _combos(cols, others)
        n = len(combos)
        fig, axs = plt.subplots(1, n, figsize=(5.2 * n, 4.2), squeeze=False)
        _, cx = _display(table, x)
        _, cy = _display(table, y)
        for ax, combo in zip(axs[0], combos):
            sel = _select(cols, combo)
            X, Y, Z = cx(cols[x][sel]), cy(cols[y][sel]), cols["efficiency"][sel]
            good = np.isfinite(Z)
            if good.sum() >= 3 and len(set(X[good])) > 1 and len(set(Y[good])) > 1:
                cs = ax.tricontourf(X[good], Y[good], 100 * Z[good], levels=12, cmap="viridis")
                ax.tricontour(X[good], Y[good], 100 * Z[good], levels=12, colors="k", linewidths=0.4)
                fig.colorbar(cs, ax=ax, label="efficiency [%]", format="%.4f")
            ax.plot(X, Y, "k.", ms=3, clip_on=False)
            if n_failed:
                fsel = _select(bad, combo) if combo else np.ones(n_failed, dtype=bool)
                ax.plot(cx(bad[x][fsel]), cy(bad[y][fsel]), "rx", ms=7, mew=1.5, clip_on=False,
                        label="failed point")
                if fsel.any():
                    ax.legend(fontsize=7, loc="best")
            ax.set_xlabel(_label(table, x))
            ax.set_ylabel(_label(table, y) + (" (+ T_damp)" if y == "T_load" else ""))
            ax.set_title(", ".join(_fmt(table, c, v) for c, v in combo.items()) or "efficiency", fontsize=9)
        fig.suptitle(_wrap(f"Mesh efficiency [%]; {case}{failed_note}", 60 * n), fontsize=9)
        fig.tight_layout()
        written.append(_save(fig, out_dir / "efficiency_map.png"))
        plt.close(fig)

    # 2. loss and TE against x, the other varied variables as curves
    if x:
        figs = [c for c in ("P_loss.mean", "TE.p2p", "efficiency") if c in cols]
        others = [c for c in varied if c != x]
        combos = _combos(cols, others)[:MAX_CURVES]
        fig, axs = plt.subplots(1, len(figs), figsize=(5.2 * len(figs), 4.0), squeeze=False)
        _, cx = _display(table, x)
        for ax, f in zip(axs[0], figs):
            _, cf = _plot_unit(table, f)
            for combo in combos:
                sel = _select(cols, combo)
                order = np.argsort(cols[x][sel])
                ax.plot(cx(cols[x][sel][order]), cf(cols[f][sel][order]), "o-", ms=3,
                        label=", ".join(_fmt(table, c, v) for c, v in combo.items()))
            if n_failed:
                # failed points: a red x on the x axis at their position (no value)
                ax.plot(cx(bad[x]), np.zeros(n_failed), "rx", ms=7, mew=1.5, clip_on=False,
                        transform=ax.get_xaxis_transform(), label="failed point")
            ax.set_xlabel(_label(table, x))
            ax.set_ylabel(_label(table, f))
            ax.ticklabel_format(axis="y", useOffset=False)
            ax.set_title(f, fontsize=9)
            ax.grid(alpha=0.3)
        if len(combos) > 1 or n_failed:
            axs[0][0].legend(fontsize=7)
        fig.suptitle(_wrap(f"{case}{failed_note}", 60 * len(figs)), fontsize=9)
        fig.tight_layout()
        written.append(_save(fig, out_dir / "loss_te.png"))
        plt.close(fig)

    # 3. Campbell-style: order amplitudes against speed
    if SPEED in cols and len(set(cols[SPEED])) > 1:
        _, cs = _display(table, SPEED)
        others = [c for c in varied if c != SPEED]
        combo = _combos(cols, others)[0]
        sel = _select(cols, combo)
        for out in sorted({c.split(".order")[0] for c in cols if ".order" in c}):
            orders = sorted(int(c.split(".order")[1]) for c in cols if c.startswith(out + ".order"))
            fig, ax = plt.subplots(figsize=(6.4, 4.0))
            sp = cs(cols[SPEED][sel])
            _, ca = _plot_unit(table, f"{out}.order{orders[0]}")
            amp = np.array([ca(cols[f"{out}.order{k}"][sel]) for k in orders])
            top = np.nanmax(amp) if np.isfinite(amp).any() else 1.0
            for k, a in zip(orders, amp):
                ax.scatter(sp, np.full_like(sp, k), s=4 + 300 * np.nan_to_num(a) / (top or 1.0),
                           c=a, cmap="magma_r", vmin=0, vmax=top, edgecolors="k", linewidths=0.3)
            ax.set_yticks(orders)
            ax.set_xlabel(_label(table, SPEED))
            ax.set_ylabel("mesh order")
            title = f"{out}: mesh-order amplitudes"
            if combo:
                title += " (" + ", ".join(_fmt(table, c, v) for c, v in combo.items()) + ")"
            ax.set_title(_wrap(f"{title}; {case}{failed_note}", 90), fontsize=8)
            unit, _ = _plot_unit(table, f"{out}.order{orders[0]}")
            fig.colorbar(ax.collections[0], ax=ax, label=f"amplitude [{unit}]")
            fig.tight_layout()
            written.append(_save(fig, out_dir / f"orders_{out}.png"))
            plt.close(fig)
    return written


def _pa():
    import pyarrow as pa

    return pa


def _combos(cols, names) -> list[dict]:
    if not names:
        return [{}]
    values = [sorted(set(cols[n][np.isfinite(cols[n])])) for n in names]
    return [dict(zip(names, v)) for v in itertools.product(*values)
            if _select(cols, dict(zip(names, v))).any()]


def _select(cols, combo: dict) -> np.ndarray:
    n = len(next(iter(cols.values())))
    sel = np.ones(n, dtype=bool)
    for c, v in combo.items():
        sel &= cols[c] == v
    return sel


def _save(fig, path: Path) -> Path:
    fig.savefig(path, dpi=110)
    return path
