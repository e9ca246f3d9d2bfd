"""Prints the README's interface table (inputs and parameters with unit, default,
declared range and meaning) from modelDescription/modelDescription.xml, so that the
README can be refreshed after the model description changes:

    python3 scripts/readme_table.py

and paste the output over the table in README.md "Interface" (tests/test_readme.py
checks that README and model description agree). Short meanings are kept here for the
core variables; others fall back to the description in the XML.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BASES = ("Real", "Integer", "Boolean", "String", "Enumeration")
MEANING = {
    "omega1": "speed of rotor 1 (smoothed by the input filter, model.md §8)",
    "T_load": "load torque on gear 2, against its rotation",
    "z1": "teeth of gear 1 (driving); with the other defaults z1 >= 13, else interference",
    "z2": "teeth of gear 2 (driven)",
    "m_n": "normal module", "alpha_n": "normal pressure angle",
    "beta": "helix angle; > 0: gear 1 left-hand, gear 2 right-hand; 0 = spur",
    "b": "face width", "x1": "profile shift of gear 1 (bounded by the rules of model.md §2)",
    "x2": "profile shift of gear 2 (idem)", "h_aP": "addendum coefficient of the basic rack",
    "a_w_set": "centre distance; 0 = from x1 + x2 (zero backlash)",
    "psi0": "initial mesh phase in base pitches (only the fractional part matters)",
    "m1": "mass of rotor 1; 0 = solid steel gear body from the geometry (`m1_solid`)",
    "J1": "polar inertia of rotor 1; 0 = solid steel gear body from the geometry (`J1_solid`)",
    "m2": "mass of rotor 2; 0 = solid steel gear body from the geometry (`m2_solid`)",
    "J2": "polar inertia of rotor 2; 0 = solid steel gear body from the geometry (`J2_solid`)", "d_phi": "rotational damper on gear 2 (tunable)",
    "mu": "Coulomb friction coefficient of laws 1 and 2 (tunable)",
    "friction_law": "1 Coulomb; 2 regularised Coulomb; 3 ISO/TR 14179-2 mean coefficient; "
                    "4 local EHL coefficient; 5 Benedict & Kelley coefficient (docs/friction.md)",
    "initialization": "1 rest, 2 static_equilibrium, 3 periodic (Enumeration; see below)",
    "on_lift_off": "1 warn, 2 discard, when Fn < 0 or the drive reverses (Enumeration)",
    "max_internal_steps": "most internal steps per doStep, then fmi2Discard (tunable)",
    "h_fixed": "real-time mode: fixed internal step bound; 0 = adaptive (see below)",
    "v_reg": "regularising speed of law 2", "eta_oil": "dynamic viscosity of the oil (laws 3, 4)",
    "Ra": "mean flank roughness (laws 3, 4)", "X_L": "lubricant factor of ISO/TR 14179-2 (law 3)",
    "E1": "Young's modulus of gear 1 (law 4)", "nu1": "Poisson's ratio of gear 1 (law 4)",
    "E2": "Young's modulus of gear 2 (law 4)", "nu2": "Poisson's ratio of gear 2 (law 4)",
    "omega1_filter_frequency": "corner frequency of the omega1 filter",
    "c_gamma": "mean mesh stiffness per unit face width; 0 = from ISO 6336-1 (calculated parameter "
               "`c_gamma_used`, docs/model.md §2.1); used by `tooth_contact = elastic` (§3.5), not by "
               "the rigid model",
    "h_fP": "dedendum coefficient of the basic rack (ISO 6336-1 stiffness only, docs/model.md §2.1)",
    "tooth_contact": "1 rigid (default: the paper's index-2 DAE), 2 elastic teeth: drive and coast "
                     "flanks, Fn = l(t) max(0, c_l delta + d_l delta') with c_l from `c_gamma_used`, "
                     "free flight in the backlash `j_bn` between them (docs/model.md §3.5, §3.6) "
                     "(Enumeration)",
    "zeta_mesh": "damping ratio of the elastic mesh on the equivalent mass of the mesh mode "
                 "(docs/model.md §3.5); elastic contact only",
    "j_bn": "normal backlash at the operating centre distance (play of the coast flanks), "
            "0 <= j_bn <= m_n/2, else refused; grows with the centre distance; elastic contact "
            "only (docs/model.md §3.6)",
    "rtol": "RADAU5 relative tolerance (fmi2SetupExperiment overrides)", "h_max": "largest internal step",
}


def fmt(x) -> str:
    x = float(x)
    return "0" if x == 0 else f"{x:.6g}"


def main() -> None:
    md = ET.parse(ROOT / "modelDescription" / "modelDescription.xml").getroot()
    units = {u.get("name"): {d.get("name"): float(d.get("factor", "1")) for d in u.iter("DisplayUnit")}
             for u in md.iter("Unit")}
    types = {st.get("name"): dict(next(c for c in st if c.tag in BASES).attrib) for st in md.iter("SimpleType")}
    print("| name | kind | unit | default | range | meaning |")
    print("|---|---|---|---|---|---|")
    for sv in md.iter("ScalarVariable"):
        a = dict(next(c for c in sv if c.tag in BASES).attrib)
        for k, v in types.get(a.get("declaredType"), {}).items():
            a.setdefault(k, v)
        name, causality = sv.get("name"), sv.get("causality")
        if causality not in ("input", "parameter"):
            continue
        du = a.get("displayUnit")

        def show(v):
            return fmt(v) + (f" ({fmt(float(v) * units[a['unit']][du])} {du})" if du else "")

        def bound(k):
            if k not in a:
                return None
            return "> 0" if float(a[k]) == 1e-300 else show(a[k])

        lo, hi = bound("min"), bound("max")
        if lo == "> 0" and hi is None:
            rng = "> 0"
        elif lo is None and hi is None:
            rng = ""
        else:
            rng = f"{lo or '-inf'} .. {hi or 'inf'}"
        if name[:2] in ("k1", "k2", "d1", "d2"):
            meaning = {"k": "bearing stiffness", "d": "bearing damping"}[name[0]] + f" of rotor {name[1]} in {name[-1]}"
        else:
            meaning = MEANING.get(name, sv.get("description"))
        start = show(a["start"]) if "start" in a else ""
        print(f"| `{name}` | {causality} | {a.get('unit', '')} | {start} | {rng} | {meaning} |")


if __name__ == "__main__":
    main()
