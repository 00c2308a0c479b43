"""A vase profile through measured points, as an exact NURBS ready for OCCT.

Builds a natural cubic spline (chord-length parameters) through the measured
points, joins a G2 Bezier lip to its top, checks the joint, converts the whole
profile to one NURBS curve and prints what OCCT's Geom_BSplineCurve would get.
Writes a PNG of the profile with its curvature comb.

Run: python examples/curve_profile.py [OUTDIR]
"""
import sys
from pathlib import Path

import numpy as np

import cagd
from cagd.plotting import plot_curves

MEASURED = np.array([[30.0, 0.0], [34.0, 12.0], [40.0, 30.0], [36.0, 52.0], [24.0, 70.0], [20.0, 84.0],
                     [22.0, 95.0]])


def main(out_dir: Path) -> int:
    body = cagd.natural_cubic_spline(MEASURED, "natural", "chord")
    body_nurbs = body.to_nurbs()
    # the lip: a cubic Bezier leaving the body's last span with G2 continuity
    last = body_nurbs.to_bezier()[-1]
    lip = cagd.join(last, [[34.0, 108.0]], "G2", alpha=2.0, beta=0.0)
    report = cagd.continuity(body_nurbs, lip)
    profile = cagd.CompositeCurve([body_nurbs, lip])
    nurbs = profile.to_nurbs()
    t = np.linspace(*profile.domain, 2001)
    deviation = float(np.abs(nurbs(t) - profile(t)).max())
    form = nurbs.occ_form()
    print(f"profile: {len(MEASURED)} measured points, spline + G2 lip -> {nurbs!r}")
    print(f"joint: {report}")
    print(f"NURBS vs pieces: max deviation {deviation:.2e} mm over {len(t)} samples")
    print(f"OCCT form: {len(form.poles)} poles, degree {form.degree}, knots {np.round(form.knots, 4).tolist()}, "
          f"multiplicities {form.multiplicities.tolist()}")
    print(f"length {profile.arc_length():.6f} mm")
    png = plot_curves(out_dir / "curve_profile.png", "vase profile: natural spline + G2 lip", [body, lip],
                      [lip.control_points], points=MEASURED)
    print(f"wrote {png}")
    ok = report.G2 and deviation < 1e-9 * 100
    print("checks passed" if ok else "CHECK FAILED")
    return 0 if ok else 1


if __name__ == "__main__":
    raise SystemExit(main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("out/examples")))
