"""A tour of the surfaces: the seed's rational ellipsoid, a vase of revolution, a
Coons patch, a cubic Bezier triangle and two bicubic patches joined with G1.

Each model is checked against an independent property (the implicit equation,
the distance from the axis, the boundary curves, its own NURBS form, the
continuity across the shared edge) and drawn as a shaded 3-D PNG.

Run: python examples/surfaces_tour.py [OUTDIR]
"""
import sys
from pathlib import Path

import numpy as np

import cagd
from cagd.plotting import plot_surfaces

TOL = 1e-12                                   # relative to the model's size
PROFILE = np.array([[30.0, 0.0], [34.0, 12.0], [40.0, 30.0], [36.0, 52.0], [24.0, 70.0], [20.0, 84.0],
                    [22.0, 95.0]])            # vase profile (x, z) in mm


def size_of(points: np.ndarray) -> float:
    pts = np.asarray(points).reshape(-1, 3)
    return float(np.linalg.norm(pts.max(axis=0) - pts.min(axis=0)))


def ellipsoid_model(out, rows):
    a, b, c = 3.0, 2.0, 1.5
    patches = cagd.ellipsoid(a, b, c)
    t = np.linspace(0.0, 1.0, 50)
    worst = 0.0
    for patch in patches:
        P = patch.grid(t, t)
        worst = max(worst, float(np.abs((P[..., 0] / a) ** 2 + (P[..., 1] / b) ** 2 + (P[..., 2] / c) ** 2
                                        - 1.0).max()))
    rows.append(("ellipsoid 3, 2, 1.5", "|x2/a2+y2/b2+z2/c2-1|, 8 x 50x50", worst, TOL))
    title = "seed 003 2.4: ellipsoid as 8 rational bicubic Bezier patches"
    return plot_surfaces(out / "ellipsoid.png", title, patches, [patches[0].control_points])


def vase_model(out, rows):
    pts = np.column_stack([PROFILE[:, 0], np.zeros(len(PROFILE)), PROFILE[:, 1]])
    profile = cagd.natural_cubic_spline(pts, "natural", "chord")
    vase = cagd.revolve(profile)                      # about the z-axis, full turn
    us = np.linspace(*profile.domain, 80)
    vs = np.linspace(0.0, 1.0, 60)
    S = vase.grid(us, vs)
    C = profile(us)
    radius = np.hypot(S[..., 0], S[..., 1])
    scale = size_of(S)
    dr = float(np.abs(radius - C[:, None, 0]).max()) / scale
    dz = float(np.abs(S[..., 2] - C[:, None, 2]).max()) / scale
    rows.append(("vase (revolved spline)", "|dist from axis - profile x| / size", dr, TOL))
    rows.append(("vase (revolved spline)", "|z - profile z| / size", dz, TOL))
    return plot_surfaces(out / "vase.png", "natural cubic spline profile revolved about z", [vase],
                         [vase.control_points[:, :1]])           # the profile's control polygon


def coons_model(out, rows):
    c0 = cagd.BezierCurve([[0, 0, 0], [1, 0, 0.8], [2, 0, -0.4], [3, 0, 0]])
    c1 = cagd.BezierCurve([[0, 3, 1], [1, 3, 0.2], [2, 3, 1.6], [3, 3, 1]])
    d0 = cagd.BezierCurve([[0, 0, 0], [0, 1, -0.6], [0, 2, 1.4], [0, 3, 1]])
    d1 = cagd.BezierCurve([[3, 0, 0], [3, 1.5, 1.2], [3, 3, 1]])
    patch = cagd.CoonsPatch(c0, c1, d0, d1)
    t = np.linspace(0.0, 1.0, 101)
    zero, one = np.zeros_like(t), np.ones_like(t)
    edges = [(patch(t, zero), c0(t)), (patch(t, one), c1(t)), (patch(zero, t), d0(t)), (patch(one, t), d1(t))]
    g = np.linspace(0.0, 1.0, 50)
    S = patch.grid(g, g)
    scale = size_of(S)
    boundary = max(float(np.abs(p - q).max()) for p, q in edges) / scale
    nurbs = float(np.abs(patch.to_nurbs().grid(g, g) - S).max()) / scale
    rows.append(("Coons patch", "|S - boundary curve| / size, 4 x 101", boundary, TOL))
    rows.append(("Coons patch", "|to_nurbs() - S| / size, 50x50", nurbs, TOL))
    return plot_surfaces(out / "coons.png", "bilinearly blended Coons patch from four Bezier curves", [patch],
                         [c.control_points[None] for c in (c0, c1, d0, d1)])


def triangle_model(out, rows):
    corners = np.array([[0.0, 0.0, 0.0], [3.5, 2.0, 0.0], [0.0, 4.0, 0.0]])   # vertices of u, v, w
    bumps = {(1, 1, 1): 2.0, (2, 1, 0): 0.8, (0, 1, 2): -0.6, (1, 0, 2): 0.5}
    net = {}
    for i, j, k in cagd.BezierTriangle.index_triples(3):
        x = (i * corners[0] + j * corners[1] + k * corners[2]) / 3.0
        net[(i, j, k)] = x + [0.0, 0.0, bumps.get((i, j, k), 0.0)]
    tri = cagd.BezierTriangle(net)
    g = np.linspace(0.0, 1.0, 50)
    s, t = np.meshgrid(g, g, indexing="ij")
    T = tri(s, (1.0 - s) * t)                         # to_nurbs is T(s, (1 - s) t) on [0, 1]^2
    dev = float(np.abs(tri.to_nurbs().grid(g, g) - T).max()) / size_of(T)
    rows.append(("cubic Bezier triangle", "|to_nurbs()(s,t) - T(s,(1-s)t)| / size", dev, TOL))
    return plot_surfaces(out / "triangle.png", "cubic Bezier triangle and its control net", [tri], [tri.control_points])


def g1_model(out, rows, alpha=1.5):
    """Seed 003, 2.2.3: C0 shares the boundary row, C1 matches the difference vectors;
    G1 keeps their direction only, Q_1j - Q_0j = alpha (P_3j - P_2j)."""
    i, j = np.meshgrid(np.arange(4.0), np.arange(4.0), indexing="ij")
    z1 = np.array([[0, 0.5, 0.3, 0], [0.2, 1.2, 1.0, 0.4], [0.6, 1.6, 1.4, 0.9], [1.0, 1.5, 1.8, 1.2]])
    P = np.stack([i, j, z1], axis=-1)
    Q = np.empty_like(P)
    Q[0] = P[3]                                        # C0: shared boundary row
    Q[1] = P[3] + alpha * (P[3] - P[2])                # G1: difference vectors alpha times the first
    Q[2] = Q[1] + [1.2, 0.1, -0.3]                     # the rest is free
    Q[3] = Q[2] + [1.0, -0.1, -0.5]
    A, B = cagd.BezierSurface(P), cagd.BezierSurface(Q)
    rep = cagd.edge_continuity(A, B, "u1", "u0")
    rows.append(("G1 bicubic pair", f"edge gap / size ({rep.level})", rep.gap / rep.size, TOL))
    rows.append(("G1 bicubic pair", "tangent-plane angle (rad)", rep.normal_angle, rep.tol))
    rows.append(("G1 bicubic pair", "|D2 - D1| / scale (so not C1)", rep.cross_derivative_mismatch
                 / rep.derivative_scale, -rep.tol))
    png = plot_surfaces(out / "g1_patches.png", f"two bicubic Bezier patches joined G1 (alpha = {alpha})", [A, B],
                        [P, Q])
    return rep.C0 and rep.G1 and not rep.C1, png


def main(out_dir: Path) -> int:
    out_dir.mkdir(parents=True, exist_ok=True)
    rows = []
    pngs = [model(out_dir, rows) for model in (ellipsoid_model, vase_model, coons_model, triangle_model)]
    g1, png = g1_model(out_dir, rows)
    pngs.append(png)
    ok = g1
    print(f"{'model':<24} {'check':<42} {'measured':>10}  limit")
    for model, check, value, limit in rows:
        # a negative limit asks for a value above |limit| (a property that must fail)
        good = value > -limit if limit < 0 else value <= limit
        ok = ok and good
        bound = f"> {-limit:.0e}" if limit < 0 else f"<= {limit:.0e}"
        print(f"{model:<24} {check:<42} {value:10.2e}  {bound}{'' if good else '  FAILED'}")
    print(f"G1 but not C1 across the shared edge: {g1}")
    for png in pngs:
        ok = ok and png.stat().st_size > 1000
        print(f"wrote {png}")
    print("checks passed" if ok else "CHECK FAILED")
    return 0 if ok else 1


if __name__ == "__main__":
    raise SystemExit(main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("out/examples")))
