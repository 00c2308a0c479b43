"""Example 1 (CadQuery): a vase. A natural cubic spline through measured profile
points (seed 000, 5.1.2), revolved about the axis, closed by planar caps and
shelled with CadQuery's own ``shell``.

Checks: the closed solid is valid; its volume equals pi * integral of x(t)^2 z'(t)
dt (Pappus; Gauss-Legendre on each spline span) by OCCT (cagd.occ.volume: 5e-11,
OCCT's adaptive integration on its own surface of revolution) and by the engine's
quadrature of the NURBS revolution (1e-15); the shelled vase is valid and lighter
by about (inner area x wall); the profile's exact NURBS revolution survives OCCT, STEP and IGES (cagd.occ.verify).

Run: python examples/cq_vase.py [OUTDIR]
"""
import numpy as np
import cadquery as cq

import cagd
import cq_ext  # noqa: F401  (registers the Workplane methods)
from cagd.occ import area, volume, write_step
from cagd.surfaces.properties import enclosed_volume
from _common import Checks, output_folder

# measured outer profile (radius x, height z) in mm, bottom to top
POINTS = np.array([[30.0, 0.0], [36.0, 14.0], [40.0, 32.0], [35.0, 55.0], [25.0, 72.0], [21.0, 86.0],
                   [24.0, 100.0]])
WALL = 2.0


def pappus_volume(profile: cagd.Curve) -> float:
    """V = pi * integral x^2 z' dt (the profile sweeps from the bottom to the top cap),
    by Gauss-Legendre on each span of the spline (exact: x^2 z' is a polynomial of
    degree 8 on a span)."""
    x, w = np.polynomial.legendre.leggauss(8)
    breaks = np.unique(profile.to_nurbs().knots)
    t = ((breaks[:-1, None] + breaks[1:, None]) / 2 + (breaks[1:, None] - breaks[:-1, None]) / 2 * x).ravel()
    wt = ((breaks[1:, None] - breaks[:-1, None]) / 2 * w).ravel()
    d = profile.derivatives(t, 1)
    return float(np.pi * np.sum(wt * d[0][:, 0] ** 2 * d[1][:, 1]))


def main() -> None:
    out = output_folder("out/examples")
    checks = Checks("vase: natural spline profile, revolved, capped and shelled")
    profile = cagd.natural_cubic_spline(POINTS, "natural", "chord")
    # Workplane("XZ"): local (x, y) are global (x, z); revolve about the local y axis = global z
    body = cq.Workplane("XZ").revolveSurface(profile, close=True)
    solid = body.val()
    checks.true("closed vase is a valid solid (isValid)", solid.isValid())
    exact = pappus_volume(profile)
    checks.at_most("closed vase volume (OCCT) vs Pappus, relative", abs(volume(solid.wrapped) - exact) / exact, 1e-9)
    vase = body.faces(">Z").shell(-WALL)
    shelled = vase.val()
    checks.true("shelled vase is a valid solid", shelled.isValid())
    v_shell = volume(shelled.wrapped)
    wall_area = area(solid.wrapped) - np.pi * POINTS[-1, 0] ** 2          # all but the removed top cap
    ratio = v_shell / (wall_area * WALL)
    checks.at_most("shell volume / (wall area x wall) - 1 (thin-wall estimate)", abs(ratio - 1.0), 0.05)
    surface = cagd.revolve(profile.transformed(np.array([[1.0, 0.0], [0.0, 0.0], [0.0, 1.0]])))
    # engine quadrature: the NURBS surface, plus the top cap's flux (1/3) z * area (the bottom's is 0)
    engine = abs(enclosed_volume(surface).value) + np.pi * POINTS[-1, 0] ** 2 * POINTS[-1, 1] / 3.0
    checks.at_most("engine quadrature (NURBS surface + caps) vs Pappus, relative", abs(engine - exact) / exact,
                   1e-12)
    checks.verified([("vase surface (NURBS)", surface), ("profile", profile)])
    path = out / "vase.step"
    write_step([("vase", shelled.wrapped)], path)
    checks.step_valid(path, 1)
    print(f"wrote {path}: volume {v_shell:.1f} mm^3 of material, outer volume {exact:.1f} mm^3")
    checks.finish()


if __name__ == "__main__":
    main()
