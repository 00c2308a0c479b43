"""The bad-input contract of the file readers and the CLI (issue 14): damaged STEP and
IGES files (truncated, bytes changed, sections dropped, deep nesting) are read in a
child process, which must end by returning the file's contents or raising CagdError:
never by a signal (OCCT's readers segfault on some of these), another exception or a
hang. The CLI, given hostile files and arguments, exits 0 or 2 with a one-line message
and no traceback."""
from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from contract import run_child

pytest.importorskip("OCP")

FILES = settings(max_examples=12, deadline=None, suppress_health_check=list(HealthCheck))
#: what the child prints for each ending: contents, a refusal, anything else
READ = """
import sys
import cagd, cagd.occ
reader = cagd.occ.read_step if sys.argv[1].lower().endswith((".step", ".stp")) else cagd.occ.read_iges
try:
    items = reader(sys.argv[1])
except cagd.CagdError as exc:
    print("CAGDERROR", exc)
    sys.exit(0)
except BaseException as exc:
    print("OTHER", type(exc).__name__, exc)
    sys.exit(3)
print("READ", len(items))
"""


@pytest.fixture(scope="module")
def good_files(tmp_path_factory):
    """A small STEP and IGES file written by the toolkit (two B-spline faces and a curve)."""
    import cagd
    from cagd.occ import write_iges, write_step
    folder = tmp_path_factory.mktemp("good")
    items = [("ball", cagd.sphere(2.0)), ("arc", cagd.BezierCurve([[0, 0, 0], [1, 2, 0], [3, 1, 1]])),
             ("patch", cagd.BezierSurface(np.random.default_rng(0).random((3, 4, 3))))]
    step, iges = folder / "good.step", folder / "good.igs"
    write_step(items, step)
    write_iges(items, iges)
    return {"step": step.read_bytes(), "iges": iges.read_bytes()}


def _read_in_child(path: Path) -> str:
    done = run_child(READ, str(path))
    assert not done.crashed, f"the reader died of signal {-done.returncode} on {path.name}:\n{done.stderr[-2000:]}"
    assert not done.timed_out, f"the reader hung on {path.name}"
    assert done.returncode == 0, \
        f"the reader raised another exception on {path.name}: {done.stdout}{done.stderr[-2000:]}"
    return done.stdout


def _damaged(data: bytes, how: str, where: float, seed: int) -> bytes:
    rng = np.random.default_rng(seed)
    cut = max(1, int(len(data) * where))
    if how == "truncate":
        return data[:cut]
    if how == "flip":
        buf = bytearray(data)
        for i in rng.integers(0, len(buf), 8):
            buf[i] = int(rng.integers(0, 256))
        return bytes(buf)
    if how == "drop-lines":
        lines = data.splitlines(keepends=True)
        start = int(len(lines) * where)
        return b"".join(lines[:start] + lines[start + 1 + int(rng.integers(0, 20)):])
    if how == "duplicate":
        return data[:cut] + data[cut // 2:]
    raise AssertionError(how)


@FILES
@given(kind=st.sampled_from(["step", "iges"]), how=st.sampled_from(["truncate", "flip", "drop-lines", "duplicate"]),
       where=st.floats(0.05, 0.999), seed=st.integers(0, 2 ** 16))
def test_damaged_files_are_read_or_refused(good_files, tmp_path_factory, kind, how, where, seed):
    path = tmp_path_factory.mktemp("bad") / ("bad.step" if kind == "step" else "bad.igs")
    path.write_bytes(_damaged(good_files[kind], how, where, seed))
    _read_in_child(path)


@pytest.mark.parametrize("cut", [0.5, 0.9, 0.99])
def test_truncated_iges_is_refused_not_a_crash(good_files, tmp_path, cut):
    """The issue's reproduction: OCCT's IGES reader segfaulted on files cut at 50, 90 and 99 %."""
    path = tmp_path / "trunc.igs"
    path.write_bytes(good_files["iges"][: int(len(good_files["iges"]) * cut)])
    assert _read_in_child(path).startswith(("CAGDERROR", "READ"))


def test_deeply_nested_step_is_refused(good_files, tmp_path):
    """100,000 nested parentheses in one entity."""
    text = good_files["step"].decode()
    head, sep, tail = text.partition("DATA;\n")
    path = tmp_path / "deep.step"
    path.write_text(head + sep + "#999999=CARTESIAN_POINT(''," + "(" * 100_000 + ")" * 100_000 + ");\n" + tail)
    assert _read_in_child(path).startswith("CAGDERROR")


def test_not_a_cad_file(tmp_path):
    for name, data in [("empty.step", b""), ("binary.igs", bytes(range(256)) * 40), ("text.step", b"hello\n" * 100)]:
        path = tmp_path / name
        path.write_bytes(data)
        assert _read_in_child(path).startswith("CAGDERROR"), name


# --- the command line -------------------------------------------------------------------
CLI = "import sys\nfrom cagd.cli import main\nsys.exit(main(sys.argv[1:]))\n"


def _cli(*args: str, cwd: Path) -> None:
    done = run_child(CLI, *args, cwd=str(cwd))
    assert not done.crashed and not done.timed_out, (args, done.returncode, done.stderr[-2000:])
    assert done.returncode in (0, 2), (args, done.returncode, done.stderr[-2000:])
    assert "Traceback" not in done.stderr, (args, done.stderr[-2000:])
    if done.returncode == 2:
        assert done.stderr.strip(), args


CSV_CASES = {
    "non-utf8": b"\xff\xfe1,2,3\n",
    "empty-field": b"1,,2,3\n4,5,6\n",
    "huge-integer": b"1,2," + b"9" * 5000 + b"\n",
    "nan": b"nan,1,2\n1,2,3\n",
    "text": b"x,y,z\na,b,c\n",
    "empty": b"",
    "far": b"1e300,1e300,1e300\n",
}


@pytest.mark.parametrize("case", sorted(CSV_CASES))
def test_cli_deviation_with_hostile_points(good_files, tmp_path, case):
    (tmp_path / "model.step").write_bytes(good_files["step"])
    (tmp_path / "points.csv").write_bytes(CSV_CASES[case])
    _cli("deviation", "model.step", "points.csv", "-o", "report.md", cwd=tmp_path)


@pytest.mark.parametrize("output", ["/dev/full", "missing/out.step", "x" * 300 + ".step", "out.\udcff.step", "."])
def test_cli_export_with_hostile_outputs(tmp_path, output):
    import cagd.demo_model as demo_model   # the built-in model, written by the toolkit
    model = tmp_path / "model.json"
    model.write_text(Path(demo_model.__file__).with_name("model").joinpath("default.json").read_text()
                     if not hasattr(demo_model, "DEFAULT_MODEL") else Path(demo_model.DEFAULT_MODEL).read_text())
    old = tmp_path / "keep.igs"
    old.write_text("the old file")
    _cli("export", "model.json", "-o", output, "--iges", "keep.igs", "--no-progress", cwd=tmp_path)
    if output in ("/dev/full", "missing/out.step", "."):
        assert old.read_text() == "the old file"     # all or nothing


def test_cli_demo_output_naming_a_file(tmp_path):
    (tmp_path / "taken").write_text("a file")
    _cli("demo", "-o", "taken", cwd=tmp_path)
    assert (tmp_path / "taken").read_text() == "a file"


if sys.platform != "linux":   # /dev/full and the child's address-space limit are Linux's
    pytestmark = pytest.mark.skip("Linux only")
os.environ.setdefault("PYTHONFAULTHANDLER", "1")
