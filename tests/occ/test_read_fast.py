"""Reading speed (issue 15, "Speed"): the shortcuts of the reading path give what the
plain computation gives, bit for bit.

- validation: ``_Flattened.check_nesting`` / ``check_crossings`` and the hierarchical
  ``LoopCheck`` (all holes at once, pieces bisected only where needed,
  only pairs of different curves in overlapping boxes) against the loop-by-loop,
  pair-by-pair versions they replaced (kept here as the oracle), on random loops that
  cross, nest, touch and lie apart, bounded and periodic;
- batched Bezier nets (``bezier_spans_many``) against ``bezier_spans`` curve by curve;
- ``hermite_fit`` (each breakpoint evaluated once) against the level-by-level version
  it replaced; ``_crossings_of`` (all bisections at once) against one at a time;
  ``_end`` against evaluation;
- ``trimmed_from_face`` with the control-hull shortcuts against the sampled path
  (EVAL_MARGIN = inf forces it), on synthetic trimmed faces and on the real files;
- the crash probe in a forked copy and in a child interpreter both turn OCCT's crash
  into a CagdError.
"""
import json
import re
import subprocess
import sys
import textwrap

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

pytest.importorskip("OCP")

from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE  # noqa: E402

import cagd  # noqa: E402
from cagd import BSplineCurve, BSplineSurface, CagdError, TrimmedSurface  # noqa: E402
from cagd.curves.bezier_spans import bezier_spans, bezier_spans_many  # noqa: E402
from cagd.occ import from_occ, make_face  # noqa: E402
import cagd.occ.trim as trim  # noqa: E402
from cagd.occ.files import _shapes  # noqa: E402
from cagd.occ.shapes import subshapes  # noqa: E402
from cagd.surfaces import trimmed as tr  # noqa: E402

from corpus import CAD as REAL  # noqa: E402
W = np.sqrt(0.5)


# --- the replaced implementations (the oracle) -------------------------------------------------
def old_check_nesting(self) -> None:
    for i in range(1, self.loop_count):
        p = self.A[np.flatnonzero(self.loop_of == i)[0]].copy()
        p[0], p[1] = self._window(p[:1], 0)[0], self._window(p[1:], 1)[0]
        for k in range(self.loop_count):
            if k == i:
                continue
            sel = self.loop_of == k
            w = int(tr._crossings(p[0], p[1], self.A[sel], self.B[sel]).sum())
            d = float(tr._segment_distance(p, self.A[sel], self.B[sel]).min())
            if d <= float(self.bound[sel].max()) + self.band:
                continue
            if k == 0 and w == 0:
                raise CagdError(f"loops[{i}]: the hole lies outside the outer loop loops[0]")
            if k > 0 and w != 0:
                raise CagdError(f"loops[{i}]: the hole lies inside the hole loops[{k}]")


def old_check_crossings(self) -> None:
    s = self.strip_segments
    counts = np.diff(self.strip_start)
    strip = np.repeat(np.arange(len(counts)), counts)
    position = np.arange(len(s)) - self.strip_start[strip]
    partners = counts[strip] - 1 - position
    total = int(partners.sum())
    if total > 4 * tr.CHUNK:
        keep = np.zeros(len(s), dtype=bool)
        keep[np.linspace(0, len(s) - 1, max(1, int(len(s) * 4 * tr.CHUNK / total))).astype(int)] = True
        partners = np.where(keep, partners, 0)
        total = int(partners.sum())
    if not total:
        return
    first = np.repeat(np.arange(len(s)), partners)
    second = first + 1 + (np.arange(total) - np.repeat(np.cumsum(partners) - partners, partners))
    i, j = s[first], s[second]
    same = (self.loop_of[i] == self.loop_of[j]) & (self.position[i] == self.position[j])
    keep = ~same & self.original[i] & self.original[j]
    i, j = i[keep], j[keep]
    shared = (np.all(self.A[i] == self.B[j], axis=1) | np.all(self.B[i] == self.A[j], axis=1) |
              np.all(self.A[i] == self.A[j], axis=1) | np.all(self.B[i] == self.B[j], axis=1))
    i, j = i[~shared], j[~shared]
    if not len(i):
        return
    a, b, c, d = self.A[i], self.B[i], self.A[j], self.B[j]

    def orient(p, q, r):
        return (q[:, 0] - p[:, 0]) * (r[:, 1] - p[:, 1]) - (q[:, 1] - p[:, 1]) * (r[:, 0] - p[:, 0])

    eps = tr.CROSSING_TOL * self.scale * self.scale
    o1, o2, o3, o4 = orient(a, b, c), orient(a, b, d), orient(c, d, a), orient(c, d, b)
    hit = (((o1 > eps) & (o2 < -eps)) | ((o1 < -eps) & (o2 > eps))) & \
          (((o3 > eps) & (o4 < -eps)) | ((o3 < -eps) & (o4 > eps)))
    if hit.any():
        hit &= ~old_at_joint(self, i, j, c, d, o1, o2)
    if hit.any():      # the crossing first in (loop, curve) order (the order of the new check's message)
        from cagd.surfaces._trim_check import first_pair
        k = first_pair(self.loop_of[i], self.curve_of[i], self.loop_of[j], self.curve_of[j], hit)
        x, y = i[k], j[k]
        where = tuple(0.5 * (a[k] + b[k]))
        raise CagdError(f"loops: {old_name(self, x)} crosses {old_name(self, y)} near (u, v) = "
                        f"({where[0]:.9g}, {where[1]:.9g})")


def old_at_joint(self, i: np.ndarray, j: np.ndarray, c: np.ndarray, d: np.ndarray, o1: np.ndarray,
              o2: np.ndarray) -> np.ndarray:
    """Crossings of consecutive curves of a loop within tr.JOINT_TOL of their common
    point (files' pcurves overshoot their vertices a little)."""
    li, lj = self.loop_of[i], self.loop_of[j]
    n = np.array(self.loop_len)[li]
    step = np.mod(self.position[j] - self.position[i], n)
    adjacent = (li == lj) & ((step == 1) | (step == n - 1))
    with np.errstate(divide="ignore", invalid="ignore"):
        x = c + (o1 / (o1 - o2))[:, None] * (d - c)       # where chord j (c -> d) meets chord i
    near = np.zeros(len(i), dtype=bool)
    for P in (self.curve_start, self.curve_end):
        for idx in (i, j):
            near |= np.linalg.norm(x - P[idx], axis=1) <= tr.JOINT_TOL * self.scale
    return adjacent & near


def old_name(self, seg: int) -> str:
    j = int(self.curve_of[seg])
    loop = int(self.loop_of[seg])
    return f"loops[{loop}][{j}]" if j >= 0 else f"the gap after a curve of loops[{loop}]"


def old_hermite_fit(f, df, breaks, tol, ddf=None):
    lo, hi = breaks[:-1].astype(float), breaks[1:].astype(float)
    checks = np.array([0.1, 0.3, 0.5, 0.7, 0.9])
    p = 3 if ddf is None else 5
    from math import comb
    bern = np.array([[comb(p, k) * s ** k * (1 - s) ** (p - k) for k in range(p + 1)] for s in checks])
    done_lo, done_hi = [], []
    error, ok = 0.0, True
    while len(lo):
        nets = tr._hermite_nets(lo, hi, f, df, ddf)
        approx = np.einsum("sk,nkd->nsd", bern, nets)
        t = lo[:, None] + (hi - lo)[:, None] * checks[None, :]
        exact = f(t.ravel()).reshape(approx.shape)
        err = np.linalg.norm(exact - approx, axis=-1).max(axis=1)
        good = err <= tol
        if sum([len(x) for x in done_lo]) + 2 * int(np.count_nonzero(~good)) + int(np.count_nonzero(good)) \
                > tr.MAX_FIT_PIECES:
            good[:] = True
            ok = False
        error = max(error, float(err[good].max(initial=0.0)))
        done_lo.append(lo[good])
        done_hi.append(hi[good])
        mid = 0.5 * (lo + hi)
        lo, hi = np.concatenate([lo[~good], mid[~good]]), np.concatenate([mid[~good], hi[~good]])
    lo, hi = np.concatenate(done_lo), np.concatenate(done_hi)
    order = np.argsort(lo)
    lo, hi = lo[order], hi[order]
    nets = tr._hermite_nets(lo, hi, f, df, ddf)
    P = np.concatenate([nets[:, :-1].reshape(-1, nets.shape[2]), nets[-1:, -1]])
    knots = np.concatenate([np.full(p + 1, lo[0]), np.repeat(lo[1:], p), np.full(p + 1, hi[-1])])
    return BSplineCurve(P, p, knots), error, ok


def old_crossings_of(c, k, knots):
    a, b = c.domain
    t = np.linspace(a, b, 257)
    x = c(t)[:, k]
    out = []
    for K in knots:
        s = np.sign(x - K)
        for i in np.flatnonzero(s[:-1] * s[1:] < 0):
            lo, hi = t[i], t[i + 1]
            flo = x[i] - K
            for _ in range(60):
                mid = 0.5 * (lo + hi)
                fm = float(c(mid)[k]) - K
                if (fm < 0) == (flo < 0):
                    lo, flo = mid, fm
                else:
                    hi = mid
            out.append(0.5 * (lo + hi))
    return np.array(out)


def outcome(check, flat):
    """The error message, with a crossing's pair of curves as a set and without its
    location (which of the crossing chords a check reports first is its own order)."""
    try:
        check(flat)
    except CagdError as exc:
        m = re.fullmatch(r"loops: (.*) crosses (.*) near \(u, v\) = .*", str(exc))
        return ("crossing", frozenset(m.groups())) if m else str(exc)
    return None


def same_curve(a: BSplineCurve, b: BSplineCurve) -> bool:
    return (a.degree == b.degree and a.periodic == b.periodic and np.array_equal(a.control_points, b.control_points)
            and np.array_equal(a.knots, b.knots)
            and (a.weights is None) == (b.weights is None)
            and (a.weights is None or np.array_equal(a.weights, b.weights)))


def same_trimmed(a, b) -> bool:
    if isinstance(a, TrimmedSurface) != isinstance(b, TrimmedSurface):
        return False
    if not isinstance(a, TrimmedSurface):
        return np.array_equal(a.control_points, b.control_points)
    return (a.tol == b.tol and a.reoriented == b.reoriented and len(a.loops) == len(b.loops)
            and all(len(x) == len(y) and all(same_curve(c, d) for c, d in zip(x, y)) for x, y in zip(a.loops, b.loops))
            and np.array_equal(a.surface.control_points, b.surface.control_points))


# --- synthetic loops ----------------------------------------------------------------------------
def circle(centre, r, clockwise=False):
    U = np.array([[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1], [1, 0]], float)
    c = BSplineCurve(U * r + np.asarray(centre, float), 2, [0, 0, 0, .25, .25, .5, .5, .75, .75, 1, 1, 1],
                     [1, W, 1, W, 1, W, 1, W, 1])
    return c.reversed() if clockwise else c


def polygon(points):
    P = np.asarray(points, float)
    return [BSplineCurve(np.stack([P[i], P[(i + 1) % len(P)]]), 1) for i in range(len(P))]


def wavy(centre, r, wave, count, seed):
    rng = np.random.default_rng(seed)
    out = []
    edges = np.linspace(0, 2 * np.pi, count + 1)
    for a, b in zip(edges[:-1], edges[1:]):
        phi = np.linspace(a, b, 5)
        rr = r * (1 + wave * np.sin(3 * phi + rng.random()))
        out.append(BSplineCurve(np.stack([centre[0] + rr * np.cos(phi), centre[1] + rr * np.sin(phi)], 1), 3))
    # close exactly: each curve starts where the previous ends
    fixed = [out[0]]
    for c in out[1:]:
        P = c.control_points.copy()
        P[0] = fixed[-1].control_points[-1]
        fixed.append(c.with_control_points(P))
    P = fixed[0].control_points.copy()
    P[0] = fixed[-1].control_points[-1]
    fixed[0] = fixed[0].with_control_points(P)
    return fixed


loop_shapes = st.sampled_from(["circle", "square", "wavy"])
# distinct holes: coincident curves overlap along their whole length, where every check can
# only sample its (unbounded many) pairs of touching chords, each its own sample
holes = st.lists(st.tuples(st.floats(-0.2, 1.2), st.floats(-0.2, 1.2), st.floats(0.01, 0.5), loop_shapes,
                           st.integers(0, 10 ** 6)), min_size=1, max_size=7, unique_by=lambda h: h[:4])


def hole(x, y, r, shape, seed):
    if shape == "circle":
        return [circle((x, y), r, clockwise=True)]
    if shape == "square":
        return polygon([(x - r, y - r), (x - r, y + r), (x + r, y + r), (x + r, y - r)])
    return [c.reversed() for c in wavy((x, y), r, 0.3, 3 + seed % 5, seed)[::-1]]


def new_check_nesting(flat):
    """The hierarchical nesting check (cagd.surfaces._trim_check) on the flattened loops'
    curves, as TrimmedSurface runs it where no loop spans a period."""
    from cagd.surfaces._chords import closed_chains
    from cagd.surfaces._trim_check import LoopCheck
    check = LoopCheck(closed_chains(flat.loops), flat.scale, tr.FLATTEN_TOL * flat.scale, tr.MAX_BISECTIONS)
    check.check_nesting(flat.band, lambda P: P, tr.CHUNK)


def polyline_cross(c1, c2, n=1500):
    """Brute force: do polylines of 1500 points on c1 and c2 properly cross?"""
    P = c1(np.linspace(*c1.domain, n))
    Q = c2(np.linspace(*c2.domain, n))
    a, b = P[:-1, None], P[1:, None]
    c, d = Q[None, :-1], Q[None, 1:]

    def orient(p, q, r):
        return (q[..., 0] - p[..., 0]) * (r[..., 1] - p[..., 1]) - (q[..., 1] - p[..., 1]) * (r[..., 0] - p[..., 0])
    o1, o2, o3, o4 = orient(a, b, c), orient(a, b, d), orient(c, d, a), orient(c, d, b)
    return bool(np.any((o1 * o2 < 0) & (o3 * o4 < 0)))


def same_crossing_outcome(flat):
    """The new crossing check against the old one: the same verdict; where they name
    different pairs (the old check samples its pairs beyond 4 CHUNK), the new pair's
    polylines cross (brute force)."""
    new, old = outcome(tr._Flattened.check_crossings, flat), outcome(old_check_crossings, flat)
    if new == old:
        return True
    if not (isinstance(new, tuple) and isinstance(old, tuple)):
        return False
    curves = []
    for name in new[1]:
        m = re.fullmatch(r"loops\[(\d+)\]\[(\d+)\]", name)
        if m is None:
            return False
        curves.append(flat.loops[int(m.group(1))][int(m.group(2))])
    return polyline_cross(*curves)


def flattened(outer, inner, periods=(0.0, 0.0)):
    loops = tuple(tuple(lp) for lp in [outer] + inner)
    return tr._Flattened(loops, 1e-9, periods)


@settings(max_examples=50, deadline=None)
@given(holes, st.sampled_from(["square", "wavy"]))
def test_nesting_and_crossing_checks_equal_the_loop_by_loop_ones(spec, outer_shape):
    outer = polygon([(0, 0), (1, 0), (1, 1), (0, 1)]) if outer_shape == "square" else wavy((0.5, 0.5), 0.45, 0.2, 6, 7)
    flat = flattened(outer, [hole(*h) for h in spec])
    assert outcome(tr._Flattened.check_nesting, flat) == outcome(old_check_nesting, flat)
    assert outcome(new_check_nesting, flat) == outcome(old_check_nesting, flat)
    assert same_crossing_outcome(flat)


@settings(max_examples=25, deadline=None)
@given(holes)
def test_the_checks_equal_the_old_ones_on_a_periodic_band(spec):
    """An outer loop spanning the whole period in u: holes have copies a period apart."""
    outer = polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    flat = flattened(outer, [hole(*h) for h in spec], periods=(1.0, 0.0))
    assert outcome(tr._Flattened.check_nesting, flat) == outcome(old_check_nesting, flat)
    assert same_crossing_outcome(flat)


def test_the_checks_see_what_they_must():
    """The oracle comparison is not vacuous: crossing, outside and nested holes are found."""
    outer = polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    for inner, words in (([hole(0.9, 0.5, 0.2, "circle", 0)], "crosses"),
                         ([hole(1.5, 0.5, 0.1, "circle", 0)], "outside the outer loop"),
                         ([hole(0.5, 0.5, 0.3, "square", 0), hole(0.5, 0.5, 0.1, "circle", 0)], "inside the hole")):
        flat = flattened(outer, inner)
        got = outcome(tr._Flattened.check_crossings, flat) or outcome(tr._Flattened.check_nesting, flat)
        assert outcome(new_check_nesting, flat) == outcome(tr._Flattened.check_nesting, flat)
        assert got is not None and (words == "crosses" if isinstance(got, tuple) else words in got)


# --- batched Bezier nets, hermite_fit, crossings, ends ---------------------------------------------
curves = st.tuples(st.integers(1, 6), st.integers(0, 12), st.booleans(), st.integers(0, 10 ** 6), st.integers(2, 3))


def random_curve(degree, extra, rational, seed, dim):
    rng = np.random.default_rng(seed)
    n = degree + 1 + extra
    inner = np.sort(rng.choice(np.linspace(0.05, 0.95, 7), extra)) if extra else np.empty(0)
    knots = np.concatenate([np.zeros(degree + 1), inner, np.ones(degree + 1)])
    values, mults = np.unique(knots, return_counts=True)
    if np.any(mults[1:-1] > degree):
        knots = np.concatenate([np.zeros(degree + 1), np.linspace(0, 1, extra + 2)[1:-1], np.ones(degree + 1)])
    w = rng.uniform(0.2, 3.0, n) if rational else None
    return BSplineCurve(rng.normal(size=(n, dim)) * 10 ** rng.uniform(-3, 3), degree, knots * rng.uniform(0.1, 9) - 2,
                        w)


@settings(max_examples=60, deadline=None)
@given(st.lists(curves, min_size=1, max_size=6), st.integers(1, 6))
def test_batched_bezier_nets_equal_one_curve_at_a_time(specs, degree):
    cs = [random_curve(degree, e, r, s, d) for _, e, r, s, d in specs]
    by_dim = {}
    for c in cs:
        by_dim.setdefault(c._hom.shape[1], []).append(c)
    for group in by_dim.values():
        if group[0]._hom.shape[1] > degree + 1:
            continue
        got = bezier_spans_many([c._u for c in group], degree, [c._hom for c in group])
        for c, (breaks, nets) in zip(group, got):
            want = bezier_spans(c._u, c.degree, c._hom)
            assert np.array_equal(breaks, want[0]) and np.array_equal(nets, want[1])


def test_primed_nets_are_what_bezier_net_gives():
    cs = [random_curve(3, 4, True, 5, 2), random_curve(3, 2, False, 6, 2), random_curve(2, 0, True, 7, 2)]
    want = [c.bezier_net() for c in cs]
    fresh = [BSplineCurve(c.control_points, c.degree, c.knots, c.weights) for c in cs]
    cagd.curves.bspline.prime_bezier_nets(fresh)
    for c, (b, n) in zip(fresh, want):
        got = c.bezier_net()
        assert np.array_equal(got[0], b) and np.array_equal(got[1], n)


@settings(max_examples=40, deadline=None)
@given(curves, st.floats(1e-13, 1e-6))
def test_hermite_fit_equals_the_level_by_level_fit(spec, tol):
    degree, extra, rational, seed, _ = spec
    c = random_curve(degree, extra, rational, seed, 2)
    scale = float(np.abs(c.control_points).max())
    mu = trim._ArcMap(np.linspace(-2.0, 2.0, 5), float("inf"))

    def f(t):
        uv = c(t) / scale
        return np.stack([mu(uv[:, 0]), uv[:, 1]], axis=1)

    def df(t):
        d = c.derivatives(t, 1) / scale
        return np.stack([mu.derivative(d[0, :, 0]) * d[1, :, 0], d[1, :, 1]], axis=1)

    def ddf(t):
        d = c.derivatives(t, 2) / scale
        return np.stack([mu.second_derivative(d[0, :, 0]) * d[1, :, 0] ** 2 + mu.derivative(d[0, :, 0]) * d[2, :, 0],
                         d[2, :, 1]], axis=1)

    a, b = c.domain
    breaks = np.unique(np.concatenate([[a], c._breaks_within(a, b), [b]]))
    for second in (None, ddf):
        new, e1, ok1 = tr.hermite_fit(f, df, breaks, tol, second)
        old, e2, ok2 = old_hermite_fit(f, df, breaks, tol, second)
        assert same_curve(new, old) and e1 == e2 and ok1 == ok2


@settings(max_examples=40, deadline=None)
@given(curves)
def test_crossings_of_equal_one_bisection_at_a_time(spec):
    degree, extra, rational, seed, _ = spec
    c = random_curve(degree, extra, rational, seed, 2)
    x = c.control_points[:, 0]
    knots = np.linspace(x.min(), x.max(), 6)[1:-1]
    assert np.array_equal(trim._crossings_of(c, 0, knots), old_crossings_of(c, 0, knots))


@settings(max_examples=40, deadline=None)
@given(curves, st.booleans())
def test_end_is_the_evaluated_end(spec, periodic):
    degree, extra, rational, seed, dim = spec
    c = random_curve(degree, extra, rational, seed, dim)
    if periodic:
        c = BSplineCurve(c.control_points, c.degree, None, c.weights, periodic=True)
    for side in (0, 1):
        assert np.array_equal(tr._end(c, side), c(c.domain[side]))


# --- trimmed_from_face: shortcuts against the sampled path -------------------------------------------
def read_both(face, monkeypatch):
    fast = from_occ(face)
    with monkeypatch.context() as m:
        m.setattr(trim, "EVAL_MARGIN", float("inf"))       # no hull decides: the samples, always
        slow = from_occ(face)
    return fast, slow


def synthetic_faces():
    x = np.linspace(0, 1, 5)
    X, Y = np.meshgrid(x, x, indexing="ij")
    S = BSplineSurface(np.stack([X, Y, 0.3 * np.sin(2 * X) * Y], axis=-1), 3, 3)
    out = []
    out.append(TrimmedSurface(S, [[circle((0.5, 0.5), 0.4)]]))                                  # one loop
    out.append(TrimmedSurface(S, [polygon([(0, 0), (1, 0), (1, 1), (0, 1)]),
                                  [circle((0.3, 0.3), 0.1, True)], [circle((0.7, 0.6), 0.15, True)]]))
    out.append(TrimmedSurface(S, [wavy((0.5, 0.5), 0.45, 0.1, 5, 3), [circle((0.5, 0.5), 0.2, True)]]))
    out.append(TrimmedSurface(S, [[circle((0.5, 0.5), 0.45)], [circle((0.5, 0.5), 0.1, True)]]))  # outer: 1 curve
    out.append(TrimmedSurface(S, [polygon([(0, 0), (1, 0), (1, 1)])]))                          # touches the box
    return out


@pytest.mark.parametrize("k", range(5))
def test_trimmed_faces_read_the_same_with_and_without_the_shortcuts(k, monkeypatch):
    ts = synthetic_faces()[k]
    face = make_face(ts)
    fast, slow = read_both(face, monkeypatch)
    assert same_trimmed(fast, slow)
    reversed_face = face.Reversed()
    fast, slow = read_both(reversed_face, monkeypatch)
    assert same_trimmed(fast, slow)


def test_a_read_face_rebuilds_the_same_through_the_validating_constructor():
    """What the reading path builds is what TrimmedSurface(surface, loops, tol) builds
    (validation included), down to the classification chords."""
    for ts in synthetic_faces():
        got = from_occ(make_face(ts))
        if not isinstance(got, TrimmedSurface):
            continue
        again = TrimmedSurface(got.surface, got.loops, tol=got.tol)
        assert same_trimmed(got, again)
        a, b = got._flattened(), again._flattened()
        for name in ("A", "B", "bound", "owner", "loop_of", "curve_of", "position", "strip_segments", "curve_start"):
            assert np.array_equal(getattr(a, name), getattr(b, name)), name


REAL_FILES = ["step/trj4_k1_geo-ac-214.stp", "step/boxed_sphere.step", "iges/bug33327.igs", "step/wing_fuselage.step",
              "step/SampleCrankshaft4A.stp"]


@pytest.mark.parametrize("name", REAL_FILES)
def test_real_faces_read_the_same_with_and_without_the_shortcuts(name, monkeypatch):
    path = REAL / name
    if not path.is_file():
        pytest.skip("real CAD files not present")
    named, _ = _shapes(path, "iges" if name.startswith("iges") else "step")
    faces = [f for _, s in named for f in subshapes(s, TopAbs_FACE)]
    step = max(1, len(faces) // 40)                        # at most about 40 faces per file
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for f in faces[::step]:
            try:
                fast, slow = read_both(f, monkeypatch)
            except CagdError:
                continue
            assert same_trimmed(fast, slow)


# --- the shared-edge cache ------------------------------------------------------------------------
def same_edges(a, b) -> bool:
    if (a.edges is None) != (b.edges is None):
        return False
    for ra, rb in zip(a.edges or (), b.edges or ()):
        for ea, eb in zip(ra, rb):
            if (ea is None) != (eb is None):
                return False
            if ea is not None:
                t = np.linspace(*ea.domain, 33)
                if ea.domain != eb.domain or not np.allclose(ea(t), eb(t), rtol=0, atol=1e-12):
                    return False
    return True


@pytest.mark.parametrize("name, sewn", [("step/boxed_sphere.step", True), ("step/trj4_k1_geo-ac-214.stp", False)])
def test_shared_edges_convert_once_and_give_the_same_edges(name, sewn, monkeypatch):
    """Within shared_edges() an edge of two faces is converted once (counted), and every
    face's edge curves are those read face by face without the cache (to 1e-12)."""
    import warnings
    path = REAL / name
    if not path.is_file():
        pytest.skip("real CAD files not present")
    named, _ = _shapes(path, "step")
    faces = [f for _, s in named for f in subshapes(s, TopAbs_FACE)][:60]
    import cagd.occ.convert as convert
    original = convert.from_occ
    edges = []

    def counting(shape, *args, **kwargs):
        if shape.ShapeType() == TopAbs_EDGE:
            edges.append(shape)
        return original(shape, *args, **kwargs)
    monkeypatch.setattr(convert, "from_occ", counting)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        plain = [original(f) for f in faces]
        converted_plain = len(edges)
        distinct = len({hash(e) for e in edges})
        edges.clear()
        with trim.shared_edges():
            cached = [original(f) for f in faces]
    trimmed = [(a, b) for a, b in zip(plain, cached) if isinstance(a, TrimmedSurface)]
    assert trimmed and all(same_edges(a, b) and same_trimmed(a, b) for a, b in trimmed)
    assert len(edges) == distinct                        # each edge once
    assert (distinct < converted_plain) == sewn          # a sewn shell shares its edges; trj4's faces do not


# --- the crash probe ---------------------------------------------------------------------------------
PROBE = """
    import json, sys, warnings
    import cagd.occ.files as files
    from cagd import CagdError
    if sys.argv[2] == "no-fork":
        files._can_fork = lambda: False
    try:
        files.read_iges(sys.argv[1])
        print(json.dumps(["read", ""]))
    except CagdError as exc:
        print(json.dumps(["CagdError", str(exc)]))
"""


@pytest.mark.parametrize("how", ["fork", "no-fork"])
def test_the_crash_probe_turns_a_crash_into_a_cagd_error_both_ways(how, tmp_path):
    src = REAL / "iges" / "OCC8842_cylinder_Ideas.igs"
    if not src.is_file():
        pytest.skip("real CAD files not present")
    text = src.read_text()
    bad = text.replace("510,25,1,1,29;    ", "510,25,111,29;    ", 1)      # a face claiming 111 loops
    assert bad != text
    (tmp_path / "face.igs").write_text(bad)
    run = subprocess.run([sys.executable, "-c", textwrap.dedent(PROBE), str(tmp_path / "face.igs"), how],
                         capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr[-1000:]
    kind, message = json.loads(run.stdout.strip().splitlines()[-1])
    assert kind == "CagdError" and "crashes on (signal" in message and "type 510" in message
