"""Global surface interpolation (Piegl & Tiller 9.2.5) against scipy's
make_interp_spline applied per direction, the averaged chord parameters written
out column by column, and polynomial reproduction."""
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.interpolate import make_interp_spline

from cagd import BSplineSurface, CagdError, parametrize
from cagd.knots import averaged
from cagd.surfaces.fitting import interpolate_surface, surface_parameters

SETTINGS = settings(max_examples=40, deadline=None)


@st.composite
def point_grids(draw, min_count=2, max_count=8, dims=(1, 3)):
    """A perturbed regular grid: Q_kl = (k, l, 0, ...) + noise in [-0.3, 0.3], so no
    two consecutive rows or columns coincide."""
    nu = draw(st.integers(min_count, max_count))
    nv = draw(st.integers(min_count, max_count))
    dim = draw(st.integers(*dims))
    noise = np.array(draw(st.lists(st.floats(-0.3, 0.3), min_size=nu * nv * dim, max_size=nu * nv * dim)))
    Q = noise.reshape(nu, nv, dim)
    Q[..., 0] += np.arange(nu)[:, None]
    if dim > 1:
        Q[..., 1] += np.arange(nv)[None, :]
    else:
        Q[..., 0] += 0.5 * np.arange(nv)[None, :]
    return Q


def degrees(data, Q):
    p = data.draw(st.integers(1, min(3, Q.shape[0] - 1)))
    q = data.draw(st.integers(1, min(3, Q.shape[1] - 1)))
    return p, q


@SETTINGS
@given(Q=point_grids(), data=st.data(), method=st.sampled_from(["chord", "centripetal", "uniform"]))
def test_interpolates_the_grid_and_matches_scipy(Q, data, method):
    p, q = degrees(data, Q)
    s = interpolate_surface(Q, p, q, method)
    assert isinstance(s, BSplineSurface) and (s.degree_u, s.degree_v) == (p, q)
    pu, pv = surface_parameters(Q, method)
    np.testing.assert_array_equal(s.knots_u, averaged(pu, p))
    np.testing.assert_array_equal(s.knots_v, averaged(pv, q))
    scale = np.abs(Q).max()
    assert np.abs(s(pu[:, None], pv[None, :]) - Q).max() <= 1e-11 * scale
    # scipy: interpolation along axis 0 with the same parameters and knots, then along axis 1
    R = make_interp_spline(pu, Q, k=p, t=s.knots_u, axis=0).c
    P = np.moveaxis(make_interp_spline(pv, R, k=q, t=s.knots_v, axis=1).c, 0, 1)   # scipy keeps axis first
    assert np.abs(s.control_points - P).max() <= 1e-10 * max(scale, np.abs(P).max())


@SETTINGS
@given(Q=point_grids(dims=(2, 3)), method=st.sampled_from(["chord", "centripetal"]))
def test_parameters_are_the_column_averages(Q, method):
    """ubar_k = (1/(m+1)) sum_l u_k^l with u^l the curve parameters of column l (eq. 9.5/9.6)."""
    pu, pv = surface_parameters(Q, method)
    ref_u = np.mean([parametrize(Q[:, l], method) for l in range(Q.shape[1])], axis=0)
    ref_v = np.mean([parametrize(Q[k], method) for k in range(Q.shape[0])], axis=0)
    np.testing.assert_allclose(pu, ref_u, rtol=1e-14, atol=1e-15)
    np.testing.assert_allclose(pv, ref_v, rtol=1e-14, atol=1e-15)
    assert pu[0] == 0.0 and pu[-1] == 1.0 and pv[0] == 0.0 and pv[-1] == 1.0


@pytest.mark.parametrize("p, q", [(3, 3), (2, 3), (3, 1), (1, 2)])
def test_reproduces_polynomials(p, q):
    """A polynomial of degree (p, q) lies in the spline space, so interpolating its
    values at the parameters gives it back everywhere."""
    rng = np.random.default_rng(p * 10 + q)
    C = rng.normal(size=(p + 1, q + 1, 3))
    f = lambda u, v: np.einsum("...a,...b,abd->...d", u[..., None] ** np.arange(p + 1),  # noqa: E731
                               v[..., None] ** np.arange(q + 1), C)
    pu, pv = np.linspace(0, 1, 7), np.sort(np.concatenate([[0, 1], rng.uniform(0, 1, 6)]))
    U, V = np.meshgrid(pu, pv, indexing="ij")
    s = interpolate_surface(f(U, V), p, q, parameters=(pu, pv))
    t = np.linspace(0, 1, 23)
    Ut, Vt = np.meshgrid(t, t, indexing="ij")
    np.testing.assert_allclose(s(Ut, Vt), f(Ut, Vt), atol=1e-12 * np.abs(C).sum())


def test_degree_one_control_points_are_the_points():
    """Degree (1, 1) with averaged knots = the parameters: the bilinear pieces through
    the grid, the control net is the grid itself."""
    rng = np.random.default_rng(1)
    Q = rng.normal(size=(4, 5, 3))
    s = interpolate_surface(Q, 1, 1)
    np.testing.assert_allclose(s.control_points, Q, atol=1e-14)


def test_collapsed_row_is_left_out_of_the_average():
    """A grid whose first column collapses to one point (a pole): the chord
    parameters in u come from the other columns only (Piegl & Tiller 9.2.5)."""
    rng = np.random.default_rng(2)
    Q = rng.normal(size=(5, 4, 3)) + np.arange(5)[:, None, None]
    Q[:, 0] = [1.0, 2.0, 3.0]
    pu, _ = surface_parameters(Q)
    ref = np.mean([parametrize(Q[:, l]) for l in range(1, 4)], axis=0)
    np.testing.assert_allclose(pu, ref, rtol=1e-14)
    s = interpolate_surface(Q, 3, 2)
    pu, pv = surface_parameters(Q)
    np.testing.assert_allclose(s(pu[:, None], pv[None, :]), Q, atol=1e-12)


def test_errors():
    Q = np.random.default_rng(0).normal(size=(4, 4, 3))
    with pytest.raises(CagdError, match="points"):
        interpolate_surface(np.zeros((4, 3)))
    with pytest.raises(CagdError, match="points"):
        interpolate_surface(np.zeros((1, 4, 3)))
    with pytest.raises(CagdError, match="points"):
        interpolate_surface(np.full((4, 4, 3), np.nan))
    with pytest.raises(CagdError, match="degree_u"):
        interpolate_surface(Q, 4, 3)
    with pytest.raises(CagdError, match="degree_v"):
        interpolate_surface(Q, 3, 0)
    with pytest.raises(CagdError, match="parameters"):
        interpolate_surface(Q, parameters="arc")
    with pytest.raises(CagdError, match="parameters"):
        interpolate_surface(Q, parameters=np.linspace(0, 1, 4))
    with pytest.raises(CagdError, match="parameters"):
        interpolate_surface(Q, parameters=(np.linspace(0, 1, 4), np.linspace(0, 1, 5)))
    with pytest.raises(CagdError, match="parameters"):
        interpolate_surface(Q, parameters=(np.linspace(0, 1, 4), [0, 0.5, 0.5, 1]))
    with pytest.raises(CagdError, match="points"):
        interpolate_surface(np.zeros((4, 4, 3)))                  # every column of zero length
    dup = Q.copy()
    dup[2] = dup[1]                                               # two rows coincide everywhere
    with pytest.raises(CagdError, match="points"):
        interpolate_surface(dup)


def _wavy_grid(nu, nv, seed):
    rng = np.random.default_rng(seed)
    u = np.sort(np.concatenate([[0, 1], rng.random(nu - 2)])) * 4
    v = np.sort(np.concatenate([[0, 1], rng.random(nv - 2)])) * 3
    U, V = np.meshgrid(u, v, indexing="ij")
    return np.stack([U, V, np.sin(3 * U) * np.cos(2 * V) + 0.01 * rng.standard_normal(U.shape)], axis=-1)


@pytest.mark.parametrize("p, q", [(3, 3), (2, 5)])
def test_200_by_150_net_matches_scipy(p, q):
    """Banded solves in both directions (issue 14) against scipy's make_interp_spline
    along each axis with the same parameters and knots."""
    Q = _wavy_grid(200, 150, p + q)
    s = interpolate_surface(Q, p, q)
    pu, pv = surface_parameters(Q)
    R = make_interp_spline(pu, Q, k=p, t=s.knots_u, axis=0).c
    P = np.moveaxis(make_interp_spline(pv, R, k=q, t=s.knots_v, axis=1).c, 0, 1)
    scale = np.abs(Q).max()
    assert np.abs(s.control_points - P).max() <= 1e-10 * max(scale, np.abs(P).max())
    assert np.abs(s(pu[::7, None], pv[None, ::5]) - Q[::7, ::5]).max() <= 1e-11 * scale


def test_big_grid_memory_is_linear():
    """A 600 x 500 grid (7.2 MB): the peak stays within a few copies of the grid (the
    wide-curve route held ~18 copies: 433 MB for a 1000 x 1000 grid)."""
    import tracemalloc
    Q = _wavy_grid(600, 500, 3)
    tracemalloc.start()
    try:
        s = interpolate_surface(Q)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 8 * Q.nbytes
    pu, pv = surface_parameters(Q)
    assert np.abs(s(pu[::37, None], pv[None, ::41]) - Q[::37, ::41]).max() <= 1e-11 * np.abs(Q).max()


def test_degree_limits_name_the_argument():
    from cagd import MAX_DEGREE
    Q = _wavy_grid(MAX_DEGREE + 3, 4, 0)
    with pytest.raises(CagdError, match="degree_u: .*MAX_DEGREE"):
        interpolate_surface(Q, MAX_DEGREE + 1, 3)
    with pytest.raises(CagdError, match="degree_v"):
        interpolate_surface(Q, 3, 4)
