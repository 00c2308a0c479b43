"""Example 6 (build123d): engine geometry in a BuildPart context through
``cq_ext.to_b3d``: a gently curved NURBS cover (bicubic B-spline surface through
measured points) thickened into a part, a round hole cut through it, and a
handle swept along an engine G2 curve (cubic spline) and added.

Checks: the part is valid; its volume equals (cover) - (hole) + (handle) measured
separately (booleans consistent to 1e-6: the offset and swept surfaces are OCCT
approximations, and the booleans intersect them within OCCT's tolerance; measured
5e-7); the cover face's points equal the engine's
surface at the same parameters (to_b3d is exact); the hole's volume lost matches
the cylinder through the cover within the thin-wall estimate; engine objects
through OCCT, STEP and IGES (cagd.occ.verify).

Run: python examples/b3d_part.py [OUTDIR]
"""
import numpy as np
import build123d as bd

import cagd
import cq_ext
from cagd.occ import volume, write_step
from _common import Checks, output_folder

THICKNESS = 2.5


def cover_surface() -> cagd.BSplineSurface:
    """Through a 5 x 5 grid of measured points, 100 x 80 mm, crowned by 6 mm."""
    x, y = np.meshgrid(np.linspace(0, 100, 5), np.linspace(0, 80, 5), indexing="ij")
    z = 6.0 * (1 - ((x - 50) / 50) ** 2) * (1 - ((y - 40) / 40) ** 2)
    return cagd.interpolate_surface(np.stack([x, y, z], axis=-1), 3, 3)


def handle_path() -> cagd.Curve:
    return cagd.natural_cubic_spline([[30, 40, 5], [40, 40, 20], [60, 40, 20], [70, 40, 5]], "natural", "chord")


def main() -> None:
    out = output_folder("out/examples")
    checks = Checks("build123d part: a NURBS cover thickened, drilled and given a swept handle")
    surface, path = cover_surface(), handle_path()
    face = cq_ext.to_b3d(surface)
    u, v = np.meshgrid(np.linspace(0, 1, 7), np.linspace(0, 1, 7), indexing="ij")
    occ_pts = np.array([tuple(face.position_at(a, b)) for a, b in zip(u.ravel(), v.ravel())])
    engine = surface(*(np.array(np.meshgrid(np.linspace(*surface.domain[0], 7), np.linspace(*surface.domain[1], 7),
                                            indexing="ij")))).reshape(-1, 3)
    checks.at_most("build123d face vs engine surface, same normalised parameters (mm)",
                   np.abs(occ_pts - engine).max(), 1e-9)
    rail = cq_ext.to_b3d(path)
    with bd.BuildPart() as cover:
        bd.thicken(face, THICKNESS)
    with bd.BuildPart() as handle:
        with bd.BuildSketch(bd.Plane(origin=rail.position_at(0), z_dir=rail.tangent_at(0))):
            bd.Circle(3.0)
        bd.sweep(path=rail)
    with bd.BuildPart() as part:
        bd.insert(cover.part)
        with bd.Locations((80, 40, 0)):
            bd.Cylinder(6.0, 40.0, mode=bd.Mode.SUBTRACT)
        bd.insert(handle.part)
    solid = part.part
    checks.true("the part is valid (is_valid)", solid.is_valid)
    v_cover, v_handle = volume(cover.part.wrapped), volume(handle.part.wrapped)
    with bd.BuildPart() as plug:
        bd.insert(cover.part)
        with bd.Locations((80, 40, 0)):
            bd.Cylinder(6.0, 40.0, mode=bd.Mode.INTERSECT)
    v_plug = volume(plug.part.wrapped)
    overlap = volume((cover.part & handle.part).wrapped)
    expected = v_cover - v_plug + v_handle - overlap
    checks.at_most("V(part) vs V(cover) - V(hole plug) + V(handle) - V(overlap), relative",
                   abs(volume(solid.wrapped) - expected) / expected, 1e-6)   # OCCT's boolean tolerance
    checks.at_most("hole plug volume / (pi r^2 t) - 1 (thin-wall estimate)",
                   abs(v_plug / (np.pi * 36 * THICKNESS) - 1), 0.05)
    checks.verified([("cover surface", surface), ("handle path", path)])
    step = out / "b3d_part.step"
    write_step([("cover part", solid.wrapped)], step)
    checks.step_valid(step, 1)
    checks.finish()


if __name__ == "__main__":
    main()
