"""cagd.occ.compat: the one module that knows the OCP line (OCCT 7.9 typedef names or
OCCT 8.0's OCP.collections). The OCCT 8.0 stage of `python3 dev.py test` sets
CAGD_EXPECT_OCP=8, so a stage that silently ran on the wrong OCCT fails here."""
import os

import numpy as np
import pytest

pytest.importorskip("OCP")
import OCP  # noqa: E402
from OCP.gp import gp_Pnt  # noqa: E402

import cagd  # noqa: E402
from cagd.occ import compat, from_occ, to_occ  # noqa: E402


def test_the_expected_ocp_line_is_running():
    assert compat.VERSION == OCP.__version__ and compat.MAJOR in (7, 8)
    expected = os.environ.get("CAGD_EXPECT_OCP")
    if expected:
        assert compat.MAJOR == int(expected), compat.VERSION


def test_arrays_hold_what_is_put_in():
    a = compat.Array1OfReal(1, 3)
    for i, x in enumerate((0.5, -2.0, 1e300), 1):
        a.SetValue(i, x)
    assert [a.Value(i) for i in (1, 2, 3)] == [0.5, -2.0, 1e300]
    net = compat.Array2OfPnt(1, 2, 1, 3)
    net.SetValue(2, 3, gp_Pnt(1.0, 2.0, 3.0))
    assert (net.Value(2, 3).X(), net.Value(2, 3).Z(), net.UpperRow(), net.UpperCol()) == (1.0, 3.0, 2, 3)
    ints = compat.Array1OfInteger(1, 2)
    ints.SetValue(2, 7)
    assert ints.Value(2) == 7


def test_casts_and_maps_work_on_a_face():
    from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE
    from OCP.TopExp import TopExp
    from cagd.occ import make_face, subshapes
    face = make_face(cagd.BezierSurface(np.random.default_rng(1).normal(size=(3, 4, 3))))
    assert compat.as_face(face).IsSame(face)
    owners = compat.IndexedDataMapOfShapeListOfShape()
    TopExp.MapShapesAndAncestors_s(face, TopAbs_EDGE, TopAbs_FACE, owners)
    assert owners.Extent() == 4 == len(subshapes(face, TopAbs_EDGE))


@pytest.mark.parametrize("weights", [None, [1.0, 2.0, 0.5, 1.0]])
@pytest.mark.parametrize("plane", [False, True])
def test_rational_curves_come_back_without_a_double_free(weights, plane):
    """OCCT 8's Weights() array was freed twice by OCP (free(): invalid pointer, the
    interpreter aborts): the bridge reads poles, weights and knots one by one."""
    c = cagd.BSplineCurve([[0, 0], [1, 2], [3, 1], [4, 0]], 3, weights=weights)
    if not plane:
        c = c.transformed(np.eye(3)[:, :2])
    back = from_occ(to_occ(c, plane=plane))
    t = np.linspace(0, 1, 7)
    assert np.abs(back(t) - c(t)).max() <= 1e-15 * 4
