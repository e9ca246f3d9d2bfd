"""A column of a results directory as text tables over two varied variables (rows: the
second, columns: the first), one table per combination of the other varied variables;
values of the axes in their display units."""

from __future__ import annotations

import numpy as np

from .plots import PREFERRED_AXES, _combos, _display, _fmt, _label, _select, _varied
from .results import read_results, require_column
from .units import StudyError


def format_table(results, column: str = "efficiency", x: str | None = None,
                 y: str | None = None, fmt: str = "{:.6g}") -> str:
    table = read_results(results)
    varied = _varied(table)
    axes = [c for c in PREFERRED_AXES if c in varied] + [c for c in varied if c not in PREFERRED_AXES]
    require_column(table, column)
    for c, opt in ((x, "--x"), (y, "--y")):
        if c is not None:
            require_column(table, c, f"variable for {opt}")
    x = x or (axes[0] if axes else None)
    y = y or next((c for c in axes if c != x), None)
    if x is None:
        raise StudyError("nothing varies in these results: no axis for a table")
    cols = {c: np.asarray(table.column(c).to_pylist(), dtype=float)
            for c in set(varied) | {x, column} | ({y} if y else set())}
    others = [c for c in varied if c not in (x, y)]
    _, cx = _display(table, x)
    lines = []
    for combo in _combos(cols, others):
        sel = _select(cols, combo)
        xs = sorted(set(cols[x][sel]))
        ys = sorted(set(cols[y][sel])) if y else [None]
        head = ", ".join(_fmt(table, c, v) for c, v in combo.items())
        lines.append(f"{column}" + (f" ({head})" if head else "") + f"; columns: {_label(table, x)}"
                     + (f", rows: {_label(table, y)}" if y else ""))
        _, cy = _display(table, y) if y else (None, None)
        lines.append(f"{'':>12}" + "".join(f"{float(cx(v)):>12g}" for v in xs))
        for yv in ys:
            cells = []
            for xv in xs:
                m = sel & (cols[x] == xv) & ((cols[y] == yv) if y else True)
                vals = cols[column][m]
                cells.append(fmt.format(vals[0]) if len(vals) and np.isfinite(vals[0]) else "failed")
            lab = f"{float(cy(yv)):g}" if y else ""
            lines.append(f"{lab:>12}" + "".join(f"{c:>12}" for c in cells))
        lines.append("")
    return "\n".join(lines)
