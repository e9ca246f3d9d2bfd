"""`--set NAME=VALUE[unit]` for the main job: parses a parameter or input setting and
converts it to SI with the units the FMU's model description declares.

    omega1=1500rpm   beta=15deg   mu=0.1   k1.x=150N/um   T_load=0.05kN.m   z1=31

A value without a unit is taken in the variable's SI unit. A unit must be the
variable's unit or one of its declared display units (display = factor * SI + offset);
"µm" may be written for "um". Integer variables take whole numbers, Enumeration variables
their item name or number (initialization=rest or initialization=1), Booleans true/false.

A value without a unit that is implausible in the SI unit (a length of 1 m or more, a speed
above 1000 rad/s, an angle above 90 deg) is taken as given but `unitless_warning` says so:
`m_n=3` is a module of 3 m.
"""

from __future__ import annotations

import difflib
import re

_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
_PATTERN = re.compile(rf"^\s*([A-Za-z_][\w.\[\]]*)\s*=\s*({_NUMBER}|true|false)\s*(\S*)\s*$")
_NAMED = re.compile(r"^\s*([A-Za-z_][\w.\[\]]*)\s*=\s*([A-Za-z_]\w*)\s*$")

#: SI unit -> (largest plausible magnitude of a value given without a unit, what to write instead)
PLAUSIBLE_WITHOUT_UNIT = {
    "m": (1.0, "mm"),  # a gear length of 1 m or more written without unit is most likely mm
    "rad/s": (1000.0, "rpm"),  # 1000 rad/s = 9549 rpm
    "rad": (1.5707963267948966, "deg"),  # above 90 deg no angle of the model makes sense
}


class SetError(ValueError):
    """A --set argument that cannot be applied; the message says what to write instead."""


def unit_of(var) -> str:
    if var.unit:
        return var.unit
    return var.declaredType.unit if var.declaredType is not None and var.declaredType.unit else ""


def display_units(md, unit: str) -> dict[str, tuple[float, float]]:
    for u in md.unitDefinitions:
        if u.name == unit:
            return {d.name: (d.factor, d.offset) for d in u.displayUnits}
    return {}


def parse_set(md, text: str) -> tuple[str, float | int | bool]:
    """(name, value in SI) of one --set argument, checked against the model description."""
    variables = {v.name: v for v in md.modelVariables}
    named = _NAMED.match(text)
    if named and named.group(2) not in ("true", "false"):
        return _parse_named(variables, text, *named.groups())
    m = _PATTERN.match(text)
    if not m:
        raise SetError(f"--set {text!r}: write NAME=VALUE or NAME=VALUEunit, e.g. omega1=1500rpm")
    name, number, unit = m.groups()
    if name not in variables:
        close = difflib.get_close_matches(name, variables, n=3)
        hint = f"; did you mean {', '.join(close)}?" if close else ""
        raise SetError(f"--set {text!r}: the FMU has no variable {name!r}{hint}")
    var = variables[name]
    if var.causality not in ("parameter", "input"):
        raise SetError(f"--set {text!r}: {name} is a {var.causality}; only parameters and inputs can be set")
    if var.type == "Boolean":
        if number not in ("true", "false") or unit:
            raise SetError(f"--set {text!r}: {name} is Boolean, write {name}=true or {name}=false")
        return name, number == "true"
    if number in ("true", "false"):
        raise SetError(f"--set {text!r}: {name} is {var.type}, not Boolean")
    value = float(number)
    si = unit_of(var)
    if unit.replace("µ", "u") in ("", si):
        pass
    else:
        table = display_units(md, si)
        key = unit.replace("µ", "u")
        if key not in table:
            accepted = [si or "(none)"] + list(table)
            raise SetError(f"--set {text!r}: unit {unit!r} is not declared for {name}; "
                           f"use one of {', '.join(accepted)}")
        factor, offset = table[key]
        value = (value - offset) / factor
    if var.type in ("Integer", "Enumeration"):
        if value != round(value):
            raise SetError(f"--set {text!r}: {name} is {var.type}, give a whole number")
        # FMI Integers are 32-bit: a larger number would wrap before the FMU sees it.
        if not -2**31 <= value < 2**31:
            raise SetError(f"--set {text!r}: {name} = {value:g} is outside the 32-bit range of an "
                           "FMI Integer; give a value within the variable's bounds")
        return name, int(round(value))
    return name, value


def enum_items(var) -> list[tuple[str, int]]:
    """(name, value) of the items of an Enumeration variable, else []."""
    dt = getattr(var, "declaredType", None)
    items = getattr(dt, "items", None) or []
    return [(i.name, int(i.value)) for i in items]


def _parse_named(variables: dict, text: str, name: str, word: str) -> tuple[str, int]:
    if name not in variables:
        close = difflib.get_close_matches(name, variables, n=3)
        hint = f"; did you mean {', '.join(close)}?" if close else ""
        raise SetError(f"--set {text!r}: the FMU has no variable {name!r}{hint}")
    var = variables[name]
    items = enum_items(var)
    if not items:
        what = f": {var.description}" if var.description else ""
        raise SetError(f"--set {text!r}: {name} takes a number ({var.type}), not the word {word!r}{what}")
    for item, value in items:
        if item == word:
            return name, value
    listed = ", ".join(f"{n} (= {v})" for n, v in items)
    raise SetError(f"--set {text!r}: {name} has no item {word!r}; use one of {listed}")


def unitless_warning(md, text: str) -> str | None:
    """A warning when `text` gives a value without a unit that is implausible in the
    variable's SI unit (PLAUSIBLE_WITHOUT_UNIT), else None."""
    m = _PATTERN.match(text)
    if not m or m.group(3) or m.group(2) in ("true", "false"):
        return None
    name, number = m.group(1), float(m.group(2))
    var = next((v for v in md.modelVariables if v.name == name), None)
    if var is None or var.type != "Real":
        return None
    si = unit_of(var)
    if si not in PLAUSIBLE_WITHOUT_UNIT:
        return None
    limit, instead = PLAUSIBLE_WITHOUT_UNIT[si]
    if abs(number) < limit:
        return None
    return (f"--set {text!r}: no unit, so {name} = {number:g} {si}; that is implausible for a gear "
            f"pair (|{name}| >= {limit:g} {si}). If you meant {instead}, write {name}={m.group(2)}{instead}")
