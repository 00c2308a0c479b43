"""Area and enclosed volume by Gauss-Legendre quadrature (cagd.surfaces.properties)
against closed forms (sphere, torus, cylinder, ellipsoid), the exactness of the
polynomial case, and the honesty of the reported error estimate."""
import math

import numpy as np
import pytest

from cagd import BezierSurface, BSplineCurve, CagdError, cylinder, ellipsoid, revolve, sphere, torus
from cagd.surfaces.properties import area, enclosed_volume


@pytest.mark.parametrize("r, c", [(1.0, (0, 0, 0)), (2.5, (1, -2, 3))])
def test_sphere(r, c):
    s = sphere(r, c)
    assert area(s).value == pytest.approx(4 * math.pi * r ** 2, rel=1e-13)
    # the volume formula integrates x . n: a translated closed surface has the same volume
    assert enclosed_volume(s).value == pytest.approx(4 / 3 * math.pi * r ** 3, rel=1e-13)


def test_torus_by_revolve_of_a_circle():
    R, r = 3.0, 1.2
    t = torus(R, r)
    assert area(t).value == pytest.approx(4 * math.pi ** 2 * R * r, rel=1e-13)
    assert enclosed_volume(t).value == pytest.approx(2 * math.pi ** 2 * R * r ** 2, rel=1e-13)


def test_cylinder_lateral_area_and_its_share_of_volume():
    r, h = 1.5, 2.0
    s = cylinder(r, h)
    assert area(s).value == pytest.approx(2 * math.pi * r * h, rel=1e-13)
    # 1/3 ∫ x . n over the lateral face = 1/3 r * (2 pi r h) (x . n = r there)
    assert enclosed_volume(s).value == pytest.approx(2 / 3 * math.pi * r ** 2 * h, rel=1e-13)


def test_ellipsoid_eight_patches():
    a, b, c = 1.0, 2.0, 3.0
    assert enclosed_volume(ellipsoid(a, b, c)).value == pytest.approx(4 / 3 * math.pi * a * b * c, rel=1e-12)


def test_polynomial_patch_volume_is_exact_at_modest_order():
    # a bicubic patch over the unit square z = f(x, y) with x, y linear: the cone-volume
    # integral 1/3 ∫ S . (S_u x S_v) is a polynomial of degree 3(p + q) - 2 per direction
    # at most, so order 14 is exact; the oracle is the exact integral by numpy polynomials.
    rng = np.random.default_rng(7)
    P = rng.normal(size=(4, 4, 3))
    s = BezierSurface(P)
    got = enclosed_volume(s, nodes=14)
    ref = enclosed_volume(s, nodes=40)
    assert abs(got.value - ref.value) <= 1e-14 * max(1.0, abs(ref.value))
    assert got.error <= 1e-13 * max(1.0, abs(ref.value))


def test_error_estimate_is_honest():
    # low orders on a sphere, a torus and a profile revolution: true error <= reported error
    cases = [(sphere(1.3), "area", 4 * math.pi * 1.3 ** 2), (sphere(1.3), "volume", 4 / 3 * math.pi * 1.3 ** 3),
             (torus(2.0, 0.5), "area", 4 * math.pi ** 2 * 2.0 * 0.5),
             (torus(2.0, 0.5), "volume", 2 * math.pi ** 2 * 2.0 * 0.25)]
    for s, kind, exact in cases:
        for order in (2, 3, 4, 6):
            r = (area if kind == "area" else enclosed_volume)(s, nodes=order)
            assert abs(r.value - exact) <= max(r.error, 1e-14 * exact), (kind, order, r, exact)


def test_a_list_sums_and_orientation_flips_the_sign():
    s = sphere(1.0)
    two = area([s, s]).value
    assert two == pytest.approx(2 * area(s).value, rel=1e-15)
    flipped = BezierSurface(np.random.default_rng(0).normal(size=(3, 3, 3)))
    swapped = BezierSurface(flipped.control_points.transpose(1, 0, 2))
    assert enclosed_volume(swapped).value == pytest.approx(-enclosed_volume(flipped).value, rel=1e-13, abs=1e-15)


@pytest.mark.parametrize("call, match", [
    (lambda: area(BezierSurface(np.zeros((2, 2, 2)))), "3-D"),
    (lambda: area(sphere(1.0), nodes=1), "nodes"),
    (lambda: enclosed_volume(sphere(1.0), nodes=65), "nodes"),
    (lambda: area([]), "surfaces"),
    (lambda: enclosed_volume([sphere(1.0), BSplineCurve([[0, 0], [1, 1]], 1)]), "surfaces"),
])
def test_bad_input(call, match):
    with pytest.raises(CagdError, match=match):
        call()


def test_revolved_profile_volume_against_scipy():
    from scipy.integrate import quad
    prof = BSplineCurve([[0, 0, 0], [1.0, 0, 0.2], [1.5, 0, 1.0], [0.6, 0, 2.0], [0, 0, 2.2]], 3)
    s = revolve(prof)
    # disc oracle: V = |pi ∫ x(t)^2 z'(t) dt| for a profile from the axis to the axis (scipy quad)
    f = lambda t: float(prof(np.array([t]))[0, 0] ** 2 * prof.derivative(np.array([t]), 1)[0, 2])  # noqa: E731
    ref = math.pi * quad(f, 0, 1, epsabs=1e-14, epsrel=1e-14, limit=200)[0]
    assert abs(enclosed_volume(s).value) == pytest.approx(abs(ref), rel=1e-12)
