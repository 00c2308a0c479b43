"""``cagd.occ.verify``: every family through every stage (engine vs its NURBS form,
vs OCCT's evaluator, vs the engine B-spline read back from OCCT, vs STEP and IGES
round trips), and the negative test: a periodic B-spline whose poles are rolled by
one (seam indexing off by one) must fail.

Bounds: the stages are all measured at ~1e-15 relative (files carry 17 significant
digits); the tests allow 1e-12 for every stage, also the files (the issue's floor is
1e-9 there), so a file writer that drops to OCCT's default 12 digits would fail.
"""
import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, note, settings
from hypothesis import strategies as st

pytest.importorskip("OCP")

import cagd.knots.vectors as kv  # noqa: E402
from cagd import (BezierCurve, BezierSurface, BezierTriangle, BSplineCurve, BSplineSurface, CagdError,  # noqa: E402
                  CoonsPatch, Surface, natural_cubic_spline, sphere)
from cagd.occ import STAGES, verify  # noqa: E402

from occ_strategies import (bezier_curves, bezier_surfaces_3d, bezier_triangles, bspline_surfaces_3d,  # noqa: E402
                            coons_patches, cubic_splines, hermite_curves, hermite_splines, kinked_curves,
                            kinked_surfaces, lofts, periodic_curves, polynomial_curves, quadrics,
                            revolved_surfaces)
from strategies import bspline_curves  # noqa: E402

EXACT = 1e-12      # to_nurbs, occt, from_occ (measured ~1e-15)
FILES = 1e-12      # step, iges: 17 significant digits (measured ~1e-15)
NORMALS = 1e-6     # unit normals next to (nearly) collapsed points, see check()
HIGH = 1e-11       # degree >= 7, times the weight ratio (measured 5.4e-12 at degree 10; 1.4e-11 with ratio 4)

FAST = settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow,
                                                                       HealthCheck.filter_too_much])


def collapsed_boundary(surface) -> bool:
    """A non-periodic boundary row/column of the NURBS net collapsed to one point. Generated nets
    with such rows (and zeros elsewhere) sometimes give no face back from STEP (see the report);
    spheres, revolutions and triangles, whose collapsed edges are tested by name, are fine."""
    s = surface.to_nurbs()
    P = s.control_points
    rows = ([] if s.periodic_u else [P[0], P[-1]]) + ([] if s.periodic_v else [P[:, 0], P[:, -1]])
    return any(np.ptp(r, axis=0).max() == 0 for r in rows)


def flat(surface) -> bool:
    """A surface collapsed to a point or a curve (S_u x S_v zero up to rounding on a grid).
    Generated nets can be such; they are not surfaces a CAD file can carry (the STEP/IGES
    readers drop or rebuild them) and their normals are rounding noise. Fixed tests below
    pin what verify does with them."""
    (a, b), (c, d) = surface.domain
    u, v = np.meshgrid(np.linspace(a, b, 7)[1:-1], np.linspace(c, d, 7)[1:-1], indexing="ij")
    D = surface.to_nurbs().derivatives(u.ravel(), v.ravel(), 1, 1)
    su, sv = D[1, 0], D[0, 1]
    if su.shape[-1] == 2:
        return False
    n = np.linalg.norm(np.cross(su, sv), axis=-1).max()
    return bool(n <= 1e-6 * np.linalg.norm(su, axis=-1).max() * np.linalg.norm(sv, axis=-1).max())


def check(obj, own_form: bool = True, files: bool = True):
    """verify() through every stage (or without the files); every quantity within the
    measured bounds."""
    if isinstance(obj, Surface) and flat(obj):
        assume(False)
    nurbs = obj.to_nurbs()
    if files and not isinstance(obj, Surface) and nurbs.weights is not None and not nurbs.periodic:
        # known STEP bug, pinned by test_closed_clamped_rational_curve_survives_step
        assume(not np.array_equal(nurbs.control_points[0], nurbs.control_points[-1]))
    try:
        note(f"to_nurbs().occ_form() = {nurbs.occ_form()!r}")
    except Exception:                # not inside a hypothesis test
        pass
    stages = STAGES if files else ("to_nurbs", "occt", "from_occ")
    report = verify(obj, stages=stages)
    expected = set(stages) if own_form else set(stages) - {"to_nurbs"}
    assert {s.stage for s in report.stages} == expected, str(report)
    for s in report.stages:
        bound = FILES if s.stage in ("step", "iges") else EXACT
        assert s.deviations, str(report)
        assert all(np.isfinite(v) for v in s.deviations.values()), str(report)
        # high degrees with cancellation: rounding ~ eps * max|P|, which is large against the size of
        # a curve that is small next to its control points (measured 1.2e-12 at degree 10, |P|/size ~ 20)
        P = np.abs(nurbs.control_points).max()
        degree = max(getattr(nurbs, "degree", 0), getattr(nurbs, "degree_u", 0), getattr(nurbs, "degree_v", 0))
        w = nurbs.weights
        ratio = 1.0 if w is None else float(w.max() / w.min())
        loose = (HIGH * ratio if degree >= 7 else bound) * max(1.0, P / report.size)
        assert max(v for k, v in s.deviations.items() if k != "normals") <= loose, str(report)
        # unit normals are ill-conditioned next to collapsed points (error ~ eps |S_u||S_v| / |S_u x S_v|):
        # measured up to 1.3e-7 on generated nets (degree 7, a nearly collapsed row), points <= 2.4e-14
        assert s.deviations.get("normals", 0.0) <= NORMALS, str(report)
        keys = {"points"} if s.note else ({"points", "d1", "d2"} | ({"normals"} if isinstance(obj, Surface) else set()))
        assert keys <= set(s.deviations), str(report)
    assert report.passed == all(s.max_deviation <= s.tolerance for s in report.stages)
    return report


# --- curves ------------------------------------------------------------------------------------
@FAST
@given(polynomial_curves())
def test_polynomial_curves(c):
    check(c)


@FAST
@given(st.one_of(hermite_curves(), hermite_splines()))
def test_hermite_curves(c):
    check(c)


@pytest.mark.parametrize("end", ["natural", "clamped", "periodic", "virtual"])
@settings(max_examples=8, deadline=None, suppress_health_check=[HealthCheck.filter_too_much])
@given(data=st.data())
def test_cubic_splines(end, data):
    c = data.draw(cubic_splines(end))
    r = check(c)
    assert c.to_nurbs().periodic == (end == "periodic")
    assert r.stage("occt").max_deviation <= EXACT


@FAST
@given(bezier_curves())
def test_bezier_curves_rational_or_not(c):
    check(c)


@FAST
@given(bspline_curves(kinds=("clamped",), max_degree=10, dims=(2, 3)))
def test_clamped_bspline_and_nurbs_curves(c):
    check(c, own_form=False)


# unclamped (floating / non-uniform) knot vectors lose the STEP round trip now and then
# (test_unclamped_curve_with_closed_polygon_survives_step and the surface analogue): the exact
# stages here; widen to the files when that is fixed
@FAST
@given(bspline_curves(kinds=("floating", "nonuniform"), max_degree=10, dims=(2, 3)))
def test_unclamped_bspline_and_nurbs_curves_without_files(c):
    check(c, own_form=False, files=False)


@FAST
@given(periodic_curves(uniform=True))
def test_periodic_uniform_curves(c):
    check(c, own_form=False)


@FAST
@given(periodic_curves(uniform=False, repeated_seam=True))
def test_periodic_curves_with_repeated_seam_knot(c):
    assert np.count_nonzero(c.knots == c.knots[0]) + np.count_nonzero(c.knots == c.knots[-1]) - 1 >= 2
    check(c, own_form=False)


@FAST
@given(periodic_curves(uniform=False))
def test_periodic_nonuniform_curves(c):
    check(c, own_form=False)


@FAST
@given(kinked_curves())
def test_curves_with_c0_kinks(c):
    check(c, own_form=False)


def test_degree_10_periodic_nurbs_curve():
    rng = np.random.default_rng(10)
    P = rng.normal(size=(13, 3))
    c = BSplineCurve(P, 10, np.cumsum(rng.uniform(0.1, 1, 14)), rng.uniform(0.5, 2, 13), periodic=True)
    check(c, own_form=False)


# --- surfaces ----------------------------------------------------------------------------------
# Non-periodic directions with unclamped knots (kinds "floating", "nonuniform") may lose the
# STEP/IGES round trip (see test_unclamped_surface_with_end_knot_of_multiplicity_degree):
# those go through the exact stages here, and through the files once that is fixed.
@FAST
@given(bspline_surfaces_3d())
def test_bspline_and_nurbs_surfaces_any_kind_without_files(s):
    check(s, own_form=False, files=False)


@FAST
@given(st.sampled_from(["clamped", "periodic"]), st.sampled_from(["clamped", "periodic"]), st.data())
def test_bspline_and_nurbs_surfaces(kind_u, kind_v, data):
    s = data.draw(bspline_surfaces_3d(kind_u, kind_v))
    assume(not collapsed_boundary(s))
    assume(not s.periodic_u or len(s.control_points) > max(s.degree_u, 2))
    assume(not s.periodic_v or s.control_points.shape[1] > max(s.degree_v, 2))
    check(s, own_form=False)


@pytest.mark.parametrize("kind_u, kind_v", [("periodic", "clamped"), ("clamped", "periodic"),
                                            ("periodic", "periodic")])
@settings(max_examples=8, deadline=None, suppress_health_check=[HealthCheck.filter_too_much])
@given(data=st.data())
def test_periodic_surfaces(kind_u, kind_v, data):
    s = data.draw(bspline_surfaces_3d(kind_u, kind_v))
    assume(not collapsed_boundary(s))
    # a periodic direction with 2 control points (or no more than its degree) folds onto itself;
    # IGES gives another surface (test_iges_periodic_direction_with_two_control_points)
    assume(not s.periodic_u or len(s.control_points) > max(s.degree_u, 2))
    assume(not s.periodic_v or s.control_points.shape[1] > max(s.degree_v, 2))
    assert (s.periodic_u, s.periodic_v) == (kind_u == "periodic", kind_v == "periodic")
    check(s, own_form=False)


@FAST
@given(bspline_surfaces_3d("clamped", "clamped", max_degree_u=10, max_degree_v=2))
def test_surfaces_of_high_degree_in_u(s):
    assume(not collapsed_boundary(s))
    check(s, own_form=False)


@FAST
@given(bspline_surfaces_3d("periodic", "clamped", max_degree_u=2, max_degree_v=10))
def test_surfaces_of_high_degree_in_v_periodic_in_u(s):
    assume(not collapsed_boundary(s))
    assume(len(s.control_points) > 2)
    check(s, own_form=False)


@FAST
@given(kinked_surfaces())
def test_surfaces_with_repeated_interior_knots(s):
    check(s, own_form=False)


@FAST
@given(bezier_surfaces_3d())
def test_bezier_surfaces_rational_or_not(s):
    check(s)


@FAST
@given(st.one_of(revolved_surfaces(), quadrics()))
def test_revolutions_spheres_tori_ellipsoid_patches(s):
    check(s, own_form=not isinstance(s, BSplineSurface))


@FAST
@given(coons_patches())
def test_coons_patches(s):
    check(s)


@FAST
@given(lofts())
def test_lofts(s):
    check(s, own_form=False)


@FAST
@given(bezier_triangles())
def test_bezier_triangles_through_collapsed_edge_form(t):
    r = check(t)
    assert "T(s, t(1-s))" in r.stage("to_nurbs").note


# --- the negative test: seam / pole indexing off by one ---------------------------------------
def _off_by(delta):
    real = kv.occ_knots

    def wrong(knots, periodic):
        distinct, mults, shift = real(knots, periodic)
        return distinct, mults, (shift + delta if periodic else shift)
    return wrong


PERIODIC_CURVE = BSplineCurve(np.array([[2, 0, 0], [1, 2, 1], [-1, 2, 0], [-2, 0, -1], [-1, -2, 0.5],
                                        [1, -2, 0.0]]), 3, [0, 0, 1, 2.5, 3, 4, 4], periodic=True)
PERIODIC_SURFACE = BSplineSurface(np.random.default_rng(4).normal(size=(6, 5, 3)), 3, 2,
                                  [0, 0, 1, 2.5, 3, 4, 4], [0, 0.3, 0.5, 1.2, 1.6, 2.0], periodic_u=True,
                                  periodic_v=True)


@pytest.mark.parametrize("obj", [PERIODIC_CURVE, PERIODIC_SURFACE], ids=["curve", "surface"])
def test_honest_periodic_objects_pass(obj):
    r = check(obj, own_form=False)
    assert r.stage("occt").max_deviation < 1e-13


@pytest.mark.parametrize("delta", [-1, 1])
@pytest.mark.parametrize("obj", [PERIODIC_CURVE, PERIODIC_SURFACE], ids=["curve", "surface"])
def test_pole_indexing_off_by_one_fails(obj, delta, monkeypatch):
    monkeypatch.setattr(kv, "occ_knots", _off_by(delta))
    r = verify(obj)
    assert not r.passed
    for stage in ("occt", "from_occ"):
        assert r.stage(stage).max_deviation >= 1e-3, str(r)
        assert r.stage(stage).deviations["points"] >= 1e-3, str(r)
        assert not r.stage(stage).passed
    # the files hold the clamped exchange form (knot insertion, no periodic pole indexing):
    # they stay right, and the report says where the fault is
    for stage in ("step", "iges"):
        assert r.stage(stage).passed, str(r)


@settings(max_examples=10, deadline=None)
@given(periodic_curves(), st.sampled_from([-1, 1]))
def test_pole_indexing_off_by_one_fails_for_generated_curves(c, delta):
    # a curve whose rolled control polygon is the same curve cannot be caught; skip those
    P = c.control_points
    if np.abs(np.roll(P, delta, axis=0) - P).max() <= 1e-3 * max(np.abs(P).max(), 1e-300):
        return
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(kv, "occ_knots", _off_by(delta))
        r = verify(c, stages=("occt",))
    assert not r.passed, str(r)


# --- report and arguments ----------------------------------------------------------------------
def test_report_lists_every_stage_and_renders():
    r = verify(BezierCurve([[0, 0], [1, 2], [3, 1]]), name="arc")
    assert [s.stage for s in r.stages] == list(STAGES)
    md = r.to_markdown()
    assert md.count("\n") == len(STAGES) + 1 and "| arc | occt |" in md and "**NO**" not in md
    assert "FAILED" not in str(r)
    assert set(r.max_deviation) == set(STAGES)


def test_stage_subset_and_kept_files(tmp_path):
    r = verify(sphere(1.5), name="ball", stages=("occt", "step"), workdir=tmp_path)
    assert [s.stage for s in r.stages] == ["occt", "step"]
    assert (tmp_path / "ball.step").is_file()
    assert not (tmp_path / "ball.igs").exists()


def test_a_tighter_tolerance_than_rounding_fails():
    r = verify(natural_cubic_spline([[0, 0, 0], [1, 2, 0], [3, 1, 1], [4, 3, 2]]), tol=0.0, file_tol=0.0,
               stages=("occt", "step"))
    # the comparison is not vacuous: OCCT's evaluation differs from the engine's by rounding
    assert r.stage("occt").max_deviation > 0 or r.stage("step").max_deviation > 0
    assert not r.passed


@pytest.mark.parametrize("bad, match", [
    (dict(obj=[1, 2, 3]), "obj"),
    (dict(obj=BezierCurve([[0, 0], [1, 1]]), stages=("occt", "stl")), "stages"),
])
def test_bad_arguments(bad, match):
    with pytest.raises(CagdError, match=match):
        verify(**bad)


def test_coons_and_triangle_examples():
    c0 = BezierCurve([[0, 0, 0], [1, 0, 1], [2, 0, 0]])
    c1 = BezierCurve([[0, 2, 0], [1, 2, -1], [2, 2, 0]])
    d0 = BezierCurve([[0, 0, 0], [0, 1, 1], [0, 2, 0]])
    d1 = BezierCurve([[2, 0, 0], [2, 1, 0.5], [2, 2, 0]], [1, 2, 1])
    check(CoonsPatch(c0, c1, d0, d1))
    check(BezierTriangle([[0, 0, 0], [1, 0, 1], [2, 0, 0], [0.5, 1, 0.5], [1.5, 1, 1], [1, 2, 0]],
                         [1, 2, 1, 1, 0.5, 1]))
    check(BezierSurface(np.random.default_rng(1).normal(size=(4, 3, 3)), np.linspace(0.5, 2, 12).reshape(4, 3)))


# --- bugs found by these tests, fixed (regression tests) ------------------------------------------
UNCLAMPED_NET = np.array([[[0.13, -0.13, 0.64], [0.1, -0.54, 0.36], [1.3, 0.95, -0.7], [-1.27, -0.62, 0.04]],
                          [[-2.33, -0.22, -1.25], [-0.73, -0.54, -0.32], [0.41, 1.04, -0.13], [1.37, -0.67, 0.35]],
                          [[0.9, 0.09, -0.74], [-0.92, -0.46, 0.22], [-1.01, -0.21, -0.16], [0.54, 0.21, 0.36]]])


def test_unclamped_surface_with_end_knot_of_multiplicity_degree():
    s = BSplineSurface(UNCLAMPED_NET, 2, 2, None, [0, 0, 1, 2, 2, 3, 3.0])
    assert verify(s.clamped(), stages=("step", "iges")).passed        # the same surface, clamped: fine
    r = verify(s, stages=("occt", "step", "iges"))
    assert r.stage("occt").passed
    assert r.stage("step").max_deviation <= FILES and r.stage("iges").max_deviation <= FILES, str(r)


def test_unclamped_curve_with_closed_polygon_survives_step(tmp_path):
    c = BSplineCurve([[0, 0, 0], [0, 1, 0], [0, 0, 0]], 2, [0, 1, 2, 3, 4, 5.0])
    assert verify(c, stages=("iges",)).passed
    from cagd.occ import read_step, write_step
    write_step([c], tmp_path / "c.step")
    assert len(read_step(tmp_path / "c.step")) == 1
    assert verify(c).passed


def test_verify_skips_normals_of_a_surface_collapsed_to_a_line():
    s = BSplineSurface(np.array([[[0, 0, 0], [1, 1.3, 0.7]], [[2, 2.6, 1.4], [3, 3.9, 2.1]]]), 1, 1)
    r = verify(s, stages=("occt", "from_occ"))
    assert r.stage("occt").deviations["points"] < 1e-14
    assert r.passed, str(r)


def test_verify_of_a_point_surface_raises_a_clear_error():
    # documented behaviour (see the report): a surface collapsed to a point gives no face in a file
    s = BSplineSurface(np.zeros((2, 2, 3)), 1, 1)
    assert verify(s, stages=("occt", "from_occ")).passed
    with pytest.raises(CagdError, match="no face was read back"):
        verify(s, stages=("step",))


def test_iges_periodic_direction_with_two_control_points():
    s = BSplineSurface(np.array([[[0, 0, 0], [0, 0, 0.0]], [[0, 0, 1], [0, 1, 0.0]]]), 2, 1,
                       [2.0, 2.4929887919453306, 2.4929887919453306], [0, 0, 1, 1.0], periodic_u=True)
    r = verify(s, stages=("occt", "step", "iges"))
    assert r.stage("occt").passed and r.stage("step").passed
    assert r.stage("iges").deviations["points"] <= FILES, str(r)


def test_closed_clamped_rational_curve_survives_step():
    P = np.array([[0.35, -0.82, 0.33], [1.2, 0.3, -0.5], [0.4, 1.6, 0.2], [-1.1, 0.7, 0.9], [-0.6, -0.9, -0.4],
                  [0.35, -0.82, 0.33]])
    c = BSplineCurve(P, 3, None, [1.0, 1.7, 0.6, 1.2, 0.8, 1.5])
    assert verify(c, stages=("iges",)).passed
    assert verify(BSplineCurve(P, 3), stages=("step",)).passed         # polynomial: fine
    r = verify(c, stages=("step",))
    assert r.passed, str(r)


# --- issue 14: extreme input is a CagdError naming the argument, never a raw exception ---
def test_domain_too_short_or_long_is_refused():
    """Knots 1e-300 apart (ZeroDivisionError before) and 1e300 apart (OverflowError):
    the derivative scales size / length^k vanish or overflow, so no relative deviation
    exists; a CagdError says why."""
    P = [[0, 0], [1, 1], [2, 0]]
    for h in (1e-300, 1e300):
        c = BSplineCurve(P, 2, [0, 0, 0, h, h, h])
        with pytest.raises(CagdError, match="obj: cannot be compared"):
            verify(c, stages=("occt",))


def test_four_dimensional_object_is_refused():
    """A 4-D object (ValueError from a broadcast before): OCCT has 2-D and 3-D geometry."""
    with pytest.raises(CagdError, match="obj: OCCT geometry is 2-D or 3-D, got a 4-D"):
        verify(BezierCurve([[0, 0, 0, 0], [1, 1, 1, 1]]))


def test_long_and_odd_names_make_valid_files(tmp_path):
    """A 255-character name (OSError: file name too long, before) and one with a
    non-ASCII letter: the file stem is cut to NAME_CHARS and ends in a hash of the whole
    name, so two long names differing at the end give two files. Longer names are refused
    as the files refuse them (MAX_NAME_LENGTH)."""
    from cagd._validate import MAX_NAME_LENGTH
    from cagd.occ.verify import NAME_CHARS, _safe
    c = BezierCurve([[0, 0, 0], [1, 2, 0], [3, 1, 1]])
    a, b = "x" * (MAX_NAME_LENGTH - 1) + "a", "x" * (MAX_NAME_LENGTH - 1) + "b"
    with pytest.raises(CagdError, match="at most 255"):
        verify(c, name=a + "z", stages=("step",), workdir=tmp_path)
    assert len(_safe(a)) == NAME_CHARS and _safe(a) != _safe(b)
    assert _safe("é") == "_"
    report = verify(c, name=a, stages=("step",), workdir=tmp_path)
    assert report.passed and report.name == a
    assert [p.name for p in tmp_path.iterdir()] == [_safe(a) + ".step"]
    with pytest.raises(CagdError, match="name: expected a string"):
        verify(c, name=3)
