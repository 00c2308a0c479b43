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


# --- issue 14: every failure one line on stderr, exit 2, no traceback; nothing half-written ---------------
def one_line(capsys, *words):
    err = [ln for ln in capsys.readouterr().err.splitlines() if ln.strip()]
    assert len(err) == 1 and err[0].startswith("cagd ") and "Traceback" not in err[0], err
    for w in words:
        assert w in err[0], err[0]
    return err[0]


def write_doc(tmp_path, doc, name="m.json"):
    src = tmp_path / name
    src.write_text(json.dumps(doc) if isinstance(doc, dict) else doc)
    return src


CURVE_ONLY = {"objects": [{"name": "arc", "type": "bspline_curve", "degree": 2,
                           "control_points": [[0, 0, 0], [10, 10, 0], [20, 0, 0]]}]}


@pytest.mark.parametrize("entry, words", [
    ({"name": "c", "type": "bspline_curve", "degree": 1, "control_points": [[0, 0, 0], [1, 1, 0], [2, 0, 0]],
      "knots": [0, 0, 1e-300, 2e-300, 2e-300]}, ["'c'", "cannot be checked"]),
    ({"name": "c", "type": "polynomial_curve", "coefficients": [[0, 0, 0], [1, 1, 1]], "domain": [0, 1e-300]},
     ["'c'", "cannot be checked"]),
    ({"name": "s", "type": "sphere", "radius": 1e200}, ["'s'", "1e+200"]),
    ({"name": "t", "type": "torus", "R": 1.0, "r": 2.0, "solid": True}, ["$.objects[0].solid", "r >= R"]),
    ({"name": "x\ud800", "type": "sphere", "radius": 1.0}, ["$.objects[0].name", "surrogate"]),
    ({"name": "n" * 256, "type": "sphere", "radius": 1.0}, ["$.objects[0].name", "at most 255"]),
])
def test_export_of_extreme_models_exits_2_with_one_line(tmp_path, capsys, entry, words):
    """Each printed a traceback and exited 1, or (sphere 1e200, torus r > R solid)
    reported "all checks passed"."""
    src = write_doc(tmp_path, small_model(objects=[entry]))
    assert main(["export", str(src), "-o", str(tmp_path / "x.step"), "--no-progress"]) == 2
    one_line(capsys, *words)
    assert not (tmp_path / "x.step").exists()


def test_export_of_a_4301_digit_integer_exits_2(tmp_path, capsys):
    text = json.dumps(small_model(**CURVE_ONLY)).replace('"degree": 2', '"degree": 2' + "0" * 4300)
    src = write_doc(tmp_path, text)
    assert main(["export", str(src), "-o", str(tmp_path / "x.step"), "--no-progress"]) == 2
    one_line(capsys, "$.objects[0].degree", "4301 digits")


def test_export_of_a_name_with_a_newline_exits_2_in_a_child_process(tmp_path):
    """`cagd export m.json --iges x.igs` exited 139 (SIGSEGV) after overwriting the STEP."""
    import subprocess
    import sys
    src = write_doc(tmp_path, small_model(objects=[{"name": "a\nb", "type": "sphere", "radius": 1.0}]))
    step = tmp_path / "x.step"
    step.write_text("old")
    run = subprocess.run([sys.executable, "-m", "cagd.cli", "export", str(src), "-o", str(step), "--iges",
                          str(tmp_path / "x.igs"), "--no-progress"], capture_output=True, text=True, timeout=240)
    assert run.returncode == 2, (run.returncode, run.stderr[-500:])
    assert "control character" in run.stderr and "Traceback" not in run.stderr
    assert step.read_text() == "old" and not (tmp_path / "x.igs").exists()


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="no /dev/full")
def test_export_to_a_full_device_keeps_the_other_outputs(tmp_path, capsys):
    """The STEP was overwritten before the IGES write to /dev/full failed with a traceback."""
    src = write_doc(tmp_path, small_model(**CURVE_ONLY))
    step = tmp_path / "x.step"
    step.write_text("old")
    assert main(["export", str(src), "-o", str(step), "--iges", "/dev/full", "--no-progress"]) == 2
    one_line(capsys, "/dev/full", "No space left")
    assert step.read_text() == "old"
    assert main(["export", str(src), "-o", "/dev/full", "--no-progress"]) == 2
    one_line(capsys, "/dev/full")


@pytest.mark.parametrize("option", ["--report", "--iges", "-o"])
def test_export_checks_every_output_before_writing_any(tmp_path, capsys, option):
    """A 256-byte report name failed after the STEP and IGES were written."""
    src = write_doc(tmp_path, small_model(**CURVE_ONLY))
    outputs = {"-o": tmp_path / "x.step", "--iges": tmp_path / "x.igs", "--report": tmp_path / "r.md"}
    outputs[option] = tmp_path / ("n" * 252 + ".ext")
    for p in outputs.values():
        if len(p.name) < 200:
            p.write_text("old")
    args = [a for k, p in outputs.items() for a in (k, str(p))]
    assert main(["export", str(src), *args, "--no-progress"]) == 2
    one_line(capsys, "256 bytes")
    assert sorted(p.read_text() for p in tmp_path.iterdir() if p.suffix != ".json") == ["old", "old"]


def test_export_writes_all_outputs_when_it_works(tmp_path, capsys):
    src = write_doc(tmp_path, small_model(**CURVE_ONLY))
    args = ["-o", str(tmp_path / "x.step"), "--iges", str(tmp_path / "x.igs"), "--report", str(tmp_path / "r.md")]
    assert main(["export", str(src), *args, "--no-progress"]) == 0
    capsys.readouterr()
    assert len(read_step(tmp_path / "x.step")) == len(read_iges(tmp_path / "x.igs")) == 1
    assert "| x.step | 1 | 0 | 1 |" in (tmp_path / "r.md").read_text()     # read back under the final name
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.json", "r.md", "x.igs", "x.step"]   # no temporaries
    assert main(["export", str(src), "-o", str(tmp_path / "y.step"), "--iges", str(tmp_path / "y.step"),
                 "--no-progress"]) == 2
    one_line(capsys, "same file")


def test_demo_into_an_existing_file_exits_2(tmp_path, capsys):
    f = tmp_path / "file"
    f.write_text("x")
    assert main(["demo", "-o", str(f), "--no-model", "--no-plots"]) == 2
    one_line(capsys, "is a file")
    assert main(["demo", "-o", str(f / "sub"), "--no-model", "--no-plots"]) == 2
    one_line(capsys, "cannot make the folder")
    assert f.read_text() == "x"
