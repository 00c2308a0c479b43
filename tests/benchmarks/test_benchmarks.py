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


def test_trimmed_benchmark_runs(capsys):
    """benchmarks/trimmed.py at tiny sizes: it runs, and the engine's contains agrees with
    BRepClass_FaceClassifier on the points it compares (where OCCT is installed)."""
    from benchmarks import trimmed
    assert trimmed.main(["--points", "2000", "--occt-points", "200", "--closest", "300"]) == 0
    out = capsys.readouterr().out
    assert "contains:" in out and "closest, points over the face" in out
    if "BRepClass_FaceClassifier" in out:
        assert "same answer on 100.0000%" in out


def test_setup_benchmark_runs(capsys):
    """benchmarks/setup.py at tiny sizes: it runs, an equal object finds its projector by
    content, and (where OCCT is installed) the engine is never farther than OCCT."""
    from benchmarks import setup
    assert setup.main(["--points", "2", "--repeat", "1"]) == 0
    out = capsys.readouterr().out
    assert "bumpy 50 x 50" in out and "light set-up" in out


def test_gordon_benchmark_runs(capsys):
    """benchmarks/gordon.py on one small network: it runs, cagd.gordon converges with the
    network within its max_error (the exit code), and build123d's row prints where present."""
    from benchmarks import gordon
    assert gordon.main(["--sizes", "3x3", "--points", "30", "--tol", "1e-4", "--repeat", "1", "--samples", "50",
                        "--occt8-python", "none"]) == 0
    out = capsys.readouterr().out
    assert "cagd.gordon" in out and "3x3 x8" in out          # the sparse network too
    try:
        import build123d  # noqa: F401
    except ImportError:
        return
    assert "build123d make_gordon" in out


def _corpus():
    """The CAD corpus (../shared/data/cad beside the checkout, or beside the main one for a
    clone elsewhere) holding occ22470.igs; skips without it or without OCCT."""
    pytest.importorskip("OCP")
    from corpus import CAD as folder
    if not (folder / "iges" / "occ22470.igs").exists():
        pytest.skip("the CAD corpus is not here")
    return folder


def test_trimmed_benchmark_on_real_faces(capsys, monkeypatch):
    """benchmarks/trimmed.py's real faces (the corpus in ../shared/data/cad, skipped
    without it or OCCT): two faces of occ22470.igs, a few points; every query converges
    (the thin face whose loop starts 4.3e-8 from the domain's corner reached the work
    bound after 30 s)."""
    from benchmarks import trimmed
    folder = _corpus()
    monkeypatch.setattr(trimmed, "REAL_FACES", (("occ22470.igs", 2),))
    trimmed.bench_real_faces(folder, 200, [0.1])
    out = capsys.readouterr().out
    assert "closest, occ22470.igs (2 faces" in out and "not converged" not in out, out


def test_many_objects_benchmark_runs(capsys):
    """benchmarks/many_objects.py at tiny sizes: it runs, and the 4-surface answers equal
    the 1-surface ones bit for bit where the first surface owns every point, closest_point's
    the unsigned deviation's (main returns 1 otherwise)."""
    from benchmarks import many_objects
    assert many_objects.main(["--layout", "apart", "--points", "1", "5", "--repeat", "1"]) == 0
    out = capsys.readouterr().out
    assert out.count("True") == 2


def test_sliver_benchmark_runs(capsys):
    """benchmarks/closest_sliver.py at a tiny size: it runs and every certificate is within
    1e-6 of the distance (the strips of issue 16, points 1e-7..1e-3 of the size off: the
    nearest 1e-6 mm away, certified to 1e-13 of the size plus 1e-10 of the distance)."""
    from benchmarks import closest_sliver
    assert closest_sliver.main(["--points", "50", "--repeat", "1"]) == 0
    lines = [line for line in capsys.readouterr().out.splitlines() if line.startswith("strip")]
    assert len(lines) == 6
    assert all(float(line.rsplit(" ", 1)[1]) <= 1e-6 for line in lines), lines


def test_real_faces_benchmark_runs(capsys):
    """benchmarks/real_faces.py on two faces of occ22470.igs (the corpus, skipped without
    it or OCCT), a few points: every engine distance is at most OCCT's + 1e-9 (the exit
    code) and no point is left unconverged."""
    from benchmarks import real_faces
    folder = _corpus()
    assert real_faces.main(["--cad", str(folder), "--files", "iges/occ22470.igs", "--faces", "2", "--points", "60",
                            "--subsample", "10", "--spread", "0.01", "0.1"]) == 0
    rows = [line.split() for line in capsys.readouterr().out.splitlines() if line.strip().endswith("yes")]
    assert len(rows) == 2 and all(r[1] == "2" and r[7] == "0" for r in rows), rows


def test_fitting_benchmark_curve_rows_run(capsys):
    """benchmarks/fitting.py, the curve rows at one tol: the engine's fit meets it (the
    exit status), and beside OCCT (where installed) its time and CPU ratios are printed."""
    from benchmarks import fitting
    assert fitting.main(["--tols", "0.001", "--no-surface"]) == 0
    out = capsys.readouterr().out
    assert "cagd.fit_curve" in out
    if "OCCT PointsToBSpline" in out:
        assert "engine/OCCT: poles" in out and "(CPU " in out
