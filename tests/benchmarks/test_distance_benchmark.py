"""The min_distance benchmark runs (one repeat, no timing asserted) and every case meets its
closed form: converged, within 1e-9, the exact value certified, the expected isolated flag."""
from benchmarks import distance


def test_distance_benchmark_runs_and_meets_the_closed_forms(capsys):
    assert distance.main(["--repeat", "1"]) == 0
    assert "every case converged to its closed form" in capsys.readouterr().out
