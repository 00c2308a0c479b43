"""OCCT's own analytic surfaces for the engine's surfaces of revolution.

A :class:`cagd.RevolvedSurface` (made by :func:`cagd.revolve`, :func:`cagd.sphere`,
:func:`cagd.torus`, :func:`cagd.cylinder`, :func:`cagd.cone`) carries its construction;
here it becomes ``Geom_SphericalSurface``, ``Geom_ToroidalSurface``,
``Geom_CylindricalSurface``, ``Geom_ConicalSurface`` (primitives) or
``Geom_SurfaceOfRevolution`` of the profile's exact B-spline (any other revolution).

Exact means: the same point set as the engine surface (the engine's NURBS form is an
exact rational parametrisation of the same surface), only the parametrisation
differs. OCCT's is by angle: U = theta(v) = :func:`cagd.surfaces.revolution.arc_angle`
of the engine's v (the rational circle's parametrisation: on each arc of sweep d,
tan((theta - m) / 2) = (2 s - 1) tan(d / 4)), and V the profile's parameter u
(revolutions) or the primitive's latitude / tube angle / height / slant distance
(:meth:`cagd.Primitive.analytic_parameters`; for a reflected primitive U = 2 pi - theta).
Measured in tests/occ/test_analytic.py: engine points lie on the OCCT surface within
about 1e-15 of its size, and back (the tests require 1e-12).

OCCT's offset algorithm (BRepOffset_MakeOffset: thickening, shelling) accepts these
surfaces; the NURBS form has the rational circle's double knots, which OCCT declares
C0, and fails there (BRepOffset_C0Geometry).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional, Tuple

from OCP.Geom import (Geom_ConicalSurface, Geom_CylindricalSurface, Geom_RectangularTrimmedSurface,
                      Geom_SphericalSurface, Geom_Surface, Geom_SurfaceOfRevolution, Geom_ToroidalSurface)
from OCP.gp import gp_Ax1, gp_Ax3, gp_Dir, gp_Pnt

from ..surfaces.base import Surface
from ..surfaces.revolution import RevolvedSurface


@dataclass(frozen=True)
class AnalyticForm:
    """The analytic OCCT surface of an engine surface of revolution.

    ``surface`` is the whole analytic surface (unbounded in V for a cylinder or cone),
    ``bounds`` = (U0, U1, V0, V1) the engine surface's range on it, and ``reversed``
    says that its natural normal D_U x D_V is the opposite of the engine's S_u x S_v,
    so a face on it must be reversed: always for ``Geom_SurfaceOfRevolution`` (its U
    is the engine's v, its V the engine's u: the order swapped), for a primitive
    after a reflection (``turn`` = -1)."""
    surface: Geom_Surface
    bounds: Tuple[float, float, float, float]
    reversed: bool

    def bounded(self) -> Geom_Surface:
        """``surface`` trimmed to ``bounds`` (the bare surface when they are its own)."""
        own = self.surface.Bounds()
        if all(abs(a - b) <= 1e-15 * max(1.0, abs(a)) for a, b in zip(own, self.bounds)):
            return self.surface
        return Geom_RectangularTrimmedSurface(self.surface, *self.bounds)


def _pnt(p) -> gp_Pnt:
    return gp_Pnt(*map(float, p))


def _dir(d) -> gp_Dir:
    return gp_Dir(*map(float, d))


def analytic_form(surface: Surface) -> Optional[AnalyticForm]:
    """The analytic form of a :class:`cagd.RevolvedSurface` (see the module
    docstring), or None for any other surface."""
    if not isinstance(surface, RevolvedSurface):
        return None
    p = surface.primitive
    if p is None:
        from .convert import to_occ          # the profile's exact B-spline
        r = surface.revolution
        geom = Geom_SurfaceOfRevolution(to_occ(r.profile), gp_Ax1(_pnt(r.axis_point), _dir(r.axis_direction)))
        return AnalyticForm(geom, surface.analytic_bounds, True)
    frame = gp_Ax3(_pnt(p.center), _dir(p.axis), _dir(p.x_direction))
    if p.kind == "sphere":
        geom = Geom_SphericalSurface(frame, p.radius)
    elif p.kind == "torus":
        geom = Geom_ToroidalSurface(frame, p.radius, p.minor_radius)
    elif p.kind == "cylinder":
        geom = Geom_CylindricalSurface(frame, p.radius)
    else:
        geom = Geom_ConicalSurface(frame, p.semi_angle, p.radius)
    return AnalyticForm(geom, p.analytic_bounds, p.turn < 0)
