"""``cagd deviation MODEL points.csv``: signed distances against known offsets, the
nearest of several patches, STEP input, and bad input with exit code 2."""
import json

import numpy as np
import pytest

import cagd
from cagd.cli import main
from cagd.deviation_cli import read_points


def write_model(tmp_path, objects):
    path = tmp_path / "m.json"
    path.write_text(json.dumps({"format": "cagd-model", "version": 1, "objects": objects}))
    return path


def offsets_from_sphere(tmp_path, n=300, radius=10.0):
    rng = np.random.default_rng(4)
    s = cagd.sphere(radius)
    P = s(rng.uniform(0, 1, n), rng.uniform(0, 1, n))
    d = rng.normal(0.0, 0.05, n)
    X = P * (1.0 + d / radius)[:, None]                      # moved along the radius by d
    path = tmp_path / "pts.csv"
    np.savetxt(path, X, delimiter=",", header="x,y,z", comments="")
    return path, d


def test_signed_distances_recover_the_offsets(tmp_path, capsys):
    model = write_model(tmp_path, [{"name": "ball", "type": "sphere", "radius": 10.0}])
    pts, d = offsets_from_sphere(tmp_path)
    report = tmp_path / "r.md"
    assert main(["deviation", str(model), str(pts), "-o", str(report)]) == 0
    text = report.read_text()
    rms = float(text.split("| rms | ")[1].split(" |")[0])
    assert rms == pytest.approx(np.sqrt(np.mean(d * d)), rel=1e-5)          # printed to 6 digits
    assert (tmp_path / "r.png").stat().st_size > 10_000
    from cagd.queries.deviation import deviation
    res = deviation(cagd.sphere(10.0), read_points(pts))
    # the sphere's normal points outward (or inward, consistently): the signs follow the offsets
    assert np.allclose(np.abs(res.distances), np.abs(d), atol=1e-9)
    assert np.allclose(res.distances, d, atol=1e-9) or np.allclose(res.distances, -d, atol=1e-9)


def test_nearest_of_several_patches(tmp_path):
    model = write_model(tmp_path, [{"name": "egg", "type": "ellipsoid", "a": 30, "b": 20, "c": 15}])
    patches = cagd.ellipsoid(30, 20, 15)
    rng = np.random.default_rng(2)
    X = np.concatenate([p(rng.uniform(0, 1, 20), rng.uniform(0, 1, 20)) for p in patches])
    pts = tmp_path / "on.csv"
    np.savetxt(pts, X, delimiter=";")
    assert main(["deviation", str(model), str(pts), "-o", str(tmp_path / "r.md")]) == 0
    from cagd.queries.deviation import deviation
    res = deviation(patches, X)
    assert np.abs(res.distances).max() < 1e-10                  # points on the patches
    assert np.all((res.lower_bounds <= np.abs(res.distances) + 1e-15))
    assert "egg.0 (" in (tmp_path / "r.md").read_text()


def test_step_model(tmp_path):
    pytest.importorskip("OCP")
    from cagd.occ import write_step
    write_step([("ball", cagd.sphere(10.0))], tmp_path / "ball.step")
    pts, d = offsets_from_sphere(tmp_path, n=50)
    assert main(["deviation", str(tmp_path / "ball.step"), str(pts), "-o", str(tmp_path / "r.md")]) == 0
    rms = float((tmp_path / "r.md").read_text().split("| rms | ")[1].split(" |")[0])
    assert rms == pytest.approx(np.sqrt(np.mean(d * d)), rel=1e-5)


@pytest.mark.parametrize("csv, args, message", [
    ("x,y,z\n1,2,3\n4,five,6\n", [], "line 3 is not numbers"),
    ("1,2,3\n4,5\n", [], "line 2 has 2 values"),
    ("1,2\n3,4\n", [], "2-D points against 3-D"),
    ("", [], "holds no points"),
    ("1,2,3\n", ["--object", "nope"], "--object nope"),
])
def test_bad_input_exits_2(tmp_path, capsys, csv, args, message):
    model = write_model(tmp_path, [{"name": "ball", "type": "sphere", "radius": 10.0}])
    pts = tmp_path / "p.csv"
    pts.write_text(csv)
    assert main(["deviation", str(model), str(pts), "-o", str(tmp_path / "r.md"), *args]) == 2
    assert message in capsys.readouterr().err
