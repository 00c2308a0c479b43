"""Example 5 (CadQuery): a corner blend. Three quarter-cylinder fillets (radius R)
along the edges of a box corner end in three quarter circles; a rational quadratic
Bezier triangle (seed 003, 3; its edges rational quadratic arcs with weights
1, cos 45°, 1) closes the corner between them.

Checks: C0 along each of the triangle's three edges: the triangle's boundary curve
against the fillet's end circle (homogeneous control points equal; samples on the
circle; the two surfaces' points at matching parameters); the normal angle across
each edge is measured and reported (the quadratic triangle is not a sphere: C0 is
what is asked); the four faces sew into one shell; every surface through OCCT,
STEP and IGES (cagd.occ.verify).

Run: python examples/cq_corner_blend.py [OUTDIR]
"""
import numpy as np
import cadquery as cq

import cagd
import cq_ext
from cagd.occ import write_step
from _common import Checks, output_folder

L, R = 40.0, 8.0                 # box corner at (L, L, L), fillet radius R (mm)
C = L - R                        # the fillets' axes meet at (C, C, C)
W = np.sqrt(0.5)


def fillets():
    """Quarter cylinders along the z, x and y edges, each ending in the plane through (C, C, C)."""
    line = lambda p, q: cagd.BSplineCurve([p, q], 1)                                  # noqa: E731
    z = cagd.revolve(line([L, C, 0.0], [L, C, C]), (C, C, 0.0), (0, 0, 1), np.pi / 2)   # +x -> +y
    x = cagd.revolve(line([0.0, L, C], [C, L, C]), (0.0, C, C), (1, 0, 0), np.pi / 2)   # +y -> +z
    y = cagd.revolve(line([C, 0.0, L], [C, C, L]), (C, 0.0, C), (0, 1, 0), np.pi / 2)   # +z -> +x
    return {"z edge": z, "x edge": x, "y edge": y}


def corner_triangle() -> cagd.BezierTriangle:
    a, b, c = [L, C, C], [C, L, C], [C, C, L]
    points = {(2, 0, 0): a, (0, 2, 0): b, (0, 0, 2): c,
              (1, 1, 0): [L, L, C], (0, 1, 1): [C, L, L], (1, 0, 1): [L, C, L]}
    weights = {(2, 0, 0): 1.0, (0, 2, 0): 1.0, (0, 0, 2): 1.0, (1, 1, 0): W, (0, 1, 1): W, (1, 0, 1): W}
    return cagd.BezierTriangle(points, weights)


def main() -> None:
    out = output_folder("out/examples")
    checks = Checks("corner blend: a rational Bezier triangle between three fillets")
    tri = corner_triangle()
    fill = fillets()
    s = np.linspace(0.02, 0.98, 25)
    along = [(1 - s, s), (0 * s, 1 - s), (s, 0 * s)]         # the triangle's edges 1->2, 2->3, 3->1 in (u, v)
    for edge, (name, surf), (tu, tv) in zip(tri.boundaries(), fill.items(), along):
        u_end = surf.domain[0][1]
        arc = surf.isocurve("v", u_end)                        # the fillet's end circle
        mine = edge.to_nurbs()
        h_tri, h_arc = mine.homogeneous_control_points, arc.homogeneous_control_points
        forward = np.abs(h_tri - h_arc).max() <= np.abs(h_tri[::-1] - h_arc).max()
        same = np.abs((h_tri if forward else h_tri[::-1]) - h_arc).max()
        checks.at_most(f"{name}: homogeneous control points of the common edge differ by", same, 1e-12)
        p = tri(tu, tv)
        on_circle = np.abs(np.linalg.norm(p - C, axis=1) - R).max()
        checks.at_most(f"{name}: triangle edge on the fillet's circle, | |P - centre| - R | (mm)", on_circle, 1e-12)
        v0, v1 = surf.domain[1]
        v = v0 + (s if forward else 1 - s) * (v1 - v0)
        gap = np.linalg.norm(surf(u_end + 0 * s, v) - p, axis=1).max()
        checks.at_most(f"{name}: triangle edge vs fillet edge at matching parameters (mm)", gap, 1e-12)
        cosine = np.abs((tri.normal(tu, tv) * surf.normal(u_end + 0 * s, v)).sum(-1))
        angle = np.degrees(np.arccos(np.clip(cosine, -1.0, 1.0))).max()
        print(f"{name}: C0 gap {gap:.1e} mm; normal angle across the edge up to {angle:.2f} degrees")
    shell = cq_ext.sew_shell([cq_ext.to_cq(s) for s in fill.values()] + [cq_ext.to_cq(tri)], tol=1e-6)
    checks.true("the triangle and the three fillets sew into one shell", isinstance(shell, cq.Shell))
    checks.true("the shell is valid", shell.isValid())
    checks.verified([("corner triangle", tri)] + list(fill.items()))
    path = out / "corner_blend.step"
    write_step([("corner blend", shell.wrapped)], path)
    checks.true(f"{path.name} written", path.stat().st_size > 5000)
    checks.finish()


if __name__ == "__main__":
    main()
