"""``cagd plot --analysis``: the pictures are written (atomically, PNG) and show what the
maps say: a sphere's Gaussian map is one colour (the top of the symmetric range), a
torus's has both signs; bad input is exit 2 with nothing written."""
import json

import numpy as np
import pytest

from cagd.cli import main

pytest.importorskip("matplotlib")


def model(tmp_path, obj):
    path = tmp_path / "m.json"
    path.write_text(json.dumps({"format": "cagd-model", "version": 1, "units": "mm",
                                "objects": [dict(name="s", **obj)]}))
    return path


def colours(png):
    import matplotlib.image
    from matplotlib import colormaps
    img = matplotlib.image.imread(png)[..., :3]
    img = img[:, :int(0.7 * img.shape[1])]          # the view, without the colour bar on the right
    cmap = colormaps["coolwarm"]
    red, blue = np.asarray(cmap(1.0)[:3]), np.asarray(cmap(0.0)[:3])
    near = lambda c: np.all(np.abs(img - c) < 0.02, axis=-1)  # noqa: E731
    return int(near(red).sum()), int(near(blue).sum())


def test_sphere_gaussian_map_is_uniform(tmp_path, capsys):
    out = tmp_path / "k.png"
    assert main(["plot", "--analysis", "gaussian", str(model(tmp_path, {"type": "sphere", "radius": 10.0})),
                 "-o", str(out), "--samples", "30"]) == 0
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    red, blue = colours(out)
    assert red > 2000 and blue < 50          # K = 1/R^2 everywhere: the top colour of (-K, K)


def test_torus_gaussian_map_changes_sign(tmp_path):
    out = tmp_path / "k.png"
    assert main(["plot", "--analysis", "gaussian", str(model(tmp_path, {"type": "torus", "R": 10.0, "r": 4.0})),
                 "-o", str(out), "--samples", "40", "--range", "-0.01", "0.01"]) == 0
    red, blue = colours(out)
    # K = 1/(r(R + r)) = 0.018 outside, -1/(r(R - r)) = -0.042 inside, both beyond the range: the two ends
    assert red > 200 and blue > 200


@pytest.mark.parametrize("kind", ["mean", "max", "min", "zebra", "isophotes", "draft"])
def test_every_analysis_writes_a_png(tmp_path, kind):
    out = tmp_path / f"{kind}.png"
    assert main(["plot", "--analysis", kind, "demo", "--object", "bicubic_patch", "-o", str(out),
                 "--samples", "12"]) == 0
    assert out.read_bytes()[:4] == b"\x89PNG"


@pytest.mark.parametrize("args, word", [
    (["--samples", "1"], "--samples"),
    (["--object", "nope"], "--object"),
    (["--range", "1", "0"], "--range"),
    (["--analysis", "zebra", "--stripes", "0"], "stripes"),
    (["--analysis", "zebra", "--light", "0", "0", "0"], "direction"),
])
def test_bad_input_is_exit_2_and_writes_nothing(tmp_path, capsys, args, word):
    out = tmp_path / "x.png"
    argv = ["plot", "demo", "-o", str(out)] + args
    if "--analysis" not in args:
        argv += ["--analysis", "gaussian"]
    assert main(argv) == 2
    assert word in capsys.readouterr().err and not out.exists()
