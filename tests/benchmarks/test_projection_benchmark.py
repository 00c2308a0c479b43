"""The projection benchmark runs at a tiny size (no timing asserted) and the engine's
distances are never above OCCT's (Extrema_ExtPS, GeomAPI_ProjectPointOnSurf) + 1e-9."""
import pytest

from benchmarks import projection


def test_projection_benchmark_runs_and_agrees_with_occt(capsys):
    pytest.importorskip("OCP")
    assert projection.main(["--points", "400", "--repeat", "1", "--subsample", "40"]) == 0
    out = capsys.readouterr().out
    assert "every engine distance <= OCCT's + 1e-9" in out
    assert "engine / faster OCCT path" in out


def test_projection_benchmark_at_other_distances(capsys):
    """--spread: points near and far (0.1% and 50% of the size), a row per surface and
    distance, every distance within OCCT's + 1e-9 and converged."""
    pytest.importorskip("OCP")
    assert projection.main(["--points", "200", "--repeat", "1", "--subsample", "20", "--spread", "0.001", "0.5"]) == 0
    out = capsys.readouterr().out
    assert "rational (weights 0.7..1.3), +-0.1%" in out and "rational (weights 0.7..1.3), +-50.0%" in out


def test_benchmark_points_lie_within_one_percent():
    import numpy as np
    s = projection.model_surface()
    X = projection.scattered_points(s, 500)
    r = projection.closest_point(s, X)
    assert np.all(r.distances <= 0.01 * np.sqrt(3) * s.size + 1e-15)
    assert r.converged and r.point_converged.all()
