"""The README's interface table agrees with modelDescription/modelDescription.xml:
every input and parameter is in it, with the declared unit, start value and min/max
(the SI numbers; the display values in brackets are checked against the declared
display-unit factor)."""

from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BASES = ("Real", "Integer", "Boolean", "String", "Enumeration")


def declared():
    md = ET.parse(ROOT / "modelDescription" / "modelDescription.xml").getroot()
    factors = {(u.get("name"), d.get("name")): float(d.get("factor", "1"))
               for u in md.iter("Unit") for d in u.iter("DisplayUnit")}
    types = {st.get("name"): dict(next(c for c in st if c.tag in BASES).attrib)
             for st in md.iter("SimpleType")}
    out = {}
    for sv in md.iter("ScalarVariable"):
        a = dict(next(c for c in sv if c.tag in BASES).attrib)
        for k, v in types.get(a.get("declaredType"), {}).items():
            a.setdefault(k, v)
        out[sv.get("name")] = (sv.get("causality"), a)
    return out, factors


def readme_rows():
    rows = {}
    for line in (ROOT / "README.md").read_text(encoding="utf-8").splitlines():
        m = re.match(r"^\| `([\w.]+)` \| (\w+) \| ([^|]*) \| ([^|]*) \| ([^|]*) \| [^|]+ \|$", line)
        if m:
            rows[m.group(1)] = [g.strip() for g in m.groups()[1:]]
    return rows


def check_value(text: str, si: str, unit: str, display: str | None, factors) -> None:
    m = re.fullmatch(r"(-?[\d.e+-]+)(?: \((-?[\d.e+-]+) (\S+)\))?", text)
    assert m, text
    assert math.isclose(float(m.group(1)), float(si), rel_tol=1e-5), (text, si)
    if m.group(2):
        assert m.group(3) == display, (text, display)
        assert math.isclose(float(m.group(2)), float(si) * factors[(unit, display)], rel_tol=1e-5,
                            abs_tol=1e-9), text


def test_readme_interface_table_matches_the_model_description():
    vars_, factors = declared()
    rows = readme_rows()
    wanted = {n for n, (c, _) in vars_.items() if c in ("input", "parameter")}
    assert wanted <= set(rows), f"missing from the README: {sorted(wanted - set(rows))}"
    for name, (kind, unit, start, rng) in rows.items():
        causality, a = vars_[name]
        assert kind == causality, name
        assert unit == a.get("unit", ""), name
        du = a.get("displayUnit")
        if "start" in a:
            check_value(start, a["start"], a.get("unit", ""), du, factors)
        lo, hi = a.get("min"), a.get("max")
        if lo is None and hi is None:
            assert rng == "", f"{name}: range {rng!r} but none declared"
            continue
        parts = [p.strip() for p in rng.split("..")]
        if len(parts) == 1:
            assert parts[0] == "> 0" and float(lo) == 1e-300 and hi is None, name
            continue
        for part, bound, inf in ((parts[0], lo, "-inf"), (parts[1], hi, "inf")):
            if bound is None:
                assert part == inf, (name, part)
            elif float(bound) == 1e-300:
                assert part == "> 0", (name, part)
            else:
                check_value(part, bound, a.get("unit", ""), du, factors)


def test_readme_keeps_the_quick_start():
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    assert "bash scripts/main.sh\nbash scripts/test.sh\n" in text
