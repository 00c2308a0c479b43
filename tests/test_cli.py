"""``cagd demo`` on the built-in model and ``cagd export MODEL.json``: files written,
read back by OCCT, the report's verdict, exit codes, messages naming the JSON path."""
import json
from pathlib import Path
import re

import numpy as np
import pytest

from cagd.cli import main

pytest.importorskip("OCP")
from cagd.model import DEFAULT_MODEL_PATH, load_model  # noqa: E402
from cagd.occ import read_iges, read_step  # noqa: E402


@pytest.fixture(scope="module")
def demo(tmp_path_factory):
    out = tmp_path_factory.mktemp("demo")
    code = main(["demo", "-o", str(out)])
    return code, out


def test_demo_writes_step_iges_report_and_pictures(demo, capsys):
    code, out = demo
    assert code == 0
    model = load_model(DEFAULT_MODEL_PATH)
    exported = model.exported()
    names = {label for e in exported for label, _ in e.labels() if not e.solid} | {e.name for e in exported if e.solid}
    for path, read in ((out / "model.step", read_step), (out / "model.igs", read_iges)):
        back = read(path)
        # every face/curve comes back, under its entry's name
        assert {b.name.split("[")[0] for b in back} == names
        faces = [b for b in back if hasattr(b.object, "degree_u")]
        assert len(faces) == sum(len(e.objects) for e in exported if e.kind == "surface")
    report = (out / "report.md").read_text()
    assert "**all checks passed**" in report
    # one table row per object and stage, none failing
    assert report.count("| occt |") == sum(len(e.objects) for e in exported)
    assert "**NO**" not in report
    pngs = sorted(out.glob("model_*.png"))
    assert len(pngs) == len(model.entries)


def test_demo_pictures_show_the_model(demo):
    import matplotlib.image as mpimg
    _, out = demo
    for png in sorted(out.glob("model_*.png")):
        img = mpimg.imread(png)[..., :3]
        # shaded surfaces are tab:blue scaled by the light; curves tab:blue exactly
        blue = (img[..., 2] > img[..., 0] + 0.15) & (img[..., 2] > 0.25)
        assert blue.sum() > 500, png.name


def test_demo_solid_volumes(demo):
    _, out = demo
    report = (out / "report.md").read_text()
    rows = re.findall(r"^\| (\w+) \| (\d+) \| yes \| ([\d.]+) \| ([\d.]+) \| ([\d.e+-]+) \|", report, re.M)
    assert {r[0] for r in rows} == {"ellipsoid", "knob"}
    ell = next(r for r in rows if r[0] == "ellipsoid")
    a, b, c = (load_model(DEFAULT_MODEL_PATH)["ellipsoid"].source[k] for k in "abc")
    exact = 4 / 3 * np.pi * a * b * c
    assert int(ell[1]) == 8
    assert abs(float(ell[3]) - exact) / exact < 1e-9       # printed to 10 digits
    assert abs(float(ell[2]) - exact) / exact < 1e-9       # OCCT's volume
    assert float(ell[4]) < 1e-9


def small_model(**extra):
    doc = {"format": "cagd-model", "version": 1, "units": "mm", "name": "t", "objects": [
        {"name": "arc", "type": "bspline_curve", "degree": 2,
         "control_points": [[0, 0, 0], [10, 10, 0], [20, 0, 0]], "weights": [1, 0.5, 1]},
        {"name": "ball", "type": "sphere", "radius": 5.0, "solid": True},
    ]}
    doc.update(extra)
    return doc


def test_export_writes_files_and_report(tmp_path, capsys):
    src = tmp_path / "m.json"
    src.write_text(json.dumps(small_model()))
    step, igs, rep = tmp_path / "m.step", tmp_path / "m.igs", tmp_path / "r.md"
    assert main(["export", str(src), "-o", str(step), "--iges", str(igs), "--report", str(rep),
                 "--no-progress"]) == 0
    text = step.read_text()
    assert "PRODUCT('arc'" in text and "PRODUCT('ball'" in text
    assert "SI_UNIT(.MILLI.,.METRE.)" in text
    back = {b.name: b.object for b in read_step(step)}
    t = np.linspace(0, 1, 7)
    m = load_model(src)
    assert np.abs(back["arc"](t)[:, :2] - m["arc"].objects[0](t)[:, :2]).max() == 0.0   # 17 digits: bit-exact
    report = rep.read_text()
    assert "**all checks passed**" in report and "| ball |" in report
    assert abs(float(re.search(r"\| ball \| \d+ \| yes \| ([\d.]+)", report).group(1)) - 4 / 3 * np.pi * 125) < 1e-6


@pytest.mark.parametrize("change, path", [
    ({"version": 99}, "$.version"),
    ({"objects": [{"name": "x", "type": "bspline_curve", "degree": "three",
                   "control_points": [[0, 0, 0], [1, 1, 1]]}]}, "$.objects[0].degree"),
    ({"objects": [{"name": "x", "type": "bezier_curve", "control_points": [[0, 0, 0], [1, 1]]}]},
     "$.objects[0].control_points[1]"),
])
def test_export_bad_model_exits_2_naming_the_json_path(tmp_path, capsys, change, path):
    src = tmp_path / "bad.json"
    src.write_text(json.dumps(small_model(**change)))
    assert main(["export", str(src), "-o", str(tmp_path / "x.step"), "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert path in err
    assert not (tmp_path / "x.step").exists()


def test_export_missing_or_broken_file_exits_2(tmp_path, capsys):
    assert main(["export", str(tmp_path / "none.json"), "-o", str(tmp_path / "x.step")]) == 2
    assert "none.json" in capsys.readouterr().err
    broken = tmp_path / "broken.json"
    broken.write_text('{"format": "cagd-model", "version": 1, "objects": [')
    assert main(["export", str(broken), "-o", str(tmp_path / "x.step")]) == 2
    assert "$" in capsys.readouterr().err


def test_export_open_surfaces_marked_solid_exit_2(tmp_path, capsys):
    # a full turn of a segment off the axis: a tube, open at both ends
    doc = small_model(objects=[{"name": "tube", "type": "revolve", "solid": True,
                                "profile": {"type": "bspline_curve", "degree": 1,
                                            "control_points": [[5, 0, 0], [5, 0, 10]]}}])
    src = tmp_path / "open.json"
    src.write_text(json.dumps(doc))
    assert main(["export", str(src), "-o", str(tmp_path / "x.step"), "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert "$.objects[0].solid" in err and "axis" in err


def test_progress_bar_on_stderr(tmp_path, capsys):
    src = tmp_path / "m.json"
    src.write_text(json.dumps(small_model()))
    assert main(["export", str(src), "-o", str(tmp_path / "m.step")]) == 0
    err = capsys.readouterr().err
    lines = [ln for ln in err.splitlines() if ln.startswith("[")]
    assert lines[-1].startswith("[" + "#" * 24 + "]") and re.search(r"(\d+)/\1 ", lines[-1])


@pytest.mark.parametrize("model", sorted((Path(__file__).parents[1] / "examples" / "models").glob("*.json")),
                         ids=lambda p: p.stem)
def test_example_models_export_and_pass_their_checks(model, tmp_path):
    assert main(["export", str(model), "-o", str(tmp_path / "m.step"), "--iges", str(tmp_path / "m.igs"),
                 "--report", str(tmp_path / "r.md"), "--no-progress"]) == 0
    assert "**all checks passed**" in (tmp_path / "r.md").read_text()
