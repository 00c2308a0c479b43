"""closest_point on sliver faces with points slightly off them (issue 16): a bicubic
strip 0.1 x 10 mm and 0.01 x 10 mm (benchmarks.closest_sliver), points 1e-7, 1e-5 and
1e-3 of its size off. Face 16 of bug24595_281390.stp, such a strip, took 70x the time
for its mesh's single-precision vertices: the box bounds took the short direction for a
degenerate one (their scale floored at a quarter of the long direction's), the boxes
were halved across the strip and the cells cut it 8 times across. The answers were
right, only slow; so besides the oracle the tests count the (point, box) rows Newton
refines in the branch and bound."""
from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import least_squares

from benchmarks.closest_sliver import LENGTH, near_points, strip
from cagd import closest_point
from cagd.queries import closest as cl

POINTS = 40                  # per offset
SAMPLES = (33, 2001)         # brute-force grid (across, along)
AGREE_RTOL = 1e-9            # engine and oracle agree to this share of the distance ...
AGREE_SIZE_RTOL = 1e-13      # ... plus this share of the size (rounding near the surface)
ROWS_PER_POINT = 40          # Newton rows per point in the branch and bound, at most


def _oracle(S, X: np.ndarray) -> np.ndarray:
    """Brute force: the nearest of SAMPLES grid points of S, refined by scipy's
    least_squares (trust region reflective, in the domain) on S(u, v) - X."""
    (a, b), (c, d) = S.domain
    u, v = np.meshgrid(np.linspace(a, b, SAMPLES[0]), np.linspace(c, d, SAMPLES[1]), indexing="ij")
    uv = np.stack([u.ravel(), v.ravel()], axis=1)
    P = S(uv[:, 0], uv[:, 1])
    out = np.empty(len(X))
    for i, x in enumerate(X):
        j = int(np.argmin(((P - x) ** 2).sum(1)))
        fit = least_squares(lambda t: S(t[:1], t[1:])[0] - x, uv[j], bounds=([a, c], [b, d]), x_scale="jac",
                            xtol=1e-15, ftol=1e-15, gtol=1e-15, method="trf")
        out[i] = min(float(np.linalg.norm(fit.fun)), float(np.sqrt(((P[j] - x) ** 2).sum())))
    return out


@pytest.fixture(scope="module", params=[1e-2, 1e-3], ids=["1:100", "1:1000"])
def case(request):
    S = strip(request.param * LENGTH)
    X = np.concatenate([near_points(S, POINTS, rel, seed=k)[0] for k, rel in enumerate((1e-7, 1e-5, 1e-3))])
    return S, X, _oracle(S, X)


@pytest.fixture
def newton_rows(monkeypatch):
    """The (point, box) rows refined by Newton in branch and bound, counted."""
    count = [0]
    real = cl.Projector._newton_rows

    def spy(self, X, pid, *a, **kw):
        count[0] += len(pid)
        return real(self, X, pid, *a, **kw)

    monkeypatch.setattr(cl.Projector, "_newton_rows", spy)
    return count


def test_distances_agree_with_brute_force(case):
    """Oracle: dense sampling and a local least-squares fit from the nearest sample
    (scipy). The engine is never farther and agrees to 1e-9 of the distance."""
    S, X, oracle = case
    r = closest_point(S, X)
    slack = AGREE_RTOL * oracle + AGREE_SIZE_RTOL * S.size
    assert np.all(r.distances <= oracle + slack), np.max(r.distances - oracle)
    assert np.all(np.abs(r.distances - oracle) <= slack), np.max(np.abs(r.distances - oracle) / oracle)


def test_lower_bounds_certify_the_distance(case):
    """lower_bounds <= distances, non-zero where the distance is, and within the
    certificate's tolerance of it (1e-10 of d plus rounding: every box closed)."""
    S, X, oracle = case
    r = closest_point(S, X)
    assert np.all(r.lower_bounds <= r.distances)
    assert np.all(r.lower_bounds > 0)
    assert np.all(r.distances - r.lower_bounds <= AGREE_RTOL * r.distances + AGREE_SIZE_RTOL * S.size)


@pytest.mark.parametrize("many", [False, True], ids=["light", "default"])
def test_branch_and_bound_work_is_bounded(case, newton_rows, many):
    """Newton rows of the branch and bound per point stay below ROWS_PER_POINT (the
    light projector of a few points and the default one, of 1,024 points or more: the
    points repeated); the old bounds and splits needed 420-500 per point on the 1:1000
    strip (fails on the code before issue 16's fix), now ~8."""
    S, X, _ = case
    Q = np.tile(X, (int(np.ceil(cl.LIGHT_POINTS / len(X))), 1)) if many else X
    closest_point(S, Q)
    assert newton_rows[0] <= ROWS_PER_POINT * len(Q), newton_rows[0] / len(Q)
