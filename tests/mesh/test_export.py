"""STL/OBJ export (issue 15): OCCT's RWStl re-reads our STL with the same triangle
count and area; OBJ parsed back by an independent parser; the mesh area of a disk
converges to pi r^2; chordal deviation reported; errors name the argument."""
import math

import numpy as np
import pytest

import cagd
from cagd import CagdError, TrimmedSurface
from cagd.mesh import write_obj, write_stl
from trim_shapes import circle, curved_patch, square_patch  # noqa: F401


def _area(V, T):
    p = V[T]
    return 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1).sum()


def _disk(r=0.3):
    return TrimmedSurface(square_patch(), [[circle((0.5, 0.5), r)]])


def test_disk_mesh_area_converges():
    ts = _disk()
    m = cagd.mesh.mesh(ts, tol=1e-4)
    assert _area(m.vertices, m.triangles) == pytest.approx(ts.area(), rel=2e-3)
    assert ts.area() == pytest.approx(4 * math.pi * 0.3 ** 2, rel=1e-6)  # square_patch() spans 2 x 2


@pytest.mark.parametrize("binary", [True, False])
def test_stl_reread_by_occt(tmp_path, binary):
    OCP = pytest.importorskip("OCP")  # noqa: F841
    from OCP.RWStl import RWStl
    from OCP.TCollection import TCollection_AsciiString  # noqa: F401
    ts = _disk()
    path = tmp_path / "d.stl"
    m = write_stl(path, [ts, square_patch()], tol=1e-3, binary=binary)
    tri = RWStl.ReadFile_s(str(path))
    assert tri.NbTriangles() == len(m.triangles)
    nodes = np.array([[tri.Node(i).X(), tri.Node(i).Y(), tri.Node(i).Z()] for i in range(1, tri.NbNodes() + 1)])
    T = np.array([tri.Triangle(i).Get() for i in range(1, tri.NbTriangles() + 1)]) - 1
    assert _area(nodes, T) == pytest.approx(_area(m.vertices, m.triangles), rel=1e-5)


def test_obj_parsed_back(tmp_path):
    ts = _disk()
    path = tmp_path / "d.obj"
    m = write_obj(path, ts, tol=1e-3)
    V, F = [], []
    for line in path.read_text().splitlines():
        w = line.split()
        if w and w[0] == "v":
            V.append([float(x) for x in w[1:4]])
        elif w and w[0] == "f":
            F.append([int(x) - 1 for x in w[1:4]])
    assert len(F) == len(m.triangles) and np.allclose(np.array(V), m.vertices, rtol=0, atol=1e-15)
    assert _area(np.array(V), np.array(F)) == pytest.approx(_area(m.vertices, m.triangles), rel=1e-12)
    assert m.converged and m.max_error <= 1e-3


def test_errors_name_the_argument(tmp_path):
    with pytest.raises(CagdError, match="tol"):
        write_stl(tmp_path / "a.stl", _disk(), tol=-1)
    with pytest.raises(CagdError, match="geometry"):
        write_stl(tmp_path / "a.stl", [])
    with pytest.raises(CagdError, match="geometry"):
        write_obj(tmp_path / "a.obj", [3])
    with pytest.raises(CagdError, match="path"):
        write_stl(tmp_path / "nofolder" / "a.stl", _disk())
