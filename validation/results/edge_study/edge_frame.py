"""Profiles of the edge experiment in the border frame of p_e (no dependencies but Python 3).

For each run directory given as VARIANT_ANGLE=DIR, reads manifest.json and pose_000_profile.csv,
takes every valid profile point from the sensor frame to the base frame with the manifest's
sensor pose (R = Rz·Ry·Rx, mm), and expresses it relative to the ground-truth border point p_e:
`out_mm` along the horizontal outward direction of the border (the laser plane's in-surface
axis), `up_mm` along z. Writes edge_frame.csv and edge_frame.svg in the current directory.
"""
import csv, json, math, sys

def rot(rx, ry, rz):
    rx, ry, rz = (math.radians(v) for v in (rx, ry, rz))
    cx, sx, cy, sy, cz, sz = math.cos(rx), math.sin(rx), math.cos(ry), math.sin(ry), math.cos(rz), math.sin(rz)
    return [[cz*cy, cz*sy*sx - sz*cx, cz*sy*cx + sz*sx],
            [sz*cy, sz*sy*sx + cz*cx, sz*sy*cx - cz*sx],
            [-sy, cy*sx, cy*cx]]

rows = []
for arg in sys.argv[1:]:
    name, d = arg.split("=")
    m = json.load(open(f"{d}/manifest.json"))
    pose = m["poses"][0]
    t = pose["sensor_pose"]["translation_mm"]; R = rot(*pose["sensor_pose"]["rotation_deg"])
    pe = pose["edge_point_mm"]
    # The laser plane's horizontal in-plane axis, pointing away from the glass: the sensor looks
    # inwards, so outward = −(horizontal part of z_S).
    zs = [R[0][2], R[1][2]]; n = math.hypot(*zs); out = [-zs[0]/n, -zs[1]/n]
    for p in csv.DictReader(open(f"{d}/pose_000_profile.csv")):
        if p["valid"] != "1":
            continue
        xs, zs_ = float(p["x_mm"]), float(p["z_mm"])
        b = [t[i] + R[i][0]*xs + R[i][2]*zs_ for i in range(3)]
        rows.append((name, (b[0]-pe[0])*out[0] + (b[1]-pe[1])*out[1], b[2]-pe[2], int(p["intensity"])))

with open("edge_frame.csv", "w", newline="") as f:
    w = csv.writer(f); w.writerow(["run", "out_mm", "up_mm", "intensity"]); w.writerows(rows)

# SVG: one panel per angle, out_mm in [-15, 15], up_mm in [-6, 2].
colours = {"tape": "#2a9d8f", "cover": "#1d3557", "bare": "#e63946"}
W, H, X0, X1, Y0, Y1 = 420, 300, -15.0, 15.0, -6.0, 2.0
svg = ['<svg xmlns="http://www.w3.org/2000/svg" width="880" height="340" font-family="sans-serif" font-size="11">']
for k, angle in enumerate(["10", "40"]):
    ox = 20 + k*440
    sx = lambda x: ox + 30 + (x - X0)/(X1 - X0)*(W - 40)
    sy = lambda y: 20 + (Y1 - y)/(Y1 - Y0)*(H - 40)
    svg.append(f'<rect x="{ox+30}" y="20" width="{W-40}" height="{H-40}" fill="none" stroke="#999"/>')
    svg.append(f'<text x="{ox+30}" y="14">scan angle {angle}° — points relative to p_e (mm)</text>')
    svg.append(f'<line x1="{sx(0)}" y1="20" x2="{sx(0)}" y2="{H-20}" stroke="#ccc"/>')
    svg.append(f'<line x1="{ox+30}" y1="{sy(0)}" x2="{ox+W-10}" y2="{sy(0)}" stroke="#ccc"/>')
    for v in range(-15, 16, 5):
        svg.append(f'<text x="{sx(v)-6}" y="{H-6}">{v}</text>')
    for v in range(-6, 3, 2):
        svg.append(f'<text x="{ox}" y="{sy(v)+4}">{v}</text>')
    for name, o, u, _ in rows:
        variant, a = name.rsplit("_", 1)
        if a == angle and X0 <= o <= X1 and Y0 <= u <= Y1:
            svg.append(f'<circle cx="{sx(o):.1f}" cy="{sy(u):.1f}" r="1.3" fill="{colours[variant]}"/>')
for i, (v, c) in enumerate(colours.items()):
    svg.append(f'<circle cx="{60+i*90}" cy="330" r="4" fill="{c}"/><text x="{68+i*90}" y="334">{v}</text>')
svg.append("</svg>")
open("edge_frame.svg", "w").write("\n".join(svg))
