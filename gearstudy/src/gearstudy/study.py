"""A study file (TOML) and the points it defines. The format is documented in docs/studies.md.

Designs: ``[grid]`` (full factorial over its variables), ``[list]`` (equal-length lists, one
point per position) and ``[lhs]`` (a Latin hypercube of ``n`` points over ranges). When a file
has more than one, the points are all combinations of their points (e.g. a grid over mu times a
Latin hypercube over profile shifts). ``[fixed]`` values apply to every point.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import continuation as continuation_mod
from . import damping
from .units import Catalog, StudyError, parse_duration

REPO_FMU = Path("target") / "fmu" / "GearedRotor.fmu"

#: reductions computed for every output named in [outputs] names
DEFAULT_OUTPUTS = ("T1", "Fn", "TE", "P_in", "P_loss", "omega2")
#: the damper's load and power, added to the default outputs when the FMU has them
LOAD_OUTPUTS = ("T_damp", "P_damp_phi")
#: outputs whose mesh-order amplitudes are computed
DEFAULT_ORDERS = ("TE", "Fn", "T1")


@dataclass(frozen=True)
class Window:
    """Where and how each point is sampled (see runner.py)."""

    transient: float = 0.1  # the documented transient cut, when the FMU starts from rest
    transient_unit: str = "s"  # "s" or "periods"
    periodic_settle: float = 0.0  # the cut when the FMU starts on its periodic solution
    periodic_settle_unit: str = "periods"
    fallback_transient: float = 0.1  # the cut of a point whose periodic start failed (from rest)
    fallback_transient_unit: str = "s"
    periods: int = 10  # whole mesh periods in the window
    samples_per_period: int = 32
    n_orders: int = 3

    def as_dict(self) -> dict:
        return dict(self.__dict__)


@dataclass
class Study:
    name: str
    path: Path | None
    fmu: Path
    catalog: Catalog
    points: list[dict]  # one dict name -> FMU value per point
    varied: list[str]  # variables that change between points, in file order
    fixed: dict
    outputs: tuple[str, ...]
    orders: tuple[str, ...]
    window: Window
    chunk_size: int = 0  # 0 = automatic (engine.chunk_size)
    tolerance: float | None = None  # fmi2SetupExperiment tolerance; None = the FMU's rtol
    extra: dict = field(default_factory=dict)
    fmu_sha256: str = ""  # the .fmu's bytes: a rebuilt binary is another model
    damping_modes: int = 0  # [damping] modes: modal damping columns per point (damping.py)
    damping_program: str = ""  # the `periodic` program that computes them
    continuation: object = None  # [continuation]: series swept from a neighbour's orbit

    @property
    def variables(self) -> list[str]:
        """Every variable a point sets: the varied ones, then the fixed ones."""
        return self.varied + [n for n in self.fixed if n not in self.varied]

    def settings(self) -> dict:
        """What, besides a point's values, determines its row; a resumed study must match."""
        return {
            "fmu_guid": self.catalog.guid,
            "fmu_sha256": self.fmu_sha256,
            "outputs": list(self.outputs),
            "orders": list(self.orders),
            "window": self.window.as_dict(),
            "tolerance": self.tolerance,
            "variables": self.variables,
            # the points themselves: a grid whose values changed is another study (a rerun
            # into the same directory would mix both grids)
            "points_sha256": _digest(sorted(point_key(p) for p in self.points)),
        } | ({"damping": {"modes": self.damping_modes, "program": self.damping_program}}
             if self.damping_modes else {})

    def settings_fingerprint(self) -> str:
        return _digest(self.settings())


def point_key(point: dict) -> str:
    """A stable identity of a point: its values, exactly (repr of floats round-trips)."""
    return _digest({k: repr(point[k]) for k in sorted(point)})[:20]


def _digest(obj) -> str:
    return hashlib.sha256(json.dumps(obj, sort_keys=True).encode()).hexdigest()


def load_study(path, fmu: Path | str | None = None, catalog: Catalog | None = None) -> Study:
    path = Path(path)
    if not path.is_file():
        what = "is a directory, not a study file" if path.is_dir() else "does not exist"
        raise StudyError(f"study file {path} {what}; give the path of a TOML study file "
                         "(e.g. examples/studies/efficiency_map.toml; format: docs/studies.md)")
    try:
        with open(path, "rb") as f:
            data = tomllib.load(f)
    except tomllib.TOMLDecodeError as e:
        raise StudyError(f"{path}: not valid TOML: {e}") from None
    except (OSError, UnicodeDecodeError) as e:
        raise StudyError(f"study file {path} cannot be read: {e}") from None
    try:
        return study_from_dict(data, base=path.parent, path=path, fmu=fmu, catalog=catalog)
    except StudyError:
        raise
    except (ValueError, TypeError, KeyError, AttributeError) as e:
        # an entry of the wrong kind (a word where a number belongs, a table where a value
        # belongs): the file's problem, said with the file's name
        raise StudyError(f"{path}: an entry has the wrong kind of value ({type(e).__name__}: {e}); "
                         "see docs/studies.md for the format") from None


def study_from_dict(
    data: dict,
    base: Path | None = None,
    path: Path | None = None,
    fmu: Path | str | None = None,
    catalog: Catalog | None = None,
) -> Study:
    known = {"study", "fixed", "grid", "list", "lhs", "outputs", "window", "run", "damping",
             "continuation"}
    unknown = set(data) - known
    if unknown:
        raise StudyError(f"unknown table(s) {sorted(unknown)}; allowed: {sorted(known)}")
    allowed = {
        "study": {"name", "fmu", "description"},
        "outputs": {"names", "orders"},
        "window": {"transient", "periodic_settle", "fallback_transient", "periods", "samples_per_period",
                   "n_orders"},
        "run": {"chunk_size", "tolerance"},
        "damping": {"modes", "program"},
    }
    for table, keys in allowed.items():
        bad = set(data.get(table, {})) - keys
        if bad:
            raise StudyError(f"[{table}] unknown key(s) {sorted(bad)}; allowed: {sorted(keys)}")
    meta = data.get("study", {})
    fmu_path = _fmu_path(fmu, meta.get("fmu"), base)
    cat = catalog or Catalog.from_fmu(fmu_path)

    fixed = {
        n: cat.to_fmu_value(n, v, "[fixed] ") for n, v in data.get("fixed", {}).items()
    }
    designs: list[tuple[list[str], list[tuple]]] = []
    if "grid" in data:
        designs.append(_grid(data["grid"], cat))
    if "list" in data:
        designs.append(_list(data["list"], cat))
    if "lhs" in data:
        designs.append(_lhs(data["lhs"], cat))
    varied: list[str] = []
    for names, _ in designs:
        for n in names:
            if n in varied:
                raise StudyError(f"'{n}' is varied in two designs; vary it in one only")
            varied.append(n)
    for n in varied:
        fixed.pop(n, None)  # a varied value overrides [fixed]
    points = []
    for combo in itertools.product(*[rows for _, rows in designs]):
        p = {}
        for (names, _), row in zip(designs, combo):
            p.update(zip(names, row))
        p.update(fixed)
        points.append(p)
    if not designs:
        points = [dict(fixed)]

    out = data.get("outputs", {})
    outputs = tuple(out.get("names", DEFAULT_OUTPUTS + tuple(n for n in LOAD_OUTPUTS if n in cat)))
    orders = tuple(out.get("orders", DEFAULT_ORDERS))
    for n in outputs + orders:
        v = cat.get(n, "[outputs] ")
        if v.causality not in ("output", "calculatedParameter", "parameter", "input", "local"):
            raise StudyError(f"[outputs] '{n}' has causality {v.causality}; it cannot be read")
    for n in orders:
        if cat.variables[n].causality != "output":
            raise StudyError(f"[outputs] orders: '{n}' is not an output of the FMU")

    w = data.get("window", {})
    tr, tr_u = parse_duration(w.get("transient", "100 ms"), cat, "[window] transient")
    ps, ps_u = parse_duration(w.get("periodic_settle", "0 periods"), cat, "[window] periodic_settle")
    fb, fb_u = parse_duration(w.get("fallback_transient", "100 ms"), cat, "[window] fallback_transient")
    window = Window(
        fallback_transient=fb,
        fallback_transient_unit=fb_u,
        transient=tr,
        transient_unit=tr_u,
        periodic_settle=ps,
        periodic_settle_unit=ps_u,
        periods=int(w.get("periods", 10)),
        samples_per_period=int(w.get("samples_per_period", 32)),
        n_orders=int(w.get("n_orders", 3)),
    )
    if window.periods < 1:
        raise StudyError("[window] periods must be >= 1 (whole mesh periods in the window)")
    if window.samples_per_period < 2 * window.n_orders + 1:
        raise StudyError(
            f"[window] samples_per_period = {window.samples_per_period} cannot resolve "
            f"n_orders = {window.n_orders}; use at least {2 * window.n_orders + 1}"
        )
    damping_modes, damping_program = 0, ""
    if "damping" in data:
        dmp = data["damping"]
        damping_modes = int(dmp.get("modes", 6))
        if damping_modes < 1:
            raise StudyError("[damping] modes must be >= 1 (the number of mode columns)")
        prog = damping.find_program(dmp.get("program"), base)
        if not prog.is_file():
            raise StudyError(
                f"[damping]: the program {prog} is not found; build it with "
                "`cargo build --release --bin periodic`, or give its path with [damping] program "
                f"or ${damping.PROGRAM_ENV}"
            )
        damping_program = str(prog)
    cont = None
    if "continuation" in data:
        if designs:
            raise StudyError("[continuation] sweeps its own speeds, series by series; a study "
                             "with it has no [grid], [list] or [lhs] (vary a value per series "
                             "with [[continuation.series]] set = {...})")
        cont = continuation_mod.parse(data["continuation"], cat, base, _axis)
    run = data.get("run", {})
    tol = run.get("tolerance")
    return Study(
        name=meta.get("name", path.stem if path else "study"),
        path=path,
        fmu=fmu_path,
        catalog=cat,
        points=points,
        varied=varied,
        fixed=fixed,
        outputs=outputs,
        orders=orders,
        window=window,
        chunk_size=int(run.get("chunk_size", 0)),
        tolerance=None if tol is None else float(tol),
        extra={"description": meta.get("description", "")},
        fmu_sha256=hashlib.sha256(fmu_path.read_bytes()).hexdigest(),
        damping_modes=damping_modes,
        damping_program=damping_program,
        continuation=cont,
    )


def _fmu_path(given, in_file, base: Path | None) -> Path:
    if given is not None:
        p = Path(given)
    elif in_file is not None:
        p = Path(in_file)
        if not p.is_absolute() and base is not None:
            p = base / p
    else:
        p = _find_repo_fmu(base)
    if not p.is_file():
        raise StudyError(
            f"FMU {p} not found; build it with `cargo run --release --bin package-fmu` or "
            f"give its path with --fmu or [study] fmu"
        )
    return p.resolve()


def _find_repo_fmu(base: Path | None) -> Path:
    for start in [Path.cwd()] + ([base.resolve()] if base else []):
        for d in [start, *start.parents]:
            if (d / REPO_FMU).is_file():
                return d / REPO_FMU
    return Path.cwd() / REPO_FMU


def _axis(name: str, spec, cat: Catalog, where: str) -> list:
    if isinstance(spec, dict):
        bad = set(spec) - {"start", "stop", "num"}
        if bad or not {"start", "stop", "num"} <= set(spec):
            raise StudyError(f"{where}{name}: a range is {{start = .., stop = .., num = N}}")
        a = cat.to_fmu_value(name, spec["start"], where)
        b = cat.to_fmu_value(name, spec["stop"], where)
        num = int(spec["num"])
        if num < 1:
            raise StudyError(f"{where}{name}: num must be >= 1")
        vals = np.linspace(a, b, num)
        if isinstance(a, int) and isinstance(b, int):
            return sorted(set(int(round(x)) for x in vals))
        return [float(x) for x in vals]
    if isinstance(spec, list):
        if not spec:
            raise StudyError(f"{where}{name}: empty list of values")
        return [cat.to_fmu_value(name, x, where) for x in spec]
    return [cat.to_fmu_value(name, spec, where)]


def _grid(table: dict, cat: Catalog):
    names = list(table)
    axes = [_axis(n, table[n], cat, "[grid] ") for n in names]
    return names, list(itertools.product(*axes))


def _list(table: dict, cat: Catalog):
    names = list(table)
    cols = [_axis(n, table[n] if isinstance(table[n], list) else [table[n]], cat, "[list] ") for n in names]
    lengths = {len(c) for c in cols}
    if len(lengths) > 1:
        raise StudyError(
            "[list] the lists must have equal lengths (one point per position); got "
            + ", ".join(f"{n}: {len(c)}" for n, c in zip(names, cols))
        )
    return names, list(zip(*cols))


def _lhs(table: dict, cat: Catalog):
    """Latin hypercube (McKay, Beckman & Conover 1979): each range cut into n equal strata,
    one sample per stratum and variable, strata paired by independent random permutations."""
    table = dict(table)
    try:
        n = int(table.pop("n"))
    except KeyError:
        raise StudyError("[lhs] needs n = number of points") from None
    seed = int(table.pop("seed", 0))
    if n < 1:
        raise StudyError("[lhs] n must be >= 1")
    rng = np.random.default_rng(seed)
    names = list(table)
    cols = []
    for name in names:
        rng_spec = table[name]
        if not (isinstance(rng_spec, list) and len(rng_spec) == 2):
            raise StudyError(f"[lhs] {name}: give a range [low, high], e.g. [\"0 deg\", \"30 deg\"]")
        lo, hi = (cat.to_fmu_value(name, x, "[lhs] ") for x in rng_spec)
        u = (rng.permutation(n) + rng.random(n)) / n
        x = lo + u * (hi - lo)
        if cat.variables[name].type in ("Integer", "Enumeration"):
            cols.append([int(math.floor(v + 0.5)) for v in x])
        else:
            cols.append([float(v) for v in x])
    return names, list(zip(*cols))
