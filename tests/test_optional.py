"""Without matplotlib (``pip install cagd`` without the plot extra) the commands that
draw stop before any work with exit code 2, naming the option and the install command,
and write nothing; before, ``cagd fit --png`` fitted, then failed on the import with a
ModuleNotFoundError and wrote nothing."""
import sys

import numpy as np
import pytest

import cagd
from cagd import _optional
from cagd.cli import main


@pytest.fixture
def no_matplotlib(monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib", None)      # import matplotlib raises ImportError


@pytest.fixture
def inputs(tmp_path):
    s = np.linspace(0, 1, 50)
    P = np.stack([100 * s, 20 * np.sin(7 * s), 5 * np.cos(3 * s)], axis=1)
    pts = tmp_path / "pts.csv"
    np.savetxt(pts, P, delimiter=",")
    u, v = np.meshgrid(np.linspace(0, 10, 8), np.linspace(0, 10, 8), indexing="ij")
    grid = tmp_path / "grid.csv"
    np.savetxt(grid, np.stack([u, v, np.sin(u / 3) * np.cos(v / 4)], -1).reshape(-1, 3), delimiter=",")
    model = tmp_path / "fit.json"                                     # a surface: cagd plot's input
    assert main(["fit", str(grid), "--surface", "--tol", "0.01", "-o", str(model)]) == 0
    return grid, model


@pytest.mark.parametrize("command, option", [
    (["fit", "{pts}", "--tol", "0.01", "-o", "{out}.json", "--png", "{out}.png"], "--png"),
    (["deviation", "{model}", "{pts}", "-o", "{out}.md"], "--png"),
    (["plot", "--analysis", "gaussian", "{model}", "-o", "{out}.png"], "--output"),
])
def test_drawing_without_matplotlib_is_refused_first(command, option, inputs, tmp_path, capsys, no_matplotlib):
    pts, model = inputs
    out = tmp_path / "result"
    argv = [a.format(pts=pts, model=model, out=out) for a in command]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert f"{option}: needs matplotlib" in err and "pip install 'cagd[plot]'" in err, err
    assert not list(tmp_path.glob("result*"))


def test_require(no_matplotlib):
    _optional.require("numpy", "--anything")
    with pytest.raises(cagd.CagdError, match=r"--x: needs matplotlib.*cagd\[plot\]"):
        _optional.require("matplotlib", "--x")
