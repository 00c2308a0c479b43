"""The main job: ``cagd demo`` runs every seed example, checks it and draws it."""
import numpy as np
import pytest

from cagd import BSplineCurve
from cagd.cli import main
from cagd.demo import EXAMPLES, run_demo
from cagd.plotting import curvature_comb


def test_every_example_meets_its_tolerance(tmp_path, capsys):
    results = run_demo(tmp_path, plots=False)
    assert len(results) == len(EXAMPLES) >= 7
    bad = [(r.example.name, r.deviation) for r in results if not r.passed]
    assert not bad
    table = capsys.readouterr().out
    for r in results:
        assert r.example.name in table


def test_cli_writes_pngs_showing_the_curve(tmp_path):
    pytest.importorskip("matplotlib")
    assert main(["demo", "-o", str(tmp_path), "--no-model"]) == 0
    pngs = sorted(tmp_path.glob("*.png"))
    assert len(pngs) == len(EXAMPLES)
    import matplotlib.image as mpimg
    img = mpimg.imread(pngs[0])[..., :3]
    # the curve is drawn in matplotlib's tab:blue (#1f77b4): its pixels must be there
    blue = np.all(np.abs(img - np.array([0x1F, 0x77, 0xB4]) / 255.0) < 0.06, axis=-1)
    assert blue.sum() > 300


def test_cli_rejects_unknown_command():
    with pytest.raises(SystemExit) as exc:
        main(["nope"])
    assert exc.value.code == 2


def test_curvature_comb_of_circle_points_outward_by_curvature():
    s = np.sqrt(0.5)
    P = [[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1], [1, 0]]
    circle = BSplineCurve(P, 2, [0, 0, 0, .25, .25, .5, .5, .75, .75, 1, 1, 1], [1, s, 1, s, 1, s, 1, s, 1])
    base, tips = curvature_comb(circle, samples=50, scale=0.5)
    # curvature 1 everywhere: every tooth has length 0.5 and points away from the centre
    assert np.allclose(np.linalg.norm(base, axis=1), 1.0, atol=1e-14)
    assert np.allclose(np.linalg.norm(tips, axis=1), 1.5, atol=1e-12)
