"""Trims read on first use (read_step/read_iges defer_trims): the same TrimmedSurface
as converting at once, a box boundary still the plain surface."""
import pickle
import warnings

import numpy as np
import pytest

pytest.importorskip("OCP")

import cagd  # noqa: E402
from cagd.occ import read_iges, read_step, write_iges, write_step  # noqa: E402
from tests.trim_shapes import circle, square_patch  # noqa: E402


def _same(a, b):
    assert a.tol == b.tol and a.reoriented == b.reoriented and len(a.loops) == len(b.loops)
    for la, lb in zip(a.loops, b.loops):
        for c, d in zip(la, lb):
            assert np.array_equal(c.control_points, d.control_points) and np.array_equal(c.knots, d.knots)


@pytest.mark.parametrize("fmt", ["step", "iges"])
def test_deferred_trim_equals_eager(tmp_path, fmt):
    disk = cagd.TrimmedSurface(square_patch(), [[circle((0.5, 0.5), 0.3)]])
    path = tmp_path / f"disk.{'stp' if fmt == 'step' else 'igs'}"
    (write_step if fmt == "step" else write_iges)([disk, square_patch()], path)
    read = read_step if fmt == "step" else read_iges
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        lazy, eager = read(path), read(path, defer_trims=False)
    kinds = sorted(type(i.object).__name__ for i in lazy)
    assert kinds == sorted(type(i.object).__name__ for i in eager) == ["BSplineSurface", "TrimmedSurface"]
    ts = next(i.object for i in lazy if isinstance(i.object, cagd.TrimmedSurface))
    ref = next(i.object for i in eager if isinstance(i.object, cagd.TrimmedSurface))
    assert ts.deferred and "first use" in repr(ts)
    assert ts.area() == pytest.approx(ref.area(), rel=1e-12)     # first use converts
    assert not ts.deferred
    _same(ts, ref)
    assert abs(ts.area() - np.pi * 0.09 * 4) < 1e-6


def test_deferred_trim_pickles_converted(tmp_path):
    disk = cagd.TrimmedSurface(square_patch(), [[circle((0.5, 0.5), 0.3)]])
    path = tmp_path / "disk.stp"
    write_step([disk], path)
    ts = read_step(path)[0].object
    assert ts.deferred
    back = pickle.loads(pickle.dumps(ts))
    assert not back.deferred and not ts.deferred
    _same(back, ts)
    with pytest.raises(AttributeError):
        ts.no_such_attribute
