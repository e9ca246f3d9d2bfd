"""Independent gear-pair formulas (model.md section 2 and 9.7), written from the
spec in plain Python so the FMU's calculated parameters and its simulated losses
can be checked against something that does not share code with it.

All angles in rad, lengths in m.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace


def inv(x: float) -> float:
    """Involute function inv x = tan x - x (model.md section 2)."""
    return math.tan(x) - x


def inv_inverse(y: float) -> float:
    """Solve inv(x) = y for x in (0, pi/2) by Newton (d inv / dx = tan^2 x)."""
    # Cube-root start: inv x ~ x^3/3 for small x.
    x = (3.0 * y) ** (1.0 / 3.0) if y > 0 else 1e-3
    for _ in range(100):
        f = inv(x) - y
        dx = f / math.tan(x) ** 2
        x -= dx
        if abs(dx) < 1e-16:
            break
    return x


@dataclass(frozen=True)
class GearData:
    """Gear data of model.md section 10 (defaults) in the FMU's parameter names."""

    z1: int = 27
    z2: int = 41
    m_n: float = 2.0e-3
    alpha_n: float = math.radians(20.0)
    beta: float = math.radians(20.0)
    b: float = 18e-3
    x1: float = 0.0
    x2: float = 0.0
    h_aP: float = 1.0
    a_w_set: float = 0.0

    def with_(self, **kw) -> "GearData":
        return replace(self, **kw)


@dataclass(frozen=True)
class Geometry:
    alpha_t: float
    r1: float
    r2: float
    r_b1: float
    r_b2: float
    beta_b: float
    p_bt: float
    alpha_wt: float
    a_w: float
    r_a1: float
    r_a2: float
    sigma_A: float
    sigma_E: float
    sigma_C: float
    eps_alpha: float
    eps_beta: float
    eps_1: float
    eps_2: float

    @property
    def u(self) -> float:
        return self.r_b2 / self.r_b1


def geometry(g: GearData) -> Geometry:
    """model.md section 2, at the nominal position (a = a_w, alpha = alpha_wt)."""
    alpha_t = math.atan(math.tan(g.alpha_n) / math.cos(g.beta))
    r1 = g.z1 * g.m_n / (2.0 * math.cos(g.beta))
    r2 = g.z2 * g.m_n / (2.0 * math.cos(g.beta))
    r_b1 = r1 * math.cos(alpha_t)
    r_b2 = r2 * math.cos(alpha_t)
    beta_b = math.asin(math.sin(g.beta) * math.cos(g.alpha_n))
    p_bt = 2.0 * math.pi * r_b1 / g.z1
    if g.a_w_set > 0.0:
        a_w = g.a_w_set
        alpha_wt = math.acos((r_b1 + r_b2) / a_w)
    else:
        alpha_wt = inv_inverse(
            inv(alpha_t) + 2.0 * math.tan(g.alpha_n) * (g.x1 + g.x2) / (g.z1 + g.z2)
        )
        a_w = (r_b1 + r_b2) / math.cos(alpha_wt)
    r_a1 = r1 + g.m_n * (g.h_aP + g.x1)
    r_a2 = r2 + g.m_n * (g.h_aP + g.x2)
    sigma_E = math.sqrt(r_a1**2 - r_b1**2)
    sigma_A = a_w * math.sin(alpha_wt) - math.sqrt(r_a2**2 - r_b2**2)
    sigma_C = r_b1 * math.tan(alpha_wt)
    return Geometry(
        alpha_t=alpha_t,
        r1=r1,
        r2=r2,
        r_b1=r_b1,
        r_b2=r_b2,
        beta_b=beta_b,
        p_bt=p_bt,
        alpha_wt=alpha_wt,
        a_w=a_w,
        r_a1=r_a1,
        r_a2=r_a2,
        sigma_A=sigma_A,
        sigma_E=sigma_E,
        sigma_C=sigma_C,
        eps_alpha=(sigma_E - sigma_A) / p_bt,
        eps_beta=g.b * math.tan(beta_b) / p_bt,
        eps_1=(sigma_C - sigma_A) / p_bt,
        eps_2=(sigma_E - sigma_C) / p_bt,
    )


def h_v_helical_integer_overlap(g: GearData) -> float:
    """H_V for a helical pair with integer eps_beta (model.md 9.7, first formula):
    H_V = pi (u+1)/(z1 u cos beta_b) * (eps_1^2 + eps_2^2)/eps_alpha."""
    geo = geometry(g)
    u = g.z2 / g.z1
    return (
        math.pi
        * (u + 1.0)
        / (g.z1 * u * math.cos(geo.beta_b))
        * (geo.eps_1**2 + geo.eps_2**2)
        / geo.eps_alpha
    )


def h_v_spur(g: GearData) -> float:
    """H_V for a spur pair, 1 < eps_alpha < 2, load shared equally in double
    contact (model.md 9.7, second formula)."""
    geo = geometry(g)
    u = g.z2 / g.z1
    e1, e2 = geo.eps_1, geo.eps_2
    bracket = e1**2 + e2**2 + (1.0 - e1) * abs(1.0 - e1) + (1.0 - e2) * abs(1.0 - e2)
    return math.pi * (u + 1.0) / (2.0 * g.z1 * u) * bracket


def h_v_ohlendorf(g: GearData) -> float:
    """Ohlendorf's spur formula pi (u+1)/(z1 u) (1 - eps_alpha + eps_1^2 + eps_2^2),
    equal to h_v_spur when eps_1, eps_2 <= 1."""
    geo = geometry(g)
    u = g.z2 / g.z1
    return (
        math.pi
        * (u + 1.0)
        / (g.z1 * u)
        * (1.0 - geo.eps_alpha + geo.eps_1**2 + geo.eps_2**2)
    )


def face_width_for_overlap(g: GearData, eps_beta: float) -> float:
    """b such that eps_beta = b tan(beta_b)/p_bt takes the given value."""
    geo = geometry(g)
    return eps_beta * geo.p_bt / math.tan(geo.beta_b)


def mesh_period(z1: int, omega1: float) -> float:
    """T_m = 2 pi/(z1 omega1) (model.md 9.9)."""
    return 2.0 * math.pi / (z1 * omega1)
