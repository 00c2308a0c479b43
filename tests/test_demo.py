"""The main job: ``cagd demo`` runs every seed example, checks it and draws it."""
import numpy as np
import pytest

from cagd.cli import main
from cagd.demo import EXAMPLES, run_demo


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
