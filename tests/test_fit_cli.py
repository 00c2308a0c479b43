"""``cagd fit points.csv --tol T -o OUT`` (issue 17): the written curve is the fit (STEP,
IGES and JSON read back to the same curve), every point within tol of what was written
(certified closest points on the re-read curve), tol not met is exit code 1 with the fit
still written, bad input is exit code 2 with nothing written."""
import numpy as np
import pytest

import cagd
from cagd.cli import main


def points_file(tmp_path, n=500):
    s = np.linspace(0, 1, n)
    P = np.stack([100 * s, 20 * np.sin(7 * s), 5 * np.cos(3 * s)], axis=1)
    path = tmp_path / "pts.csv"
    np.savetxt(path, P, delimiter=",", header="x,y,z", comments="")
    return path, P


def test_json_output_is_the_fit(tmp_path, capsys):
    pts, P = points_file(tmp_path)
    out = tmp_path / "fit.json"
    assert main(["fit", str(pts), "--tol", "0.01", "-o", str(out), "--report", str(tmp_path / "r.md")]) == 0
    curve, = cagd.model.load_model(out)["fit"].objects
    direct = cagd.fit_curve(P, 0.01).curve
    assert np.array_equal(curve.control_points, direct.control_points)
    assert np.array_equal(curve.knots, direct.knots)
    assert float(cagd.closest_point(curve, P).distances.max()) <= 0.01
    text = (tmp_path / "r.md").read_text()
    assert "every point within tol" in text and f"{len(direct.control_points)} control points" in text
    assert "every point within tol" in capsys.readouterr().out


@pytest.mark.parametrize("suffix", [".step", ".igs"])
def test_step_and_iges_read_back_to_the_fit(tmp_path, suffix):
    pytest.importorskip("OCP")
    from cagd.occ import read_iges, read_step
    pts, P = points_file(tmp_path)
    out = tmp_path / f"fit{suffix}"
    png = tmp_path / "fit.png"
    assert main(["fit", str(pts), "--tol", "0.01", "-o", str(out), "--png", str(png)]) == 0
    items = list((read_step if suffix == ".step" else read_iges)(out))
    assert len(items) == 1
    back = items[0].object
    direct = cagd.fit_curve(P, 0.01).curve
    t = np.linspace(0, 1, 1001)
    a, b = back.domain
    assert np.abs(back(a + t * (b - a)) - direct(t)).max() <= 1e-9
    assert float(cagd.closest_point(back, P).distances.max()) <= 0.01 + 1e-9
    from PIL import Image
    img = np.asarray(Image.open(png).convert("RGB")).astype(int)
    red = (img[..., 0] > 180) & (img[..., 1] < 90) & (img[..., 2] < 90)      # the fit, drawn in red
    assert red.sum() > 200


def test_tol_not_met_is_exit_1_and_says_so(tmp_path, capsys):
    pts, _ = points_file(tmp_path)
    out = tmp_path / "fit.json"
    assert main(["fit", str(pts), "--tol", "1e-9", "--max-poles", "10", "-o", str(out)]) == 1
    assert out.exists()
    text = capsys.readouterr().out
    assert "TOL NOT MET" in text and "points over tol" in text


@pytest.mark.parametrize("args, word", [
    (["--tol", "-1", "-o", "fit.json"], "tol"),
    (["--tol", "0.1", "-o", "fit.txt"], "--output"),
    (["--tol", "0.1", "-o", "fit.json", "--degree", "0"], "degree"),
    (["--tol", "0.1", "-o", "fit.json", "--png", "fit.jpg"], "--png"),
    (["--tol", "0.1", "-o", "fit.json", "--parameters", "arc"], "parameters"),
])
def test_bad_input_is_exit_2_and_writes_nothing(tmp_path, capsys, args, word):
    pts, _ = points_file(tmp_path)
    args = [a if not a.startswith("fit.") else str(tmp_path / a) for a in args]
    assert main(["fit", str(pts)] + args) == 2
    err = capsys.readouterr().err
    assert err.startswith("cagd fit: ") and word in err
    assert not list(tmp_path.glob("fit.*"))


def test_periodic_flag(tmp_path, capsys):
    phi = np.linspace(0, 2 * np.pi, 300, endpoint=False)
    pts = tmp_path / "ring.csv"
    np.savetxt(pts, np.stack([5 * np.cos(phi), 3 * np.sin(phi)], axis=1), delimiter=",")
    out = tmp_path / "ring.json"
    assert main(["fit", str(pts), "--tol", "0.001", "--periodic", "-o", str(out)]) == 0
    curve, = cagd.model.load_model(out)["fit"].objects
    assert curve.periodic
    assert "periodic (closed)" in capsys.readouterr().out


def test_surface_flag_fits_scattered_points(tmp_path, capsys):
    pytest.importorskip("OCP")
    from cagd.occ import read_step
    rng = np.random.default_rng(2)
    X, Y = rng.random(3000) * 50, rng.random(3000) * 50
    P = np.stack([X, Y, 2 * np.sin(X / 10) * np.cos(Y / 15)], axis=1)
    pts = tmp_path / "scan.csv"
    np.savetxt(pts, P, delimiter=",")
    out, png = tmp_path / "sheet.step", tmp_path / "sheet.png"
    assert main(["fit", str(pts), "--tol", "0.01", "--surface", "-o", str(out), "--png", str(png)]) == 0
    face = list(read_step(out))[0].object
    assert float(cagd.closest_point(face, P).distances.max()) <= 0.01 + 1e-9
    assert "surface: degree 3 x 3" in capsys.readouterr().out and png.stat().st_size > 10_000
    assert main(["fit", str(pts), "--tol", "0.01", "--surface", "--periodic", "-o", str(out)]) == 2


def test_surface_degree_auto_is_the_engines_choice(tmp_path, capsys):
    """``--surface --degree auto``: the written surface is fit_surface(..., degree="auto")'s,
    whose degree is the one of AUTO_DEGREES with the fewest control points among the
    converged fits (each degree fitted on its own here), every point within tol of it."""
    from cagd.fitting.fit_surface import AUTO_DEGREES
    rng = np.random.default_rng(5)
    X, Y = rng.random(600) * 40, rng.random(600) * 30
    P = np.stack([X, Y, 3 * np.sin(X / 9) * np.cos(Y / 7)], axis=1)
    pts = tmp_path / "scan.csv"
    np.savetxt(pts, P, delimiter=",")
    out = tmp_path / "sheet.json"
    assert main(["fit", str(pts), "--tol", "0.02", "--surface", "--degree", "auto", "-o", str(out)]) == 0
    surface, = cagd.model.load_model(out)["fit"].objects
    direct = cagd.fit_surface(P, 0.02, degree="auto").surface
    assert np.array_equal(surface.control_points, direct.control_points)
    each = {p: cagd.fit_surface(P, 0.02, degree=p) for p in AUTO_DEGREES}
    fewest = min((f.surface.control_points[..., 0].size, p) for p, f in each.items() if f.converged)[1]
    assert (surface.degree_u, surface.degree_v) == (fewest, fewest)
    assert float(cagd.closest_point(surface, P).distances.max()) <= 0.02
    assert f"surface: degree {fewest} x {fewest}" in capsys.readouterr().out


def test_degree_auto_is_a_surface_option(tmp_path, capsys):
    """'auto' without --surface is bad input (exit 2, nothing written); a word other than
    'auto' is refused by the parser (exit 2)."""
    pts, _ = points_file(tmp_path, 50)
    out = tmp_path / "fit.json"
    assert main(["fit", str(pts), "--tol", "0.1", "--degree", "auto", "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("cagd fit: ") and "--degree" in err and "--surface" in err
    assert not out.exists()
    with pytest.raises(SystemExit) as exc:
        main(["fit", str(pts), "--tol", "0.1", "--degree", "cubic", "-o", str(out)])
    assert exc.value.code == 2 and "--degree" in capsys.readouterr().err
    assert not out.exists()
