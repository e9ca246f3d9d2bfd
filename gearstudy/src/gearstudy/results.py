"""The results directory of a study.

    OUT/study.toml      a copy of the study file (when it came from a file)
    OUT/settings.json   what a resumed study must match (FMU GUID, outputs, window, variables)
    OUT/rows/part-*.parquet   one file per finished chunk, one row per point

A part file is written to a hidden temporary name and renamed when complete, so an interrupted
study never leaves a half-written part behind (readers skip names starting with '.').
Column units are stored in the Parquet schema metadata (``units``: column -> unit).
"""

from __future__ import annotations

import json
import os
import shutil
import uuid
from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq

from .runner import result_columns
from .units import StudyError

#: how a changed entry of settings.json is named in the refusal of a rerun
SETTING_NAMES = {
    "points_sha256": "the points: values of [grid], [list], [lhs] or [fixed]",
    "fmu_sha256": "the .fmu (rebuilt)",
    "fmu_guid": "the FMU's model description",
}

_ARROW = {"float64": pa.float64(), "int64": pa.int64(), "string": pa.string(), "bool": pa.bool_()}


class ResultStore:
    def __init__(self, out: Path, study, overwrite: bool = False):
        self.out = Path(out)
        self.rows_dir = self.out / "rows"
        if overwrite and self.rows_dir.is_dir():
            shutil.rmtree(self.rows_dir)
        self.rows_dir.mkdir(parents=True, exist_ok=True)
        settings = study.settings()
        meta = self.out / "settings.json"
        if meta.is_file() and any(self.rows_dir.glob("part-*.parquet")):
            old = json.loads(meta.read_text())
            if old != settings:
                changed = sorted(k for k in set(settings) | set(old) if old.get(k) != settings.get(k))
                what = [SETTING_NAMES.get(k, k) for k in changed]
                raise StudyError(
                    f"{self.out} holds results made with other settings ({', '.join(what)} "
                    f"changed); use another output directory (--out), or --overwrite (overwrite=True) "
                    f"to delete them and start over"
                )
        meta.write_text(json.dumps(settings, indent=1, sort_keys=True))
        if study.path is not None:
            shutil.copyfile(study.path, self.out / "study.toml")
        cols = result_columns(settings, study.catalog)
        units, display = {}, {}
        for c, _ in cols:
            base = c if c in study.catalog else c.rsplit(".", 1)[0]
            if base in study.catalog:
                v = study.catalog.variables[base]
                units[c] = v.unit or "1"
                du = next((d for d in v.display_units if d.name == v.display_unit), None)
                if du is not None:
                    display[c] = [du.name, du.factor, du.offset]
        units.update(cpu_s="s", t_window="s", mesh_period="s", efficiency="1")
        self.schema = pa.schema(
            [pa.field(c, _ARROW[t]) for c, t in cols],
            metadata={
                "units": json.dumps(units),
                "display": json.dumps(display),
                "varied": json.dumps(study.varied),
                "study": study.name,
            },
        )
        self.session = uuid.uuid4().hex[:8]
        self.written = 0

    def done_keys(self) -> set[str]:
        if not any(self.rows_dir.glob("part-*.parquet")):
            return set()
        t = pq.read_table(self.rows_dir, columns=["key"])
        return set(t.column("key").to_pylist())

    def write(self, rows: list[dict]) -> Path:
        table = pa.Table.from_pylist(rows, schema=self.schema)
        name = f"part-{self.session}-{self.written:07d}-{uuid.uuid4().hex[:6]}.parquet"
        tmp = self.rows_dir / f".{name}.tmp"
        pq.write_table(table, tmp)
        os.replace(tmp, self.rows_dir / name)
        self.written += len(rows)
        return self.rows_dir / name


def read_results(out) -> pa.Table:
    """All rows of a results directory (or of one Parquet file), sorted by point.

    Raises StudyError when there is nothing to read (no such directory, no rows yet)."""
    p = Path(out)
    if not p.exists():
        raise StudyError(f"results {p} do not exist; give the directory `gearstudy sweep` wrote "
                         "(its --out, default out/studies/<study name>)")
    src = p / "rows" if (p / "rows").is_dir() else p
    if src.is_dir() and not any(src.glob("part-*.parquet")):
        raise StudyError(f"{p} holds no results (no rows/part-*.parquet); run `gearstudy sweep` first")
    try:
        t = pq.read_table(src)
    except (pa.ArrowInvalid, OSError) as e:
        raise StudyError(f"{p}: not a results directory or Parquet file of gearstudy ({e})") from None
    if "point" not in t.column_names:
        raise StudyError(f"{p}: not written by gearstudy (no column 'point')")
    return t.sort_by("point")


def require_column(table: pa.Table, name: str, what: str = "column") -> None:
    """StudyError naming the column and the ones that come close, if `name` is not a numeric
    column of the table."""
    if name in table.column_names:
        kind = table.schema.field(name).type
        if pa.types.is_floating(kind) or pa.types.is_integer(kind):
            return
        numeric = [c for c in table.column_names
                   if pa.types.is_floating(table.schema.field(c).type)]
        raise StudyError(f"{what} '{name}' holds text, not numbers; give one of: {', '.join(numeric)}")
    import difflib

    close = difflib.get_close_matches(name, table.column_names, n=4, cutoff=0.5)
    hint = f"; did you mean {', '.join(close)}?" if close else ""
    numeric = [c for c in table.column_names if pa.types.is_floating(table.schema.field(c).type)]
    raise StudyError(f"no {what} '{name}' in these results{hint} (columns: {', '.join(numeric)})")


def column_units(table: pa.Table) -> dict:
    md = table.schema.metadata or {}
    return json.loads(md.get(b"units", b"{}"))
