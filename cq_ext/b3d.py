"""cq_ext for build123d users, with or without CadQuery: engine objects to build123d
edges and faces (:func:`to_b3d`), any library's edges and faces back to engine
B-splines (:func:`from_shape`), and the solid helpers returning build123d shapes
(``Solid``, ``Shell``, ``Edge``): :func:`sew_solid`, :func:`sew_shell`,
:func:`close_with_caps`, :func:`thicken`, :func:`free_edges`. They take engine
surfaces and the shapes of build123d (``Face``, ``Shell``, ``Solid``, ``Part``,
``Sketch``, ``Curve``; ``BuildPart``/``BuildSketch``/``BuildLine`` contexts), of
CadQuery, and bare OCCT shapes. Works with build123d 0.12 (OCCT 7.9) and 0.13
(OCCT 8.0, where CadQuery cannot be installed alongside)::

    import cagd
    from cq_ext import b3d
    solid = b3d.sew_solid(cagd.ellipsoid(3, 2, 1.5))      # a build123d Solid

The surfaces from curve networks, sweeps and blends (issue 18) return build123d
faces and edges: :func:`loft_surface`, :func:`gordon_surface`, :func:`sweep_surface`,
:func:`sweep2_surface`, :func:`blend_curve`, :func:`blend_surface` and
:func:`match_surface`. Their curves and surfaces are engine objects (global
coordinates) or edges and faces of any library; a result that misses its tolerance is
a CagdError giving the accuracy reached, as for the CadQuery methods.
"""
from __future__ import annotations

import logging
from typing import Callable, Optional, Sequence, Union

import build123d as bd

import cagd

from .convert import curve_list, from_shape, global_curve, reported, to_b3d, untrimmed_surface
from .solids import front_end, gap_report

LOG = logging.getLogger(__name__)            # achieved accuracy of the network, sweep and blend functions
Law = Union[None, float, Callable]

sew_shell, sew_solid, close_with_caps, thicken, free_edges = front_end(bd.Shape.cast, "build123d", __name__)

__all__ = ["to_b3d", "from_shape", "sew_shell", "sew_solid", "close_with_caps", "thicken", "free_edges",
           "gap_report", "loft_surface", "gordon_surface", "sweep_surface", "sweep2_surface", "blend_curve",
           "blend_surface", "match_surface"]


def loft_surface(sections, degree_v: int = 3, parameters="chord", *, guides=None, tol: float = 1e-6,
                 align: bool = True) -> bd.Face:
    """The skinned face through the sections (:func:`cagd.loft`: any degrees, knots and
    weights; closed sections aligned; ``guides``: the Gordon surface within ``tol``).

    Raises:
        CagdError: the engine's refusals (naming sections, degree_v, parameters, guides)."""
    g = None if guides is None else curve_list(guides, "guides")
    return to_b3d(cagd.loft(curve_list(sections, "sections"), degree_v, parameters, guides=g, tol=tol, align=align))


def gordon_surface(profiles, guides, tol: float = 1e-6) -> bd.Face:
    """The Gordon face through a network (:func:`cagd.gordon`: every profile crosses every
    guide once within ``tol``; u along the profiles, v along the guides).

    Raises:
        CagdError: the engine's refusals, or ``max_error`` above ``tol``."""
    network = cagd.gordon(curve_list(profiles, "profiles"), curve_list(guides, "guides"), tol)
    result = reported("gordon_surface", network, "tol", LOG)
    return to_b3d(result.surface)


def sweep_surface(profile, path, frame="rmf", scale: Law = None, twist: Law = None, tol: float = 1e-6) -> bd.Face:
    """The profile swept along the path (:func:`cagd.sweep`: frame "rmf", "frenet",
    "fixed" or an up vector; ``scale`` and ``twist`` laws; stations refined to ``tol``).

    Raises:
        CagdError: the engine's refusals, or ``max_error`` above ``tol``."""
    result = cagd.sweep(global_curve(profile, "profile"), global_curve(path, "path"), frame=frame, scale=scale,
                        twist=twist, tol=tol)
    return to_b3d(reported("sweep_surface", result, "tol", LOG).surface)


def sweep2_surface(profiles, rail1, rail2, tol: float = 1e-6) -> bd.Face:
    """Profiles swept between two rails (:func:`cagd.sweep2`: each runs from rail1 to
    rail2, scaled to the chord between them).

    Raises:
        CagdError: the engine's refusals, or ``max_error`` above ``tol``."""
    result = cagd.sweep2(curve_list(profiles, "profiles"), global_curve(rail1, "rail1"), global_curve(rail2, "rail2"),
                         tol=tol)
    return to_b3d(reported("sweep2_surface", result, "tol", LOG).surface)


def blend_curve(c1, end1: str, c2, end2: str, continuity: int = 1,
                tangent_scales: Optional[Sequence[float]] = None) -> bd.Edge:
    """The Bezier bridge edge from c1's ``end1`` to c2's ``end2`` ("start" or "end"),
    G1, G2 or G3 to both (:func:`cagd.blend_curve`; tangent lengths automatic unless
    ``tangent_scales``).

    Raises:
        CagdError: the engine's refusals, or continuity not met within cagd's tolerance."""
    result = cagd.blend_curve(global_curve(c1, "c1"), end1, global_curve(c2, "c2"), end2, continuity,
                              tangent_scales)
    return to_b3d(reported("blend_curve", result, "continuity", LOG).curve)


def blend_surface(face1, edge1: str, face2, edge2: str, continuity: int = 1,
                  tangent_scales: Optional[Sequence[float]] = None) -> bd.Face:
    """The face bridging ``edge1`` of face1 and ``edge2`` of face2 ("u0", "u1", "v0",
    "v1" of their parameter boxes), G1 or G2 to both (:func:`cagd.blend_surface`);
    untrimmed faces or engine surfaces.

    Raises:
        CagdError: a trimmed face, the engine's refusals, or continuity not met."""
    result = cagd.blend_surface(untrimmed_surface(face1, "face1"), edge1, untrimmed_surface(face2, "face2"), edge2,
                                continuity, tangent_scales)
    return to_b3d(reported("blend_surface", result, "continuity", LOG).surface)


def match_surface(face, edge: str, target, target_edge: str, continuity: int = 1) -> bd.Face:
    """``face`` modified next to its ``edge`` to meet ``target`` at ``target_edge`` G0,
    G1 or G2 (:func:`cagd.match_surface`); untrimmed faces or engine surfaces.

    Raises:
        CagdError: a trimmed face, the engine's refusals, or continuity not met."""
    result = cagd.match_surface(untrimmed_surface(face, "face"), edge, untrimmed_surface(target, "target"),
                                target_edge, continuity)
    return to_b3d(reported("match_surface", result, "continuity", LOG).surface)
