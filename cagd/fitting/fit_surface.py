"""A B-spline surface within a tolerance of a grid of points, with the control-point counts
chosen (issue 17; seed 002 names the task, the method is the standard literature).

The grid Q (m, n, d) gets averaged parameters per direction (Piegl & Tiller 9.2.5,
:func:`cagd.surfaces.surface_parameters`), and a tensor-product least-squares fit with the
corner rows held: along u for every column, then along v (the tensor least squares
separates; Piegl & Tiller 9.4.3), by dense per-direction operators built once per knot
vector (:mod:`cagd.fitting.separable`: a solve is four matrix products). The knots of
each direction are placed as in :func:`cagd.fit_curve` (de Boor's equidistribution of
the error), each direction by its own error: the residuals of fitting the grid's
columns along u alone (the u knots' part of the error) and its rows along v alone (the
v knots' part). Rounds grow the span counts until every grid point is within tol at its
parameters (an upper bound of its distance), then shrink both counts while they stay
within (:func:`_shrunk`), then trim one span at a time, the direction and error source
whose candidate misses least (:func:`_trimmed`; a candidate that misses gets its knots
re-equidistributed by its own misses at the same counts, :func:`_polished`), then one
span fewer at a time with the knots of both directions moved by free-knot least squares
(:mod:`cagd.fitting.grid_knots`; on the 100 x 100 anchor of ``benchmarks/fitting.py``,
degree 3: 12 x 12 -> 11 x 10 poles at tol 0.01, 18 x 17 -> 17 x 15 at 0.001). Near the
grid's size the equidistributed knots are moved towards the sites' own where the sites
would not determine the poles or the least squares would amplify the data
(:func:`cagd.fitting.separable.interlaced`; at the cap: interpolation). The
reported largest error is the certified closest-point distance (the closest-point
machinery's light tier, :func:`_certified`), certified for the points that can decide it
(:func:`_measured`); the others get their local feet. The separable fit holds the
boundary curves: its boundary rows of control points are the 1-D fits of the grid's
boundary rows (``boundary="G0"``). ``degree="auto"`` keeps the degree of AUTO_DEGREES with
the fewest control points (a grid fit of a later degree with no fewer is not measured).

Scattered points (:func:`fit_scattered`) get their parameters by projection onto a base
(plane, least-squares quadric, or a given surface), one least-squares solve over all
control points per knot vector (normal equations per knot cell), the same grow (at most
SCATTER_GROWTH per round) / shrink / trim, and parameter correction by re-projection
onto the fit (local feet, Piegl & Tiller 9.4.1) where a candidate misses tol narrowly
(:func:`_corrected`).

Periodic directions, tangent planes held along edges and thin-plate smoothing need the
least squares over the whole net (:mod:`cagd.fitting.surface_net`); ``minimax`` fits a
noisy grid with knots placed by the shape of its least-squares fit and Lawson's
reweighted least squares (:func:`_minimax_stage`).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping, Optional, Tuple, Union

import numpy as np
from numpy.typing import ArrayLike

from .. import _checks
from .._results import ReadOnlyArrays
from ..errors import CagdError
from ..surfaces.base import Surface
from ..surfaces.bspline import BSplineSurface
from .fit import (CORRECTION_GAIN, GROW_TARGET, MAX_FIT_ROUNDS, MAX_GROWTH, MAX_SHRINK, _knots, _redistributed,
                  _span_errors, _worth, stalled)
from .grid_knots import fewer_spans
from .interpolation import _frame
from .rebuild import _pair
from .separable import SeparableGrid, ends_held_operator, interlaced


#: the share of tol each direction's own residual is grown to (the two add up to at most
#: about sqrt(2) of it where they are independent)
DIRECTION_SHARE = 1.0 / np.sqrt(2.0)


@dataclass(frozen=True)
class SurfaceFit(ReadOnlyArrays):
    """The result of :func:`fit_surface`: ``surface``; ``max_error`` the largest certified
    distance of the points from it; ``rms_error`` the root-mean-square of their distances
    (certified near the largest, elsewhere at the local feet); ``params`` (m, n, 2) (or
    (N, 2)) the feet; ``rounds``; ``converged`` (max_error <= tol) and ``message``."""
    surface: BSplineSurface
    max_error: float
    rms_error: float
    params: np.ndarray
    rounds: int
    converged: bool
    message: str


def _degrees_and_caps(degree, caps, default: Tuple[int, int]) -> Tuple[int, int, int, int]:
    """(pu, pv, cap_u, cap_v) checked: a degree or a pair, a cap pair or None (the default
    size, at least degree + 1)."""
    pu, pv = _pair(degree, "degree")
    pu, pv = _checks.degree(pu, "degree", 1), _checks.degree(pv, "degree", 1)
    if caps is None:
        return pu, pv, max(default[0], pu + 1), max(default[1], pv + 1)
    if not isinstance(caps, (tuple, list)) or len(caps) != 2:
        raise CagdError(f"max_control_points: expected a pair (count_u, count_v), got {caps!r}")
    return (pu, pv, _checks.integer(caps[0], "max_control_points", pu + 1),
            _checks.integer(caps[1], "max_control_points", pv + 1))


def _boundary_rows(Q: np.ndarray, u: np.ndarray, v: np.ndarray, U: np.ndarray, V: np.ndarray, pu: int, pv: int
                   ) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The four boundary rows of control points: 1-D least-squares fits (ends held, P&T
    9.4.1) of the grid's boundary rows to the surface's knots: u = 0 and u = 1 along v
    (cv, d), v = 0 and v = 1 along u (cu, d), by the separable fit's operators
    (:func:`cagd.fitting.separable.ends_held_operator`: the minimum-norm least squares
    where a count at the grid's size leaves a pole without a site; the ends exact)."""
    Fu, Fv = ends_held_operator(U, pu, u)[1], ends_held_operator(V, pv, v)[1]
    return Fv @ Q[0], Fv @ Q[-1], Fu @ Q[:, 0], Fu @ Q[:, -1]


def _grown(breaks: np.ndarray, t: np.ndarray, e: np.ndarray, tol: float, p: int, most: int,
           interlace: str = "") -> np.ndarray:
    """The next breakpoints of one direction from its residuals e (per parameter t): the
    same breakpoints where every span is within GROW_TARGET * tol, else more."""
    E = _span_errors(breaks, t, e)
    if E.max(initial=0.0) <= GROW_TARGET * tol:
        return breaks
    s = len(breaks) - 1
    c = _worth(E, GROW_TARGET * tol, p)
    count = int(np.clip(max(np.ceil(c.sum()), s + np.count_nonzero(E > tol)), s + 1, min(most, MAX_GROWTH * s + 1)))
    return _sited(_redistributed(breaks, c, count), t, p, interlace) if count > s else breaks


def _placed(breaks: np.ndarray, t: np.ndarray, e: np.ndarray, tol: float, p: int, count: int,
            interlace: str = "") -> np.ndarray:
    """``count`` spans equidistributing the misses e (per parameter t) of the spans of
    ``breaks`` (de Boor; :func:`cagd.fitting.fit._worth`), through :func:`_sited`."""
    return _sited(_redistributed(breaks, _worth(_span_errors(breaks, t, e), tol, p), count), t, p, interlace)


def _sited(breaks: np.ndarray, t: np.ndarray, p: int, interlace: str) -> np.ndarray:
    """The breakpoints as they are, or with ``interlace`` ("clamped": a grid's separable
    fit, which has no regulariser; "periodic": a grid's periodic direction) kept
    determined and conditioned by the sites t (:func:`cagd.fitting.separable.interlaced`)."""
    return interlaced(breaks, t, p, interlace == "periodic") if interlace else breaks


#: the boundary conditions of a grid fit: free, or the boundary curves held (G0)
BOUNDARIES = (None, "G0")
#: one-span trimming steps after the shrink at most (each: two separable solves)
MAX_TRIM_STEPS = 24
#: a grid's trimming candidates that miss get at most this many re-equidistribution passes
#: (:func:`_polished`; the 100 x 100 anchor: 13 x 12 -> 12 x 12 poles at tol 0.01,
#: 19 x 18 -> 19 x 17 at 0.001, 20 more separable solves)
POLISH_PASSES = 6


def _shrunk(best, solve, sources, tol: float, degrees: Tuple[int, int], most: int,
            interlace: Tuple[str, str] = ("", "")):
    """Shrinking: both directions to MAX_SHRINK of their spans at once, the breakpoints
    redistributed by the first error source (as :func:`_trimmed`), while the fit stays
    within tol, at most ``most`` steps. Returns (best, steps)."""
    steps = 0
    while best[3] <= tol and steps < most and (len(best[1]) > 2 or len(best[2]) > 2):
        steps += 1
        new = []
        for axis, pairs in enumerate(sources(best)):
            breaks, (t, e) = best[1 + axis], pairs[0]
            s = len(breaks) - 1
            new.append(_placed(breaks, t, e, tol, degrees[axis], max(1, int(MAX_SHRINK * s)), interlace[axis])
                       if s > 1 else breaks)
        S2, miss2, *extra = solve(*new)
        if miss2.max() > tol:
            break
        best = (S2, new[0], new[1], float(miss2.max()), miss2, *extra)
    return best, steps


def _trimmed(best, solve, sources, tol: float, degrees: Tuple[int, int],
             polish=None, interlace: Tuple[str, str] = ("", "")):
    """Greedy knot trimming (knot placement that follows the residual): while the fit
    ``best`` = (surface, breaks_u, breaks_v, largest miss, misses) is within tol, try one
    span fewer along u and along v, the breakpoints redistributed by each error source
    (``sources(best)``: per direction, pairs (parameters, misses); de Boor's
    equidistribution, as the rounds), each candidate solved by ``solve(bu, bv)`` ->
    (surface, misses); keep the one with the smallest largest miss while it stays within
    tol, at most MAX_TRIM_STEPS steps. Grids: when every candidate misses, each
    direction's best one gets :func:`_polished` (``polish`` = (passes, misses), see
    there). Returns (best, steps)."""
    steps = 0
    while best[3] <= tol and steps < MAX_TRIM_STEPS:
        steps += 1
        cands = []
        for axis, pairs in enumerate(sources(best)):
            breaks = best[1 + axis]
            if len(breaks) <= 2:
                continue
            for t, e in pairs:
                fewer = _placed(breaks, t, e, tol, degrees[axis], len(breaks) - 2, interlace[axis])
                bu, bv = (fewer, best[2]) if axis == 0 else (best[1], fewer)
                S2, miss2, *extra = solve(bu, bv)
                cands.append((axis, (S2, bu, bv, float(miss2.max()), miss2, *extra)))
        if not cands:
            break
        top = min((c for _, c in cands), key=lambda c: c[3])
        if top[3] > tol and polish:
            firsts = [min((c for a, c in cands if a == axis), key=lambda c: c[3], default=None) for axis in (0, 1)]
            found = [_polished(c, solve, polish, tol, degrees, interlace) for c in firsts if c is not None]
            top = min((c for c in found if c is not None), key=lambda c: c[3], default=top)
        if top[3] > tol:
            break
        best = top
    return best, steps


def _polished(fit, solve, polish, tol: float, degrees: Tuple[int, int], interlace: Tuple[str, str] = ("", "")):
    """The knots of a fit that misses tol moved at the same span counts: both directions'
    breakpoints redistributed by the fit's own misses (``polish`` = (passes, misses):
    ``misses(fit)`` per direction a pair (parameters, misses), e.g. a grid's largest per
    row and per column; de Boor's equidistribution repeated, towards equal span errors),
    at most ``passes`` solves, stopping when the largest miss grows; the first fit within
    tol, or None."""
    passes, misses = polish
    for _ in range(passes):
        new = [_placed(fit[1 + axis], t, e, tol, degrees[axis], len(fit[1 + axis]) - 1, interlace[axis])
               for axis, (t, e) in enumerate(misses(fit))]
        S2, miss2, *extra = solve(*new)
        if float(miss2.max()) > fit[3]:
            return None
        fit = (S2, new[0], new[1], float(miss2.max()), miss2, *extra)
        if fit[3] <= tol:
            return fit
    return None


def fit_surface(points: ArrayLike, tol: float, degree: Union[int, Tuple[int, int], str] = 3,
                parameters: str = "centripetal", max_control_points: Optional[Tuple[int, int]] = None,
                base: Union[str, Surface, None] = None, boundary: Optional[str] = None, *,
                periodic: Union[bool, str, Tuple[bool, bool], None] = None,
                tangent_edges: Optional[Mapping[str, object]] = None, smoothing: float = 0.0,
                minimax: bool = False, tune_knots: bool = True) -> SurfaceFit:
    """A clamped B-spline surface on [0, 1]^2 within ``tol`` (a distance) of every point of
    the grid ``points`` (m, n, d), m, n >= 2, corner points held, with few control
    points; see the module docstring. Scattered points (N, 3) are parametrised by their
    projection onto a base surface and corrected by re-projection (:func:`fit_scattered`).

    Args:
        points: (m, n, d) grid, rows along u; or (N, 3) scattered points.
        tol: the largest allowed distance of a point from the surface (> 0).
        degree: per direction, or a pair (degree_u, degree_v); or "auto": the fit of
            each degree of AUTO_DEGREES (both directions; a grid's at most m - 1 and
            n - 1) with the fewest control points (the lower degree on a tie; the
            smallest error when none is within tol).
        parameters: a rule of :data:`cagd.fitting.PARAMETERS` (averaged over the grid lines).
        max_control_points: a cap (count_u, count_v) (default: the grid's size; a
            periodic direction at most its distinct rows).
        base: scattered points only: "plane" (default), "quadric" or a cagd Surface to
            project them onto for their first parameters.
        boundary: grids only: None or "G0". The separable fit already makes the four
            boundary rows of control points the 1-D least-squares fits (ends held) of the
            grid's boundary rows to the surface's knots; "G0" sets them from those fits
            in model units once more (exact, not through the normalised frame).
        periodic: grids only: the closed directions, (periodic_u, periodic_v), or "u", "v",
            "uv" (True: both). A periodic direction is fitted with periodic knots
            (:func:`cagd.knots.periodic_extend`), so the seam is C^(degree-1); the grid's
            rows (columns) run once round the loop, a last row within tol of the first is
            taken for the first again. At least 2 degree + 1 control points there.
        tangent_edges: grids only: the edges ("u0", "u1", "v0", "v1"; u0 is u = 0, running
            in v) whose tangent plane is held (G1), each mapped to its cross-boundary data:
            a neighbouring BSplineSurface (its opposite edge: "u1" for "u0", ...), a pair
            (neighbour, its edge name), or "grid" (the grid's own boundary row and its
            one-sided cross derivatives). A neighbour's edge is held exactly (G0: the
            fit's boundary row of control points is the neighbour's edge row, its knots
            inserted, its degree raised to the fit's) and the fit's next row is the edge
            row plus alpha times the neighbour's last difference row (one alpha > 0 per
            edge, by least squares), so the tangent planes agree along the whole edge
            (Farin, Curves and Surfaces for CAGD, 16.5, the G1 condition on the nets);
            the grid's parameters along that edge are the feet of its boundary row on the
            neighbour's edge. Opposite edges only (two adjacent ones would both own the
            corner's twist pole); not with a periodic direction.
        smoothing: grids only: weight of the thin-plate energy int int |S_uu|^2 +
            2 |S_uv|^2 + |S_vv|^2 against the mean squared miss, in the grid's frame
            scaled to the unit ball over [0, 1]^2 (Dierckx's smoothing norm; see
            :mod:`cagd.fitting.surface_net`); > 0 keeps a noisy grid's fit from chasing
            the noise (it lowers the bending energy; it does not lower the pole count
            where the noise takes most of tol: see ``minimax``).
        minimax: grids only, with none of periodic, tangent_edges, smoothing, boundary:
            after the least-squares fit, fits towards the best uniform approximation on
            knots placed by the shape of the least-squares fit (Lawson's reweighted least
            squares, :func:`_minimax_solve`): a noisy grid's largest miss is set by a few
            noise peaks, which a minimax fit meets with fewer poles on knots that follow
            the shape (:func:`_minimax_stage`); the least-squares fit with its knots tuned
            (:mod:`cagd.fitting.grid_knots`) where that needs no more control points. The
            corner points are not held then.
        tune_knots: the separable grid fit (a grid without periodic, tangent_edges or
            smoothing) ends with fewer spans, both directions' knots moved by free-knot
            least squares (:mod:`cagd.fitting.grid_knots`); False skips that stage: on the
            100 x 100 anchor of ``benchmarks/fitting.py`` at tol 0.01, 12 x 12 control
            points instead of 11 x 10 in 0.09 s instead of 0.26 s (CPU; at tol 0.001 18 x 17
            instead of 17 x 15 in 0.08 s instead of 0.40 s). The other fits do not tune
            their knots.

    Returns:
        SurfaceFit; ``converged`` False (with the achieved error) when the cap or
        MAX_FIT_ROUNDS is reached first, or (scattered points) the growth stalls
        (:func:`cagd.fitting.fit.stalled`: tol below the points' noise).

    Raises:
        CagdError: not a finite (m >= 2, n >= 2, d) grid, bad tol, degree or parameters;
            bad periodic, tangent_edges (unknown or adjacent edges, a neighbour that is
            not a polynomial BSplineSurface or whose edge does not run along the grid's
            boundary row, of a higher degree than the fit), smoothing or minimax, or one
            of them given with scattered points or an option it cannot go with.
    """
    args = dict(points=points, tol=tol, parameters=parameters, max_control_points=max_control_points, base=base,
                boundary=boundary, periodic=periodic, tangent_edges=tangent_edges, smoothing=smoothing,
                minimax=minimax, tune_knots=tune_knots)
    if isinstance(degree, str):
        return _auto_degree(degree, args)
    fit = _fit_surface(degree, args)
    assert fit is not None                      # no beat: always a fit
    return fit


def _fit_surface(degree, args: dict, beat: Optional[int] = None) -> Optional[SurfaceFit]:
    """:func:`fit_surface` of the degree (a degree or a pair) with the other arguments
    ``args``; with ``beat``, None instead of a separable grid fit of at least that many
    control points, unmeasured (degree="auto" keeps the first converged fit with the
    fewest: such a fit cannot win, and its measure is most of its time after the knots'
    tuning)."""
    points, tol, parameters, max_control_points, base, boundary, periodic, tangent_edges, smoothing, minimax, \
        tune_knots = (args[k] for k in ARGUMENTS)
    from ..surfaces.fitting import surface_parameters
    if np.ndim(points) == 2:
        if boundary is not None:
            raise CagdError("boundary: held boundary curves need a grid (m, n, d); scattered points have none")
        for name, given in (("periodic", periodic not in (None, False, (False, False))),
                            ("tangent_edges", bool(tangent_edges)), ("smoothing", smoothing != 0.0),
                            ("minimax", minimax is not False)):
            if given:
                raise CagdError(f"{name}: only grid fits (m, n, d) take it; scattered points have none")
        return fit_scattered(points, tol, degree, max_control_points, "plane" if base is None else base)
    if base is not None:
        raise CagdError("base: only scattered (N, 3) points are projected onto a base; a grid has its own parameters")
    Q = _checks.finite_array(points, "points", ndim=3)
    m, n, d = Q.shape
    if m < 2 or n < 2:
        raise CagdError(f"points: expected a grid of at least 2 x 2 points, got {m} x {n}")
    tol = _checks.positive(tol, "tol")
    pu, pv, cap_u, cap_v = _degrees_and_caps(degree, max_control_points, (m, n))
    if boundary not in BOUNDARIES:
        raise CagdError(f"boundary: expected one of {BOUNDARIES}, got {boundary!r}")
    held = boundary == "G0"
    if m < pu + 1 or n < pv + 1:
        raise CagdError(f"degree: a {m} x {n} grid fits at most degree {m - 1} x {n - 1}, got {pu} x {pv}")
    closed = _periodic_pair(periodic)
    smoothing = _checks.nonnegative(smoothing, "smoothing")
    if not isinstance(minimax, (bool, np.bool_)):
        raise CagdError(f"minimax: expected True or False, got {minimax!r}")
    if not isinstance(tune_knots, (bool, np.bool_)):
        raise CagdError(f"tune_knots: expected True or False, got {tune_knots!r}")
    if minimax and (any(closed) or tangent_edges or smoothing > 0.0 or held):
        raise CagdError("minimax: a grid fit without periodic, tangent_edges, smoothing or boundary='G0' only "
                        "(their rows and seams are held by the least squares)")
    if any(closed) or tangent_edges or smoothing > 0.0:
        return _net_fit(Q, tol, (pu, pv), (cap_u, cap_v), parameters, closed, tangent_edges, smoothing, held)
    u, v = surface_parameters(Q, parameters)
    u, v = (u - u[0]) / (u[-1] - u[0]), (v - v[0]) / (v[-1] - v[0])
    center, scale = _frame(Q.reshape(-1, d))
    Qn = (Q - center) / scale
    tol_n = tol / scale
    recovered = _recovered(Qn, tol_n, (pu, pv), cap_u * cap_v + 1) if not (minimax or held) else None
    if recovered is not None:              # a sampled B-spline surface: its knots and parameters
        best, rounds, u, v = (recovered[0],), 0, recovered[1], recovered[2]
    else:
        best, rounds = _separable(Qn, u, v, tol_n, (pu, pv), (cap_u - pu, cap_v - pv),
                                  tune=bool(tune_knots) and not minimax)
    if minimax:         # the minimax stage from the rounds' fit, beside that fit's knots tuned
        best, more = _minimax_stage(best, Qn, u, v, tol_n, (pu, pv), (cap_u - pu, cap_v - pv))
        rounds += more
        if tune_knots:
            tuned, again = _separable(Qn, u, v, tol_n, (pu, pv), (cap_u - pu, cap_v - pv))
            rounds += again
            if _poles(tuned[0]) <= _poles(best[0]) and tuned[3] <= tol_n:
                best = tuned
    S = best[0]
    if beat is not None and _poles(S) >= beat:
        return None
    P = S.control_points * scale + center
    if held:        # the boundary curves exactly the 1-D fits of the boundary points
        P[0], P[-1], P[:, 0], P[:, -1] = _boundary_rows(Q, u, v, S.knots_u, S.knots_v, pu, pv)
    if not minimax:
        P[0, 0], P[0, -1], P[-1, 0], P[-1, -1] = Q[0, 0], Q[0, -1], Q[-1, 0], Q[-1, -1]
    out = BSplineSurface(P, pu, pv, S.knots_u, S.knots_v)
    jet = (out.grid(u, v).reshape(-1, d), out.grid(u, v, 1, 0).reshape(-1, d), out.grid(u, v, 0, 1).reshape(-1, d))
    at = np.sqrt(((jet[0] - Q.reshape(-1, d)) ** 2).sum(-1))
    grid_uv = np.stack(np.meshgrid(u, v, indexing="ij"), axis=-1).reshape(-1, 2)
    fit = _measured(out, Q.reshape(-1, d), at, grid_uv, tol, rounds, jet)
    return SurfaceFit(fit.surface, fit.max_error, fit.rms_error, fit.params.reshape(m, n, 2), rounds,
                      fit.converged, fit.message)


def _poles(S: BSplineSurface) -> int:
    return int(np.prod(S.control_points.shape[:2]))


def _recovered(Qn: np.ndarray, tol_n: float, degrees: Tuple[int, int], poles: int):
    """Below the curve stage's SEARCH_TOL (the exactness case): the grid's knots and
    parameters recovered per direction (:func:`cagd.fitting.surface_knots.recovered_surface`),
    or None (then the adaptive separable fit)."""
    from .fit import SEARCH_TOL
    from .surface_knots import recovered_surface
    return recovered_surface(Qn, tol_n, degrees, poles) if tol_n <= SEARCH_TOL else None


#: the degrees ``degree="auto"`` tries (OCCT's GeomAPI_PointsToBSplineSurface takes 3..8;
#: on the 100 x 100 anchor at tol 0.001 degree 3 took 19 x 18 poles, 4 17 x 15, 5 17 x 16,
#: 6 17 x 17; at tol 0.01 13 x 12 for 3 and 4, more above)
AUTO_DEGREES = (3, 4, 5)


#: the arguments of :func:`fit_surface` after the degree, as :func:`_fit_surface` takes them
ARGUMENTS = ("points", "tol", "parameters", "max_control_points", "base", "boundary", "periodic", "tangent_edges",
             "smoothing", "minimax", "tune_knots")


def _auto_degree(name: str, args: dict) -> SurfaceFit:
    """:func:`fit_surface` with ``degree="auto"``: a fit per degree of AUTO_DEGREES, the
    converged one with the fewest control points kept (the first on a tie), else the one
    with the smallest max_error. A grid of m x n points caps the degrees at m - 1 and
    n - 1 (a 3 x 20 grid tries 2 x 3, 2 x 4, 2 x 5); a degree that cannot be fitted
    otherwise is skipped (the first tried: bad input raises there), and a separable grid
    fit with at least the poles of an earlier converged one is not measured (it cannot
    win; ``rounds`` counts the degrees measured)."""
    if name != "auto":
        raise CagdError(f"degree: expected a degree, a pair (degree_u, degree_v) or 'auto', got {name!r}")
    best: Optional[SurfaceFit] = None
    rounds = 0
    shape = np.shape(args["points"])
    grid = len(shape) == 3 and min(shape[:2]) >= 2
    tried: list = []
    for p in AUTO_DEGREES:
        degrees = (min(p, shape[0] - 1), min(p, shape[1] - 1)) if grid else (p, p)
        if degrees in tried:
            continue
        tried.append(degrees)
        try:
            fit = _fit_surface(degrees, args, _count(best) if best is not None and best.converged else None)
        except CagdError:
            if len(tried) == 1:
                raise
            continue
        if fit is None:                 # more poles than a converged fit of an earlier degree
            continue
        rounds += fit.rounds
        if best is None or _rank(fit) > _rank(best):
            best = fit
    assert best is not None
    return SurfaceFit(best.surface, best.max_error, best.rms_error, best.params, rounds, best.converged,
                      f"{best.message}; degree {best.surface.degree_u} x {best.surface.degree_v} of {AUTO_DEGREES} "
                      f"(the fewest control points)")


def _count(fit: SurfaceFit) -> int:
    return _poles(fit.surface)


def _rank(fit: SurfaceFit) -> Tuple[int, float]:
    """Larger is better: a converged fit by its fewer control points, before any other by
    its smaller error."""
    return (1, -float(_count(fit))) if fit.converged else (0, -fit.max_error)


def _periodic_pair(periodic) -> Tuple[bool, bool]:
    """(periodic_u, periodic_v) from None / a bool / "u" / "v" / "uv" / a pair of bools."""
    if periodic is None or periodic is False:
        return False, False
    if periodic is True:
        return True, True
    if isinstance(periodic, str) and periodic in ("u", "v", "uv"):
        return "u" in periodic, "v" in periodic
    if isinstance(periodic, (tuple, list)) and len(periodic) == 2 and all(
            isinstance(x, (bool, np.bool_)) for x in periodic):
        return bool(periodic[0]), bool(periodic[1])
    raise CagdError(f"periodic: expected (bool, bool), 'u', 'v', 'uv' or a bool, got {periodic!r}")


def _closed_grid(Q: np.ndarray, tol: float, closed: Tuple[bool, bool]) -> Tuple[np.ndarray, Tuple[bool, bool]]:
    """The grid without a last row (column) that repeats the first within tol in a
    periodic direction, and which were dropped."""
    dropped = [False, False]
    for axis in (0, 1):
        if closed[axis]:
            G = Q if axis == 0 else Q.transpose(1, 0, 2)
            if float(np.sqrt(((G[-1] - G[0]) ** 2).sum(-1)).max()) <= tol:
                Q = Q[:-1] if axis == 0 else Q[:, :-1]
                dropped[axis] = True
    return Q, (dropped[0], dropped[1])


def _net_parameters(Q: np.ndarray, parameters, closed: Tuple[bool, bool]) -> Tuple[np.ndarray, np.ndarray]:
    """The averaged parameters on [0, 1] per direction; a periodic direction's on [0, 1)
    with the closing chord (last row to first) counted (the grid closed for the rule)."""
    from ..surfaces.fitting import surface_parameters
    G = Q
    if closed[0]:
        G = np.concatenate([G, G[:1]], axis=0)
    if closed[1]:
        G = np.concatenate([G, G[:, :1]], axis=1)
    u, v = surface_parameters(G, parameters)
    u, v = (u - u[0]) / (u[-1] - u[0]), (v - v[0]) / (v[-1] - v[0])
    return (u[:-1] if closed[0] else u), (v[:-1] if closed[1] else v)


def _tangent_edges(tangent_edges, Q: np.ndarray, closed: Tuple[bool, bool], degrees: Tuple[int, int]):
    """The checked Edges of ``tangent_edges`` (:func:`fit_surface`)."""
    from .surface_net import EDGE_NAMES, Edge, neighbour_edge
    if not tangent_edges:
        return []
    if not isinstance(tangent_edges, Mapping):
        raise CagdError(f"tangent_edges: expected a mapping of edge names to 'grid' or a neighbouring surface, "
                        f"got {type(tangent_edges).__name__}")
    if any(closed):
        raise CagdError("tangent_edges: not with a periodic direction (its edges would run round the seam)")
    bad = [k for k in tangent_edges if k not in EDGE_NAMES]
    if bad:
        raise CagdError(f"tangent_edges: edge names are {EDGE_NAMES}, got {bad[0]!r}")
    if {"u0", "u1"} & set(tangent_edges) and {"v0", "v1"} & set(tangent_edges):
        raise CagdError(f"tangent_edges: adjacent edges {sorted(tangent_edges)} share a corner's twist pole; "
                        f"hold opposite edges only")
    edges = []
    for name, spec in tangent_edges.items():
        if isinstance(spec, str):
            if spec != "grid":
                raise CagdError(f"tangent_edges: edge {name!r} expects 'grid' or a neighbouring surface, "
                                f"got {spec!r}")
            edges.append(Edge(name, "grid"))
        else:
            edges.append(neighbour_edge(name, spec, Q, *degrees))
    return edges


def _net_fit(Q: np.ndarray, tol: float, degrees: Tuple[int, int], caps: Tuple[int, int], parameters,
             closed: Tuple[bool, bool], tangent_edges, smoothing: float, g0: bool) -> SurfaceFit:
    """fit_surface with periodic directions, tangent edges or smoothing: the full-net
    least squares of :mod:`cagd.fitting.surface_net`, measured by certified closest points
    of every grid point (the dropped seam rows too)."""
    from .surface_net import fit_net
    m0, n0, d = Q.shape
    if g0 and any(closed):
        raise CagdError("boundary: 'G0' holds the four boundary curves; a periodic direction has no boundary there")
    edges = _tangent_edges(tangent_edges, Q, closed, degrees)
    Qf, dropped = _closed_grid(Q, tol, closed)
    # a periodic direction: no more poles than distinct rows (a dropped seam row is the first)
    caps = (min(caps[0], Qf.shape[0]) if closed[0] else caps[0], min(caps[1], Qf.shape[1]) if closed[1] else caps[1])
    u, v = _net_parameters(Qf, parameters, closed)
    for e in edges:                  # the parameters along a neighbour's edge: the feet on it
        if e.kind == "surface":
            if e.name[0] == "u":
                v = e.feet
            else:
                u = e.feet
    transpose = closed[0] and not closed[1]          # the periodic direction inner: the narrower band
    if transpose:
        net = fit_net(Qf.transpose(1, 0, 2), v, u, tol, degrees[::-1], caps[::-1], closed[::-1], edges,
                      smoothing, g0)
        P, U, V = net.P.transpose(1, 0, 2), net.V, net.U
    else:
        net = fit_net(Qf, u, v, tol, degrees, caps, closed, edges, smoothing, g0)
        P, U, V = net.P, net.U, net.V
    pu, pv = degrees
    ku = U[pu:len(U) - pu] if closed[0] else U
    kv_ = V[pv:len(V) - pv] if closed[1] else V
    out = BSplineSurface(P, pu, pv, ku, kv_, periodic_u=closed[0], periodic_v=closed[1])
    uu = np.append(u, 1.0) if dropped[0] else u
    vv = np.append(v, 1.0) if dropped[1] else v
    at = np.sqrt(((out.grid(uu, vv) - Q) ** 2).sum(-1)).ravel()
    grid_uv = np.stack(np.meshgrid(uu, vv, indexing="ij"), axis=-1).reshape(-1, 2)
    fit = _measured(out, Q.reshape(-1, d), at, grid_uv, tol, net.rounds)
    return SurfaceFit(fit.surface, fit.max_error, fit.rms_error, fit.params.reshape(m0, n0, 2), net.rounds,
                      fit.converged, fit.message)


#: weight of the thin-plate regulariser of a scattered fit, relative to the data term
#: (knot cells without points stay defined; 1e-9 moves an exact fit by ~1e-9 of its size)
SCATTER_REGULARISATION = 1e-9
#: the points' second principal spread below this fraction of the first: they lie on a line
PLANE_SPREAD_TOL = 1e-9
#: a scattered fit's trimming polish passes (:func:`_polished`; each one solve)
SCATTER_POLISH = 2
#: a scattered fit's spans grow by at most this factor per round (the error model
#: overshot: 12 x 12 -> 28 x 34 poles on the 10,000-point anchor at tol 0.001, trimmed back
#: to 22 x 21 span by span in 49 solves; 23 with the factor 2)
SCATTER_GROWTH = 2
#: points per chunk of the scattered normal equations
SCATTER_CHUNK = 65536


#: the named bases of a scattered fit (or a cagd Surface to project onto)
BASES = ("plane", "quadric")
#: parameter-correction passes of a scattered fit per knot vector at most (each: the
#: certified feet on the current fit, a new solve; kept only while the largest miss drops
#: by CORRECTION_GAIN at least, the better fit kept)
SCATTER_CORRECTIONS = 3
#: a trimming candidate of a scattered fit that misses tol by at most this factor gets
#: parameter correction (farther ones are dropped: correction gains a few per cent)
TRIM_CORRECTION_REACH = 1.25


def _plane_frame(Q: np.ndarray) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(center, axes (3, 3), local coordinates (N, 3)) of the least-squares plane of the
    points: the first two axes span it, the third is its normal (SVD)."""
    c = Q.mean(axis=0)
    _, sigma, vt = np.linalg.svd(Q - c, full_matrices=False)
    local = (Q - c) @ vt.T
    lo, hi = local[:, :2].min(axis=0), local[:, :2].max(axis=0)
    if not sigma[1] > PLANE_SPREAD_TOL * sigma[0] or not np.all(hi - lo > 0.0):
        raise CagdError("points: the scattered points lie on a line; no surface is defined by them")
    return c, vt, local


def _unit_box(uv: np.ndarray, what: str) -> np.ndarray:
    """uv scaled to [0, 1]^2 by its bounding box."""
    lo, hi = uv.min(axis=0), uv.max(axis=0)
    if not np.all(hi - lo > 0.0):
        raise CagdError(f"{what}: the points project onto a curve of the base; no surface is defined by them")
    return np.clip((uv - lo) / (hi - lo), 0.0, 1.0)


def _plane_parameters(Q: np.ndarray) -> np.ndarray:
    """(u, v) in [0, 1]^2: the points projected onto their two principal directions (the
    least-squares plane), scaled to the bounding box of the projection."""
    return _unit_box(_plane_frame(Q)[2][:, :2], "points")


def _quadric_base(Q: np.ndarray) -> BSplineSurface:
    """The least-squares quadric height field over the points' plane, h = a + b x + c y +
    d x^2 + e x y + f y^2 in the plane's frame, over the box of the projection: exactly a
    biquadratic Bezier patch (its control net from the values at s, t in {0, 1/2, 1},
    the Bernstein collocation matrix inverted)."""
    c, axes, local = _plane_frame(Q)
    x, y, h = local.T
    coef = np.linalg.lstsq(np.stack([np.ones_like(x), x, y, x * x, x * y, y * y], axis=1), h, rcond=None)[0]
    s = np.array([0.0, 0.5, 1.0])
    X, Y = np.meshgrid(x.min() + (x.max() - x.min()) * s, y.min() + (y.max() - y.min()) * s, indexing="ij")
    H = coef[0] + coef[1] * X + coef[2] * Y + coef[3] * X * X + coef[4] * X * Y + coef[5] * Y * Y
    values = c + np.stack([X, Y, H], axis=-1) @ axes                                  # (3, 3, 3)
    Minv = np.linalg.inv(np.array([[1.0, 0.0, 0.0], [0.25, 0.5, 0.25], [0.0, 0.0, 1.0]]))
    return BSplineSurface(np.einsum("ia,abk,jb->ijk", Minv, values, Minv), 2, 2)


def _base_parameters(Q: np.ndarray, base) -> np.ndarray:
    """The points' parameters in [0, 1]^2 from their base: the plane (projection onto it),
    the quadric (:func:`_quadric_base`) or a given surface (their certified closest points
    on it), scaled to the bounding box of the feet."""
    from ..queries.closest import closest_point
    from ..surfaces.base import Surface
    if isinstance(base, str) and base == "plane":
        return _plane_parameters(Q)
    if isinstance(base, str) and base == "quadric":
        base = _quadric_base(Q)
    elif not isinstance(base, Surface) or not base.rectangular:
        raise CagdError(f"base: expected one of {BASES} or a cagd Surface on a rectangle, got {base!r}")
    elif base.dim != 3:
        raise CagdError(f"base: expected a surface in 3-D, got a {base.dim}-D one")
    near = closest_point(base, Q)
    return _unit_box(np.asarray(near.params, dtype=float), "base")


def _corrected(Q: np.ndarray, uv: np.ndarray, S: BSplineSurface, miss: np.ndarray, bu: np.ndarray, bv: np.ndarray,
               pu: int, pv: int) -> Tuple[np.ndarray, BSplineSurface, np.ndarray]:
    """Parameter correction (Hoschek 1988; Piegl & Tiller 9.4.1, here for a surface): the
    parameters move to the points' feet on the current fit (:func:`_local_feet`, from
    the current parameters) and the fit is solved again on the same knots, at most SCATTER_CORRECTIONS passes, stopping
    when the largest miss drops by less than CORRECTION_GAIN; the better fit is kept."""
    for _ in range(SCATTER_CORRECTIONS):
        uv2 = _local_feet(S, Q, uv)[0]
        S2, miss2 = _scattered_solve(Q, uv2, bu, bv, pu, pv)
        gain = float(miss2.max()) < (1.0 - CORRECTION_GAIN) * float(miss.max())
        if float(miss2.max()) < float(miss.max()):
            uv, S, miss = uv2, S2, miss2
        if not gain:
            break
    return uv, S, miss


#: Gauss-Newton steps of :func:`_local_feet` (parameter correction) ...
FOOT_STEPS = 3
#: ... and of the measurement's feet (:func:`_measured`; on the anchors the rms of the
#: distances then agrees with the certified one to 5e-10)
MEASURE_STEPS = 2


def _local_feet(S: BSplineSurface, Q: np.ndarray, uv: np.ndarray,
                jet: Optional[Tuple[np.ndarray, np.ndarray, np.ndarray]] = None,
                steps: int = FOOT_STEPS) -> Tuple[np.ndarray, np.ndarray]:
    """The points' feet on S near their parameters uv (N, 2): ``steps`` Gauss-Newton
    steps on |S(x) - Q|^2 (x <- x + (J^T J)^-1 J^T (Q - S(x)), J = [S_u S_v]; Piegl &
    Tiller 6.1 without the curvature term, which vanishes with the distance), clamped to
    [0, 1]^2, each point's step kept only where its distance drops; ``jet`` (S, S_u, S_v)
    at uv when known (a grid's, by matrix products), the last step's point evaluated
    without derivatives. Local (the parameter correction of a fit whose points lie near
    it; the measurement certifies where it decides). Returns (feet (N, 2), distances (N,))."""
    x = np.array(uv, dtype=float)
    if jet is None:
        D = S.derivatives(x[:, 0], x[:, 1], 1, 1)
        jet = (D[0, 0], D[1, 0], D[0, 1])
    F, Su, Sv = (np.array(a, dtype=float) for a in jet)
    r = Q - F
    d = np.einsum("ij,ij->i", r, r)
    for k in range(steps):
        # J and r divided by a power of two near |J| per point (exact: the same step bit
        # for bit), so that the products of the normal equations stay in range at any
        # coordinate scale (points at 1e150 overflowed a c to inf, det to nan)
        top = np.maximum(np.abs(Su).max(axis=1), np.abs(Sv).max(axis=1))
        sig = np.exp2(np.floor(np.log2(np.where(top > 0, top, 1.0))))[:, None]
        su, sv, rs = Su / sig, Sv / sig, r / sig
        a, b, c = (np.einsum("ij,ij->i", A, B) for A, B in ((su, su), (su, sv), (sv, sv)))
        gu, gv = np.einsum("ij,ij->i", su, rs), np.einsum("ij,ij->i", sv, rs)
        det = a * c - b * b
        ok = det > 1e-12 * np.maximum(a * c, 1e-300)
        safe = np.where(ok, det, 1.0)
        step = np.stack([np.where(ok, (c * gu - b * gv) / safe, 0.0), np.where(ok, (a * gv - b * gu) / safe, 0.0)], 1)
        y = np.clip(x + step, 0.0, 1.0)
        last = k == steps - 1
        E = S.derivatives(y[:, 0], y[:, 1], 0 if last else 1, 0 if last else 1)
        r2 = Q - E[0, 0]
        d2 = np.einsum("ij,ij->i", r2, r2)
        better = d2 < d
        x[better], r[better], d[better] = y[better], r2[better], d2[better]
        if not last:
            Su[better], Sv[better] = E[1, 0][better], E[0, 1][better]
    return x, np.sqrt(d)


def _chunk_basis(uv: np.ndarray, U: np.ndarray, V: np.ndarray, pu: int, pv: int):
    """Per chunk of SCATTER_CHUNK points: (first row, B (k, (pu+1)(pv+1)) the tensor basis
    values N_i(u) N_j(v) of the poles each point touches, cols their flat pole indices
    i nv + j)."""
    from ..basis.bspline import basis_derivatives
    from ..knots import vectors as kv
    nu, nv = len(U) - pu - 1, len(V) - pv - 1
    a, b = np.meshgrid(np.arange(pu + 1), np.arange(pv + 1), indexing="ij")
    for c0 in range(0, len(uv), SCATTER_CHUNK):
        u, v = uv[c0:c0 + SCATTER_CHUNK, 0], uv[c0:c0 + SCATTER_CHUNK, 1]
        su, sv = kv.find_span(U, pu, u, nu), kv.find_span(V, pv, v, nv)
        Nu, Nv = basis_derivatives(U, pu, u, su, 0)[0], basis_derivatives(V, pv, v, sv, 0)[0]
        B = (Nu[:, :, None] * Nv[:, None, :]).reshape(len(u), -1)
        cols = ((su - pu)[:, None] + a.ravel()) * nv + (sv - pv)[:, None] + b.ravel()
        yield c0, B, cols


def _scattered_solve(Q: np.ndarray, uv: np.ndarray, bu: np.ndarray, bv: np.ndarray, pu: int, pv: int,
                     weights: Optional[np.ndarray] = None) -> Tuple[BSplineSurface, np.ndarray]:
    """The least-squares tensor B-spline on the breakpoints through the scattered points
    at their parameters (normal equations accumulated per knot cell,
    :func:`cagd.fitting.separable.cell_normal_band`; the band pu nv + pv wide; a thin-plate
    regulariser of SCATTER_REGULARISATION), and its misses there (from the same basis
    values); ``weights`` (N,) of the points (default: equal), scaled to sum 1."""
    from ..basis.banded import solve_banded_rows
    from .fair import _thin_plate_band
    from .separable import cell_normal_band
    U, V = _knots(bu, pu), _knots(bv, pv)
    nu, nv = len(U) - pu - 1, len(V) - pv - 1
    start, E = _thin_plate_band(U, pu, V, pv)
    A = np.zeros_like(E)
    d = Q.shape[1]
    rhs = np.zeros((nu * nv, d))
    w = np.full(len(Q), 1.0 / len(Q)) if weights is None else weights / weights.sum()
    chunks = _chunk_basis(uv, U, V, pu, pv)
    kept = []                       # one chunk: its basis values serve the misses too
    for c0, B, cols in chunks:
        if len(uv) <= SCATTER_CHUNK:
            kept.append((c0, B, cols))
        wc = w[c0:c0 + len(B)]
        cell_normal_band(A, start, cols, B, wc)
        for k in range(d):
            rhs[:, k] += np.bincount(cols.ravel(), (B * (wc * Q[c0:c0 + len(B), k])[:, None]).ravel(),
                                     minlength=nu * nv)
    A += SCATTER_REGULARISATION * float(np.abs(A).max()) / (float(np.abs(E).max()) or 1.0) * E
    P = solve_banded_rows(start, A, rhs, "points")
    miss = np.empty(len(Q))
    for c0, B, cols in kept or _chunk_basis(uv, U, V, pu, pv):
        values = np.einsum("kq,kqd->kd", B, P[cols])
        D = values - Q[c0:c0 + len(B)]
        miss[c0:c0 + len(B)] = np.sqrt(np.einsum("kd,kd->k", D, D))
    return BSplineSurface(P.reshape(nu, nv, d), pu, pv, U, V), miss


def _separable(Qn: np.ndarray, u: np.ndarray, v: np.ndarray, tol_n: float, degrees: Tuple[int, int],
               most: Tuple[int, int], tune: bool = True):
    """The separable fit's grow / shrink / trim (module docstring) of the normalised grid
    Qn at the parameters u, v, at most ``most`` spans per direction, by the per-direction
    operators of :class:`cagd.fitting.separable.SeparableGrid`, then (``tune``) fewer
    spans with the knots moved (:func:`cagd.fitting.grid_knots.fewer_spans`; not for the
    minimax stage's shape fit, whose knots only start its growth). Returns (best, rounds),
    best = (surface, breaks_u, breaks_v, largest miss, misses (m, n))."""
    pu, pv = degrees
    most_u, most_v = most
    grid = SeparableGrid(Qn, u, v, pu, pv)
    bu, bv = np.array([0.0, 1.0]), np.array([0.0, 1.0])
    rounds = 0
    P, miss = grid.fit(bu, bv)
    while miss.max() > tol_n and rounds < MAX_FIT_ROUNDS:
        rounds += 1
        ru, rv = grid.residuals(bu, bv)
        nu = _grown(bu, u, ru.max(axis=1), DIRECTION_SHARE * tol_n, pu, most_u, "clamped")
        nv = _grown(bv, v, rv.max(axis=0), DIRECTION_SHARE * tol_n, pv, most_v, "clamped")
        if len(nu) == len(bu) and len(nv) == len(bv):
            # each direction alone is within its share: refine the one with the larger residual
            if ru.max() >= rv.max() and len(bu) - 1 < most_u:
                nu = _placed(bu, u, ru.max(axis=1), tol_n, pu, len(bu), "clamped")
            elif len(bv) - 1 < most_v:
                nv = _placed(bv, v, rv.max(axis=0), tol_n, pv, len(bv), "clamped")
            else:
                break
        bu, bv = nu, nv
        P, miss = grid.fit(bu, bv)

    def grid_sources(fit):
        ru, rv = grid.residuals(fit[1], fit[2])
        return ([(u, fit[4].max(axis=1)), (u, ru.max(axis=1))], [(v, fit[4].max(axis=0)), (v, rv.max(axis=0))])

    sites = ("clamped", "clamped")           # no regulariser here: knots the sites determine
    best, shrunk = _shrunk((P, bu, bv, float(miss.max()), miss), grid.fit, grid_sources, tol_n, (pu, pv),
                           MAX_FIT_ROUNDS - rounds, sites)
    best, trimmed = _trimmed(best, grid.fit, grid_sources, tol_n, (pu, pv),
                             (POLISH_PASSES, lambda fit: ((u, fit[4].max(axis=1)), (v, fit[4].max(axis=0)))), sites)
    rounds += shrunk + trimmed

    def fewer(fit, axis: int) -> np.ndarray:          # one span fewer, equidistributing the fit's misses
        t, e = (u, fit[4].max(axis=1)) if axis == 0 else (v, fit[4].max(axis=0))
        return _placed(fit[1 + axis], t, e, tol_n, degrees[axis], len(fit[1 + axis]) - 2, "clamped")
    if tune:
        best, tuned = fewer_spans(grid, best, tol_n, fewer)
        rounds += tuned
    S = BSplineSurface(best[0], pu, pv, _knots(best[1], pu), _knots(best[2], pv))
    return (S,) + tuple(best[1:]), rounds


#: Lawson passes of a minimax fit per knot vector at most (each: one weighted solve)
MINIMAX_PASSES = 30
#: the smallest weight of a point in the Lawson passes, relative to their mean (keeps the
#: normal equations definite where the misses vanish)
MINIMAX_FLOOR = 1e-6


def _minimax_solve(Q: np.ndarray, uv: np.ndarray, bu: np.ndarray, bv: np.ndarray, pu: int, pv: int,
                   tol: float) -> Tuple[BSplineSurface, np.ndarray]:
    """Towards the best uniform (L-infinity) fit on the breakpoints: Lawson's iteratively
    reweighted least squares, w_k <- w_k |r_k| after every weighted solve (C. L. Lawson,
    Contributions to the theory of linear least maximum approximation, 1961; Rice & Usow,
    Math. Comp. 22, 1968), at most MINIMAX_PASSES solves, stopping as soon as every point
    is within tol. Returns the fit with the smallest largest miss and its misses."""
    w = np.ones(len(Q))
    best: Optional[Tuple[BSplineSurface, np.ndarray]] = None
    for _ in range(MINIMAX_PASSES):
        S, miss = _scattered_solve(Q, uv, bu, bv, pu, pv, w)
        if best is None or miss.max() < best[1].max():
            best = (S, miss)
        if miss.max() <= tol:
            break
        w = w * miss
        w = np.maximum(w / w.mean(), MINIMAX_FLOOR) if w.max() > 0.0 else np.ones(len(Q))
    assert best is not None
    return best


def _minimax_stage(best, Qn: np.ndarray, u: np.ndarray, v: np.ndarray, tol_n: float, degrees: Tuple[int, int],
                   most: Tuple[int, int]):
    """Fewer poles for a noisy grid: the knots of the separable fit of the least-squares
    fit's own values (``best``: the noise averaged out, so the knots follow the shape, not
    the noise peaks), then minimax fits of the grid (:func:`_minimax_solve`) on them, one
    span more per step (alternately along u and v, the knots' density kept) until every
    point is within tol; ``best`` is kept when that needs as many poles. Returns (best,
    rounds)."""
    m, n, d = Qn.shape
    pu, pv = degrees
    flat = Qn.reshape(-1, d)
    uv = np.stack(np.meshgrid(u, v, indexing="ij"), axis=-1).reshape(-1, 2)
    shape, rounds = _separable(best[0].grid(u, v), u, v, tol_n, degrees, most, tune=False)
    bu, bv = shape[1], shape[2]

    def count(bu: np.ndarray, bv: np.ndarray) -> int:
        return (len(bu) - 1 + pu) * (len(bv) - 1 + pv)
    limit = count(best[1], best[2])
    for step in range(MAX_FIT_ROUNDS):
        if count(bu, bv) >= limit:
            break
        S, miss = _minimax_solve(flat, uv, bu, bv, pu, pv, tol_n)
        rounds += 1
        if miss.max() <= tol_n:
            return (S, bu, bv, float(miss.max()), miss.reshape(m, n)), rounds
        grow_u = (step % 2 == 0 and len(bu) - 1 < most[0]) or len(bv) - 1 >= most[1]
        if grow_u and len(bu) - 1 < most[0]:
            bu = _redistributed(bu, np.ones(len(bu) - 1), len(bu))
        elif len(bv) - 1 < most[1]:
            bv = _redistributed(bv, np.ones(len(bv) - 1), len(bv))
        else:
            break
    return best, rounds


def fit_scattered(points: ArrayLike, tol: float, degree: Union[int, Tuple[int, int]] = 3,
                  max_control_points: Optional[Tuple[int, int]] = None,
                  base: Union[str, Surface] = "plane") -> SurfaceFit:
    """A B-spline surface within ``tol`` of scattered points (N, 3) (a scan of a sheet):
    parameters from the projection onto a base (``base``: "plane", the points'
    least-squares plane; "quadric", the least-squares quadric height field over that
    plane; or a cagd Surface, by certified closest points; the points must be a graph
    over it), least squares over all control points with a tiny thin-plate regulariser,
    knots per direction equidistributing the largest miss of the points in each span
    (as :func:`fit_surface`), grown until every point is within tol at its parameters;
    after every solve the parameters are corrected by re-projection onto the fit
    (Piegl & Tiller 9.4.1; :func:`_corrected`); errors reported by certified closest
    points. A growth whose largest miss stalls while the poles grow stops there
    (:func:`cagd.fitting.fit.stalled`: tol below the points' noise), the grown fit with
    the smallest largest miss returned, converged False, the message saying why.

    Raises:
        CagdError: not (N >= 4, 3) finite points, collinear points, bad tol, degree or base."""
    Q = _checks.points(points, "points", min_count=4)
    if Q.shape[1] != 3:
        raise CagdError(f"points: scattered points are (N, 3), got {Q.shape[1]}-D points")
    tol = _checks.positive(tol, "tol")
    side = int(np.sqrt(len(Q)))
    pu, pv, cap_u, cap_v = _degrees_and_caps(degree, max_control_points, (side, side))
    uv = _base_parameters(Q, base)
    center, scale = _frame(Q)
    Qn = (Q - center) / scale
    tol_n = tol / scale
    most_u, most_v = cap_u - pu, cap_v - pv
    bu, bv = np.array([0.0, 1.0]), np.array([0.0, 1.0])
    S, miss = _scattered_solve(Qn, uv, bu, bv, pu, pv)
    rounds = 0

    def poles(bu: np.ndarray, bv: np.ndarray) -> int:
        return (len(bu) - 1 + pu) * (len(bv) - 1 + pv)

    history = [(poles(bu, bv), float(miss.max()) * scale)]
    least = (S, miss, bu, bv)                  # the grown fit with the smallest largest miss
    why = None
    while miss.max() > tol_n and rounds < MAX_FIT_ROUNDS:
        rounds += 1
        nu = _grown(bu, uv[:, 0], miss, tol_n, pu, min(most_u, SCATTER_GROWTH * (len(bu) - 1)))
        nv = _grown(bv, uv[:, 1], miss, tol_n, pv, min(most_v, SCATTER_GROWTH * (len(bv) - 1)))
        if len(nu) == len(bu) and len(nv) == len(bv):
            break
        bu, bv = nu, nv
        S, miss = _scattered_solve(Qn, uv, bu, bv, pu, pv)
        history.append((poles(bu, bv), float(miss.max()) * scale))
        if miss.max() < least[1].max():
            least = (S, miss, bu, bv)
        why = stalled(history, len(Q))
        if why:                                # tol below the noise: the least miss grown
            S, miss, bu, bv = least
            break
    if miss.max() > tol_n:
        uv, S, miss = _corrected(Qn, uv, S, miss, bu, bv, pu, pv)

    def solve(bu, bv):
        S2, miss2 = _scattered_solve(Qn, uv, bu, bv, pu, pv)
        if tol_n < miss2.max() <= TRIM_CORRECTION_REACH * tol_n:   # correction where it can lower the count
            uv2, S2, miss2 = _corrected(Qn, uv, S2, miss2, bu, bv, pu, pv)
            return S2, miss2, uv2
        return S2, miss2, uv

    def sources(fit):
        return [(fit[5][:, 0], fit[4])], [(fit[5][:, 1], fit[4])]

    best, shrunk = _shrunk((S, bu, bv, float(miss.max()), miss, uv), solve, sources, tol_n, (pu, pv),
                           MAX_FIT_ROUNDS - rounds)
    best, trimmed = _trimmed(best, solve, sources, tol_n, (pu, pv),
                             (SCATTER_POLISH, lambda fit: ((fit[5][:, 0], fit[4]), (fit[5][:, 1], fit[4]))))
    rounds += shrunk + trimmed
    S, uv = best[0], best[5]
    out = BSplineSurface(S.control_points * scale + center, pu, pv, S.knots_u, S.knots_v)
    at = np.sqrt(((out(uv[:, 0], uv[:, 1]) - Q) ** 2).sum(-1))
    return _measured(out, Q, at, uv, tol, rounds, why=why)


def _certified(S: Surface, X: np.ndarray, light=None):
    """The certified closest points of X (N, d) on the fit S (:class:`cagd.ClosestPoints`)
    by the closest-point machinery's light tier (:class:`cagd.queries.closest.Projector`
    with ``light=True``: about one cell per Bezier piece, no voxel grid, every point
    descending the cells' hierarchy; the same certificate), or by the given one. A fit's
    points lie near it, so the default tier's voxel grid does not pay: on the 100 x 100
    anchor's 19 x 18 fit its set-up took 0.43 s and the query of all 10,000 points
    0.07 s, the light tier's 0.01 s and 0.15 s."""
    from ..queries.closest import Projector
    return (Projector(S, light=True) if light is None else light).closest(X)


#: the points whose closest points :func:`_measured` certifies first: those whose distance
#: at their fitting parameters is at least this share of the largest one
CERTIFY_SHARE = 0.9
#: ... and while the certified largest distance is below the share, the share times this
CERTIFY_LOWER = 0.5
#: ... down to this share; below it every point is certified
CERTIFY_FLOOR = 1e-3
#: ... except the points within this share of the points' extent at their fitting
#: parameters (the closest-point query's own tolerance, CLOSEST_TOL: an exact fit's
#: rounding; 160,000 such points took 1.9 s to certify)
CERTIFY_ROUNDING = 1e-12


def _measured(out: BSplineSurface, X: np.ndarray, at: np.ndarray, uv: np.ndarray, tol: float,
              rounds: int, jet: Optional[Tuple[np.ndarray, np.ndarray, np.ndarray]] = None,
              why: Optional[str] = None) -> SurfaceFit:
    """The result measured: every point's distance is at most ``at``, its distance from
    the fit at its fitting parameters ``uv``, and the certified closest-point distance
    (:func:`_certified`) of the points where ``at`` is at least s times the largest,
    s = CERTIFY_SHARE (lowered by CERTIFY_LOWER while the largest certified distance is
    below s times the largest ``at``, every point below CERTIFY_FLOOR; none with ``at``
    within CERTIFY_ROUNDING of the points' extent; by the default tier after a stalled
    growth). The other points
    are closer than s max(at), at most that largest certified distance, so ``max_error``
    is the certified largest distance of all points; ``rms_error`` and ``params`` take
    the certified distance and foot where computed and the local foot from ``uv``
    elsewhere (:func:`_local_feet`: the closest point of a point near the fit; ``jet``:
    S, S_u, S_v (N, d) at uv when known); ``why`` the growth stopped short of tol
    (:func:`cagd.fitting.fit.stalled`), for the message."""
    from ..queries.closest import Projector
    top = float(at.max())
    dist, params = at.copy(), uv.copy()
    done = np.zeros(len(X), dtype=bool)
    # a stalled growth's fit (tol below the noise) lies away from its points, wavy, where the
    # light tier descends into many cells: the default tier (voxel grid) then (the 1,341-point
    # noise cloud's 20 x 20 fit, 3 points: light 6.4 s, default 1.0 s; 12 x 12, 10 points:
    # 2.1 s and 0.7 s); elsewhere its set-up does not pay (a 100-point 10 x 10 fit missing
    # tol: 0.1 s light, 1.5 s default)
    light = Projector(out, light=why is None)
    share = CERTIFY_SHARE
    rounding = CERTIFY_ROUNDING * max(float(np.ptp(X, axis=0).max()), 1e-300)
    while top > rounding:
        pick = np.flatnonzero(~done & (at > rounding) & (at >= (share * top if share >= CERTIFY_FLOOR else -1.0)))
        if len(pick):
            near = _certified(out, X[pick], light)
            closer = np.asarray(near.distances) <= at[pick]
            dist[pick] = np.where(closer, np.asarray(near.distances), at[pick])
            params[pick] = np.where(closer[:, None], np.asarray(near.params), uv[pick])
            done[pick] = True
        if done.all() or float(dist[done].max()) >= share * top:
            break
        share *= CERTIFY_LOWER
    rest = np.flatnonzero(~done & (at > rounding))
    if len(rest):                   # the others' local feet: their distances for the rms
        feet, local = _local_feet(out, X[rest], uv[rest],
                                  None if jet is None else (jet[0][rest], jet[1][rest], jet[2][rest]), MEASURE_STEPS)
        closer = local < dist[rest]
        dist[rest[closer]], params[rest[closer]] = local[closer], feet[closer]
    worst, rms = float(dist.max()), float(np.sqrt(np.mean(dist ** 2)))
    shape = out.control_points.shape[:2]
    ok = worst <= tol
    msg = (f"{shape[0]} x {shape[1]} control points, every point within {worst:.3g} (tol {tol:g})" if ok else
           f"tol {tol:g} not met: {shape[0]} x {shape[1]} control points, largest distance {worst:.3g} "
           f"({why or f'the cap or {MAX_FIT_ROUNDS} rounds reached'})" if why is None else
           f"tol {tol:g} not met: returned the grown fit with the smallest largest miss, {shape[0]} x {shape[1]} "
           f"= {shape[0] * shape[1]} control points, largest distance {worst:.3g} ({why})")
    return SurfaceFit(out, worst, rms, params, rounds, ok, msg)
