"""Area and enclosed volume with trimmed faces (issue 15): cagd.area/enclosed_volume
count a TrimmedSurface over its trimmed domain (they used the untrimmed one). Oracles:
closed forms (a block with a round hole: a b c - pi r^2 c; its faces' areas) and OCCT's
BRepGProp on the same solid."""
import math

import numpy as np
import pytest

import cagd
from cagd import TrimmedSurface
from cagd.surfaces.properties import area as total_area, enclosed_volume
from trim_shapes import circle, rectangle, square_patch


def test_a_trimmed_disk_counts_its_disk_only():
    ts = TrimmedSurface(square_patch(2.0), [[circle((0.5, 0.5), 0.3)]])
    assert total_area(ts).value == pytest.approx(4 * math.pi * 0.09, rel=1e-12)
    assert total_area([ts, ts.untrimmed]).value == pytest.approx(4 * math.pi * 0.09 + 4.0, rel=1e-12)


def block_with_a_hole(a=3.0, b=2.0, c=1.0, r=0.4, centre=(1.2, 0.9), offset=(0.0, 0.0, 0.0)):
    pytest.importorskip("OCP")
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Cut
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox, BRepPrimAPI_MakeCylinder
    from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt
    ox, oy, oz = offset
    box = BRepPrimAPI_MakeBox(gp_Pnt(ox, oy, oz), a, b, c).Shape()
    cyl = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(ox + centre[0], oy + centre[1], oz - 1), gp_Dir(0, 0, 1)), r,
                                   c + 2).Shape()
    cut = BRepAlgoAPI_Cut(box, cyl)
    cut.Build()
    return cut.Shape()


@pytest.mark.parametrize("offset", [(0.0, 0.0, 0.0), (10.0, -20.0, 5.0)])
def test_block_with_a_round_hole(offset):
    """Six faces, two of them (top and bottom) trimmed by the hole, the hole a
    cylindrical face: the volume a b c - pi r^2 c, the area 2 (a b - pi r^2) + 2 (a + b) c
    + 2 pi r c; BRepGProp agrees. Away from the origin too."""
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps
    from cagd.occ import from_occ, subshapes
    a, b, c, r = 3.0, 2.0, 1.0, 0.4
    solid = block_with_a_hole(a, b, c, r, offset=offset)
    from OCP.TopAbs import TopAbs_FACE
    faces = [from_occ(f) for f in subshapes(solid, TopAbs_FACE)]
    assert sum(isinstance(f, TrimmedSurface) for f in faces) >= 2
    volume = enclosed_volume(faces)
    exact = a * b * c - math.pi * r * r * c
    assert abs(volume.value) == pytest.approx(exact, rel=1e-10)
    assert volume.error <= 1e-9 * exact
    props = GProp_GProps()
    BRepGProp.VolumeProperties_s(solid, props)
    assert abs(volume.value) == pytest.approx(props.Mass(), rel=1e-9)
    area = total_area(faces).value
    assert area == pytest.approx(2 * (a * b - math.pi * r * r) + 2 * (a + b) * c + 2 * math.pi * r * c, rel=1e-10)


def test_volume_sign_follows_the_normals_whichever_direction_is_integrated():
    """A cube whose top face is trimmed to its whole square: the same volume as the
    untrimmed cube; the trimmed top integrated along u or v (exchanged) gives the same
    signed contribution."""
    from cagd.surfaces.trimmed import _area
    P = np.array([[[0, 0, 1], [0, 1, 1]], [[1, 0, 1], [1, 1, 1]]], float)
    top = cagd.BSplineSurface(P, 1, 1)
    ts = TrimmedSurface(top, [rectangle(0, 1, 0, 1)])
    c = np.array([0.5, 0.5, 0.5])
    by_u = _area(ts, 1e-12, c).value
    by_v = -_area(ts._exchanged(), 1e-12, c).value
    assert by_u == pytest.approx(by_v, rel=1e-12) and by_u == pytest.approx(1 / 6, rel=1e-12)
