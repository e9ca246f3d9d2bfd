"""Draws docs/figures/geared_rotor.svg: both rotors on their bearings, the frame
x/y/z, the senses of phi1 and phi2, the line of action T1-T2 with the normal force,
and the helix hand (docs/model.md §1). Plain SVG text, no dependencies; the
proportions are those of the default pair (docs/model.md §10), not to scale for
the bearings. Run: python3 scripts/draw_sketch.py (rewrites the committed file).
"""

from __future__ import annotations

import math
from pathlib import Path

OUT = Path(__file__).resolve().parents[1] / "docs" / "figures" / "geared_rotor.svg"

# default pair (mm): base radii and operating centre distance, working pressure angle
RB1, RB2, AW, ALPHA = 26.793, 40.686, 72.364, math.radians(21.173)
RA1, RA2 = 29.737, 45.642  # tip radii (approx., drawing only)
S = 3.2  # px per mm in view (a)
W, H = 980, 470


def arrow(x1, y1, x2, y2, color="black", width=1.6, head=9):
    ang = math.atan2(y2 - y1, x2 - x1)
    hx1 = x2 - head * math.cos(ang - 0.35)
    hy1 = y2 - head * math.sin(ang - 0.35)
    hx2 = x2 - head * math.cos(ang + 0.35)
    hy2 = y2 - head * math.sin(ang + 0.35)
    return (f'<line x1="{x1:.1f}" y1="{y1:.1f}" x2="{x2:.1f}" y2="{y2:.1f}" stroke="{color}" '
            f'stroke-width="{width}"/><polygon points="{x2:.1f},{y2:.1f} {hx1:.1f},{hy1:.1f} '
            f'{hx2:.1f},{hy2:.1f}" fill="{color}"/>')


def spring(x1, y1, x2, y2, n=6, amp=5, color="#555"):
    """Zig-zag spring with a damper box beside it, from (x1, y1) to (x2, y2)."""
    L = math.hypot(x2 - x1, y2 - y1)
    ux, uy = (x2 - x1) / L, (y2 - y1) / L
    px, py = -uy, ux
    pts = [(x1, y1)]
    for i in range(1, 2 * n):
        s = i / (2 * n)
        sgn = 1 if i % 2 else -1
        pts.append((x1 + ux * L * s + px * amp * sgn, y1 + uy * L * s + py * amp * sgn))
    pts.append((x2, y2))
    path = " ".join(f"{x:.1f},{y:.1f}" for x, y in pts)
    return f'<polyline points="{path}" fill="none" stroke="{color}" stroke-width="1.3"/>'


def ground(x, y, horizontal=True):
    if horizontal:
        marks = "".join(f'<line x1="{x - 12 + 6 * i:.1f}" y1="{y:.1f}" x2="{x - 16 + 6 * i:.1f}" '
                        f'y2="{y + 6:.1f}" stroke="#555"/>' for i in range(5))
        return f'<line x1="{x - 14:.1f}" y1="{y:.1f}" x2="{x + 14:.1f}" y2="{y:.1f}" stroke="#555" stroke-width="2"/>' + marks
    marks = "".join(f'<line x1="{x:.1f}" y1="{y - 12 + 6 * i:.1f}" x2="{x + 6:.1f}" '
                    f'y2="{y - 16 + 6 * i:.1f}" stroke="#555"/>' for i in range(5))
    return f'<line x1="{x:.1f}" y1="{y - 14:.1f}" x2="{x:.1f}" y2="{y + 14:.1f}" stroke="#555" stroke-width="2"/>' + marks


def view_transverse() -> list[str]:
    o = []
    cx1, cy = 150.0, 250.0
    cx2 = cx1 + AW * S
    o.append('<text x="20" y="28" font-size="15" font-weight="bold">(a) transverse plane, seen from +z</text>')
    for cx, rb, ra, name, col in [(cx1, RB1, RA1, "1", "#c0392b"), (cx2, RB2, RA2, "2", "#1f4e9c")]:
        o.append(f'<circle cx="{cx:.1f}" cy="{cy:.1f}" r="{ra * S:.1f}" fill="{col}" fill-opacity="0.08" '
                 f'stroke="{col}" stroke-dasharray="5 3"/>')
        o.append(f'<circle cx="{cx:.1f}" cy="{cy:.1f}" r="{rb * S:.1f}" fill="none" stroke="{col}" stroke-width="1.8"/>')
        o.append(f'<circle cx="{cx:.1f}" cy="{cy:.1f}" r="3.5" fill="black"/>')
        o.append(f'<text x="{cx - 34:.1f}" y="{cy + 20:.1f}" fill="{col}">gear {name}, c{name}</text>')
        # bearing: spring in x (to the left/right) and in y (downwards)
        sx = -1 if name == "1" else 1
        x_end = cx + sx * (ra * S + 28)
        o.append(spring(cx + sx * 4, cy, x_end, cy))
        o.append(ground(x_end, cy, horizontal=False))
        o.append(spring(cx, cy + 4, cx, cy + ra * S + 30))
        o.append(ground(cx, cy + ra * S + 30, horizontal=True))
    o.append(f'<text x="{cx1 - 118:.1f}" y="{cy - 12:.1f}" font-size="11">k1.x, d1.x</text>')
    o.append(f'<text x="{cx1 + 8:.1f}" y="{cy + RA1 * S + 22:.1f}" font-size="11">k1.y, d1.y</text>')
    o.append(f'<text x="{cx2 + RA2 * S + 6:.1f}" y="{cy - 12:.1f}" font-size="11">k2.x, d2.x</text>')
    o.append(f'<text x="{cx2 + 8:.1f}" y="{cy + RA2 * S + 22:.1f}" font-size="11">k2.y, d2.y</text>')
    # line of action: e_w = (cos a, -sin a) in model coordinates (theta = 0); SVG y is down
    ewx, ewy = math.cos(ALPHA), math.sin(ALPHA)  # SVG: model -sin a -> +sin a downwards
    t1 = (cx1 + RB1 * S * ewx, cy + RB1 * S * ewy)
    t2 = (cx2 - RB2 * S * ewx, cy - RB2 * S * ewy)
    o.append(f'<line x1="{cx1:.1f}" y1="{cy:.1f}" x2="{t1[0]:.1f}" y2="{t1[1]:.1f}" stroke="#c0392b"/>')
    o.append(f'<line x1="{cx2:.1f}" y1="{cy:.1f}" x2="{t2[0]:.1f}" y2="{t2[1]:.1f}" stroke="#1f4e9c"/>')
    o.append(f'<line x1="{t1[0]:.1f}" y1="{t1[1]:.1f}" x2="{t2[0]:.1f}" y2="{t2[1]:.1f}" stroke="#222" stroke-width="1.4"/>')
    for (px, py), lab, dx, dy in [(t1, "T1", -4, 18), (t2, "T2", -10, -9)]:
        o.append(f'<circle cx="{px:.1f}" cy="{py:.1f}" r="3"/><text x="{px + dx:.1f}" y="{py + dy:.1f}">{lab}</text>')
    # pitch point C on the line of centres
    pc = cx1 + RB1 / math.cos(ALPHA) * S
    o.append(f'<circle cx="{pc:.1f}" cy="{cy:.1f}" r="3" fill="#2e7d32"/><text x="{pc + 5:.1f}" y="{cy + 16:.1f}" fill="#2e7d32">C</text>')
    o.append(f'<line x1="{cx1:.1f}" y1="{cy:.1f}" x2="{cx2:.1f}" y2="{cy:.1f}" stroke="#999" stroke-dasharray="2 3"/>')
    # direction t of the line of action and the normal force on gear 2
    tx, ty = t2[0] - t1[0], t2[1] - t1[1]
    L = math.hypot(tx, ty)
    tx, ty = tx / L, ty / L
    o.append(arrow(pc + 6 * tx, cy + 6 * ty, pc + 60 * tx, cy + 60 * ty, "#2e7d32", 2.2))
    o.append(f'<line x1="{pc + 60 * tx:.1f}" y1="{cy + 60 * ty:.1f}" x2="{pc + 60 * tx:.1f}" y2="72" stroke="#2e7d32" stroke-dasharray="2 2"/>')
    o.append(f'<text x="{pc + 60 * tx - 60:.1f}" y="66" fill="#2e7d32">t: line of action T1&#8594;T2 (at alpha_wt); force +Fn on gear 2, -Fn on gear 1</text>')
    # senses of rotation: phi1 about +z (counter-clockwise on screen), phi2 about -z
    for cx, r, ccw, lab in [(cx1, RB1 * S * 0.55, True, "phi1, omega1 about +z"), (cx2, RB2 * S * 0.5, False, "phi2, omega2 about -z")]:
        a0, a1 = (math.radians(110), math.radians(200)) if ccw else (math.radians(70), math.radians(-20))
        x0, y0 = cx + r * math.cos(a0), cy - r * math.sin(a0)
        x1, y1 = cx + r * math.cos(a1), cy - r * math.sin(a1)
        sweep = 1 if not ccw else 0
        o.append(f'<path d="M {x0:.1f} {y0:.1f} A {r:.1f} {r:.1f} 0 0 {sweep} {x1:.1f} {y1:.1f}" fill="none" stroke="black" stroke-width="1.5"/>')
        # arrow head tangent at the end
        da = 0.15 if ccw else -0.15
        xe, ye = cx + r * math.cos(a1 + da), cy - r * math.sin(a1 + da)
        o.append(arrow(x1, y1, x1 + (xe - x1) * 0.05, y1 + (ye - y1) * 0.05, "black", 1.5, 9))
        o.append(f'<text x="{cx - 50:.1f}" y="{cy - r - 14:.1f}" font-size="11">{lab}</text>')
    # frame
    ox, oy = 40.0, 430.0
    o.append(arrow(ox, oy, ox + 45, oy))
    o.append(arrow(ox, oy, ox, oy - 45))
    o.append(f'<circle cx="{ox:.1f}" cy="{oy:.1f}" r="5" fill="none" stroke="black"/><circle cx="{ox:.1f}" cy="{oy:.1f}" r="1.5"/>')
    o.append(f'<text x="{ox + 48:.1f}" y="{oy + 4:.1f}">x</text><text x="{ox - 4:.1f}" y="{oy - 50:.1f}">y</text>'
             f'<text x="{ox + 8:.1f}" y="{oy + 16:.1f}">z (towards the viewer)</text>')
    return o


def view_axial() -> list[str]:
    """(b) the pair seen from -y: axes vertical (z up), tooth traces of the hands."""
    o = []
    x0 = 640.0
    o.append(f'<text x="{x0 - 20:.1f}" y="28" font-size="15" font-weight="bold">(b) seen from -y: helix hand (beta &gt; 0)</text>')
    zc, hb = 250.0, 70.0  # centre height and half face width in px
    s = 2.0
    c1 = x0 + 20 + RA1 * s
    c2 = c1 + AW * s
    for cx, ra, name, col, hand in [(c1, RA1, "1", "#c0392b", "left hand"), (c2, RA2, "2", "#1f4e9c", "right hand")]:
        o.append(f'<rect x="{cx - ra * s:.1f}" y="{zc - hb:.1f}" width="{2 * ra * s:.1f}" height="{2 * hb:.1f}" '
                 f'fill="{col}" fill-opacity="0.08" stroke="{col}"/>')
        # tooth traces on the near side: a left-hand helix rises to the left, a right-hand
        # one to the right (seen from any side, axis vertical)
        slope = math.tan(math.radians(20)) * (-1 if name == "1" else 1)
        for i in range(-4, 5):
            xa = cx + i * 12 - slope * hb
            xb = cx + i * 12 + slope * hb
            xa_c, xb_c = min(max(xa, cx - ra * s), cx + ra * s), min(max(xb, cx - ra * s), cx + ra * s)
            o.append(f'<line x1="{xa_c:.1f}" y1="{zc + hb:.1f}" x2="{xb_c:.1f}" y2="{zc - hb:.1f}" stroke="{col}" stroke-width="1.1"/>')
        # shaft, bearings at both ends (springs in z: k.z, d.z)
        o.append(f'<line x1="{cx:.1f}" y1="{zc - hb - 45:.1f}" x2="{cx:.1f}" y2="{zc + hb + 45:.1f}" stroke="black" stroke-width="3"/>')
        o.append(spring(cx, zc + hb + 45, cx, zc + hb + 80))
        o.append(ground(cx, zc + hb + 80))
        o.append(f'<text x="{cx - 28:.1f}" y="{zc - hb - 52:.1f}" fill="{col}">gear {name}: {hand}</text>')
        o.append(f'<text x="{cx + 6:.1f}" y="{zc + hb + 70:.1f}" font-size="11">k{name}.z, d{name}.z</text>')
    ox, oy = x0 - 10, 430.0
    o.append(arrow(ox, oy, ox + 45, oy))
    o.append(arrow(ox, oy, ox, oy - 45))
    o.append(f'<text x="{ox + 48:.1f}" y="{oy + 4:.1f}">x</text><text x="{ox - 4:.1f}" y="{oy - 50:.1f}">z</text>'
             f'<text x="{ox + 8:.1f}" y="{oy + 16:.1f}">y away from the viewer; beta &lt; 0 swaps the hands</text>')
    return o


def main() -> None:
    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" viewBox="0 0 {W} {H}" '
             'font-family="sans-serif" font-size="13">',
             f'<rect width="{W}" height="{H}" fill="white"/>']
    parts += view_transverse()
    parts += view_axial()
    parts.append("</svg>")
    OUT.parent.mkdir(parents=True, exist_ok=True)
    OUT.write_text("\n".join(parts) + "\n", encoding="utf-8")
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
