"""The benchmarks run (tiny sizes, no timing asserted) and their peers agree with the engine."""
import pytest

from benchmarks import bspline_eval, surface_grid


def test_curve_benchmark_runs_and_agrees(capsys):
    pytest.importorskip("scipy")
    assert bspline_eval.main(["--points", "3000", "--repeat", "1", "--subsample", "50"]) == 0
    assert "within 1e-12 of the engine" in capsys.readouterr().out


def test_surface_benchmark_runs_and_agrees(capsys):
    pytest.importorskip("scipy")
    assert surface_grid.main(["--grid", "40", "--repeat", "1", "--subsample", "50"]) == 0
    assert "within 1e-12 of the engine" in capsys.readouterr().out
