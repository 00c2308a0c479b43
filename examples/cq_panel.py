"""Example 4 (CadQuery): a freeform panel. Two bicubic Bezier patches joined with G1
across their common edge (the second patch's first inner row continues the first
patch's last row: Q1 = P3 + alpha (P3 - P2), seed 003's tensor-product form of the
seed 000 5.2.5 join), a G2 curve blend continuing one boundary (cagd.join, seed 000
5.2.5), the two faces thickened into a solid (OCCT offset) and cut with an
ordinary CadQuery box.

Checks: G1 across the patch edge (edge_continuity: gap, normal angle); G2 of the
blend (continuity: curvature difference); a valid thickened solid whose volume is
close to area x thickness (the offset of a free-form surface is approximated by
OCCT: a thin-wall estimate); a valid cut with V(panel) = V(cut) + V(panel ∩ box);
patches and curves through OCCT, STEP and IGES (cagd.occ.verify).

Run: python examples/cq_panel.py [OUTDIR]
"""
import numpy as np
import cadquery as cq

import cagd
import cq_ext
from cagd.occ import area, volume, write_step
from _common import Checks, output_folder

ALPHA = 0.8                # G1 ratio of the cross-boundary control legs
THICKNESS = 3.0            # mm


def patches():
    x, y = np.linspace(0.0, 60.0, 4), np.linspace(0.0, 60.0, 4)
    A = np.zeros((4, 4, 3))
    A[..., 0], A[..., 1] = x[:, None], y[None, :]
    A[..., 2] = [[0, 3, 3, 0], [2, 6, 7, 2], [3, 8, 7, 3], [2, 5, 5, 1]]
    B = np.zeros((4, 4, 3))
    B[0] = A[3]
    B[1] = A[3] + ALPHA * (A[3] - A[2])                   # the G1 condition, row by row
    B[2] = A[3] + [40.0, 0.0, 0.0]
    B[2][:, 2] = [1, 4, 4, 0]
    B[3] = A[3] + [60.0, 0.0, 0.0]
    B[3][:, 2] = [0, 2, 2, 0]
    return cagd.BezierSurface(A), cagd.BezierSurface(B)


def main() -> None:
    out = output_folder("out/examples")
    checks = Checks("freeform panel: two G1 bicubic patches, a G2 blend, thickened and cut")
    a, b = patches()
    g1 = cagd.edge_continuity(a, b, "u1", "u0")
    print(g1)
    checks.at_most("patch edge gap, relative", g1.gap / g1.size, 1e-12)
    checks.at_most("patch edge normal angle (rad): G1", g1.normal_angle, 1e-9)
    edge = cagd.BezierCurve(b.control_points[:, 0])           # the second patch's v = 0 boundary
    blend = cagd.join(edge, [[140.0, -20.0, 0.0]], "G2", 1.0, 0.5)
    g2 = cagd.continuity(edge, blend)
    print(g2)
    checks.true("blend curve is G2 at the boundary's end", g2.G2)
    checks.at_most("blend curvature difference at the joint, relative", g2.curvature_difference, 1e-9)
    faces = [cq_ext.to_cq(a), cq_ext.to_cq(b)]
    solid = cq.Workplane().add(faces).thickenSurface(THICKNESS).val()      # sewn, then offset
    checks.true("thickened panel is a valid solid", solid.isValid())
    estimate = (area(faces[0].wrapped) + area(faces[1].wrapped)) * THICKNESS
    checks.at_most("volume / (area x thickness) - 1 (thin-wall estimate)", abs(volume(solid.wrapped) / estimate - 1),
                   0.05)
    box = cq.Workplane().box(20, 20, 40).translate((60, 30, 0))
    cut = cq.Workplane().add(solid).cut(box).val()
    common = cq.Workplane().add(solid).intersect(box).val()
    checks.true("panel cut by a box is valid", cut.isValid())
    v = volume(solid.wrapped)
    checks.at_most("V(panel) vs V(cut) + V(panel ∩ box), relative",
                   abs(volume(cut.wrapped) + volume(common.wrapped) - v) / v, 1e-9)
    checks.verified([("patch A", a), ("patch B", b), ("boundary", edge), ("G2 blend", blend)])
    path = out / "panel.step"
    write_step([("panel", cut.wrapped), ("boundary", cq_ext.to_cq(edge).wrapped),
                ("G2 blend", cq_ext.to_cq(blend).wrapped)], path)
    checks.step_valid(path, 1)
    checks.finish()


if __name__ == "__main__":
    main()
