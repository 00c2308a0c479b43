"""The surface intersection benchmark runs at a tiny size (no timing asserted): the
engine's curves lie within tol of both patches, and the OCCT peer runs when OCP is there."""
import numpy as np

from benchmarks import surface_intersection as bench


def test_surface_intersection_benchmark_runs(capsys):
    assert bench.main(["--size", "5", "--repeat", "1"]) == 0
    out = capsys.readouterr().out
    assert "engine curves within tol of both surfaces" in out
    try:
        import OCP  # noqa: F401
        assert "time engine / OCCT" in out
    except ImportError:
        assert "OCP not installed" in out


def test_model_patches_cross():
    a, b = bench.model_patches(6)
    res = bench.intersect(a, b, tol=1e-6)
    assert res.curves and all(br.max_distance <= 1e-6 for br in res.curves)
    P = np.concatenate([br.curve(np.linspace(*br.curve.domain, 50)) for br in res.curves])
    assert bench.max_distance([P], a, b) <= 1e-6
