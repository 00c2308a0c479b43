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


# --- issue 14: one-line errors with exit 2, nothing half-written, damaged files in a child process ----------
def one_line(capsys, *words):
    err = [ln for ln in capsys.readouterr().err.splitlines() if ln.strip()]
    assert len(err) == 1 and err[0].startswith("cagd deviation: ") and "Traceback" not in err[0], err
    for w in words:
        assert w in err[0], err[0]


def ball(tmp_path):
    return write_model(tmp_path, [{"name": "ball", "type": "sphere", "radius": 10.0}])


def test_a_row_with_an_empty_field_is_an_error_naming_it(tmp_path):
    """`1,,2,3` was read as the three coordinates 1, 2, 3."""
    pts = tmp_path / "p.csv"
    pts.write_text("0,0,1\n1,,2,3\n")
    with pytest.raises(cagd.CagdError, match=r"line 2 has an empty field: '1,,2,3'"):
        read_points(pts)
    pts.write_text("0;0;1\n1; ;2\n")
    with pytest.raises(cagd.CagdError, match="line 2 has an empty field"):
        read_points(pts)
    pts.write_text("x y z\n0 0 1\n1  2   3\n")                # runs of spaces are one separator
    assert read_points(pts).tolist() == [[0, 0, 1], [1, 2, 3]]


@pytest.mark.parametrize("data, words", [(b"x,y,z\n1,2,\xff\n", "not UTF-8 text (byte 0xff on line 2)"),
                                         (b"1,,2,3\n", "empty field")])
def test_bad_csv_exits_2_with_one_line(tmp_path, capsys, data, words):
    """A non-UTF-8 CSV printed a UnicodeDecodeError traceback and exited 1."""
    pts = tmp_path / "p.csv"
    pts.write_bytes(data)
    assert main(["deviation", str(ball(tmp_path)), str(pts), "-o", str(tmp_path / "r.md")]) == 2
    one_line(capsys, words)
    assert not (tmp_path / "r.md").exists()


@pytest.mark.parametrize("png, words", [("missing/x.png", "does not exist"), ("x.xyz", "unknown picture type"),
                                        ("folder", "is a folder")])
def test_a_bad_png_path_exits_2_before_any_work(tmp_path, capsys, png, words):
    """--png in a missing folder or with an unknown extension was a traceback after the
    report was written; --png naming a folder wrote <folder>.png and exited 0."""
    (tmp_path / "folder").mkdir()
    pts = tmp_path / "p.csv"
    pts.write_text("1,2,3\n")
    assert main(["deviation", str(ball(tmp_path)), str(pts), "-o", str(tmp_path / "r.md"),
                 "--png", str(tmp_path / png)]) == 2
    one_line(capsys, "--png", words)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["folder", "m.json", "p.csv"]


def test_report_and_picture_are_written_together(tmp_path, capsys):
    pts, _ = offsets_from_sphere(tmp_path, n=20)
    assert main(["deviation", str(ball(tmp_path)), str(pts), "-o", str(tmp_path / "r.md"),
                 "--png", str(tmp_path / "map.svg")]) == 0
    assert (tmp_path / "map.svg").read_text().lstrip().startswith("<?xml")
    assert "map.svg" in (tmp_path / "r.md").read_text()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.json", "map.svg", "pts.csv", "r.md", "r.points.csv"]


@pytest.mark.skipif(not __import__("os").path.exists("/dev/full"), reason="no /dev/full")
def test_a_full_output_exits_2(tmp_path, capsys):
    pts, _ = offsets_from_sphere(tmp_path, n=20)
    png = tmp_path / "keep.png"
    png.write_bytes(b"old")
    assert main(["deviation", str(ball(tmp_path)), str(pts), "-o", "/dev/full", "--png", str(png)]) == 2
    one_line(capsys, "/dev/full", "No space left")
    assert png.read_bytes() == b"old"                       # the device fails before the picture is replaced


def test_deviation_against_a_truncated_iges_exits_2_in_a_child_process(tmp_path):
    """`cagd deviation trunc.igs pts.csv` exited 139 (SIGSEGV in OCCT's IGES reader)."""
    pytest.importorskip("OCP")
    import subprocess
    import sys
    from cagd.occ import write_iges
    write_iges([("ball", cagd.sphere(10.0))], tmp_path / "ball.igs")
    data = (tmp_path / "ball.igs").read_bytes()
    (tmp_path / "trunc.igs").write_bytes(data[:len(data) // 2])
    pts, _ = offsets_from_sphere(tmp_path, n=20)
    run = subprocess.run([sys.executable, "-m", "cagd.cli", "deviation", str(tmp_path / "trunc.igs"), str(pts),
                          "-o", str(tmp_path / "r.md")], capture_output=True, text=True, timeout=240)
    assert run.returncode == 2, (run.returncode, run.stderr[-500:])
    assert "trunc.igs" in run.stderr and "Traceback" not in run.stderr


def test_an_unexpected_engine_error_is_one_line_with_exit_2(tmp_path, capsys, monkeypatch):
    """A sphere of radius 1e200 ended in an IndexError traceback from the closest-point
    query; whatever the engine raises, the command prints one line and exits 2."""
    model = write_model(tmp_path, [{"name": "big", "type": "sphere", "radius": 1e200}])
    pts = tmp_path / "p.csv"
    pts.write_text("1,2,3\n4,5,6\n")
    code = main(["deviation", str(model), str(pts), "-o", str(tmp_path / "r.md")])
    if code == 0:                                       # the engine answers it (once its queries are fixed)
        assert (tmp_path / "r.md").exists()
        capsys.readouterr()
    else:
        assert code == 2
        one_line(capsys)

    def broken(*args, **kwargs):
        raise IndexError("index 1 is out of bounds")
    import sys
    monkeypatch.setattr(sys.modules["cagd.queries.deviation"], "deviation", broken)
    assert main(["deviation", str(ball(tmp_path)), str(pts), "-o", str(tmp_path / "s.md")]) == 2
    one_line(capsys, "IndexError", "CAGD_DEBUG")
    monkeypatch.setenv("CAGD_DEBUG", "1")
    with pytest.raises(IndexError):
        main(["deviation", str(ball(tmp_path)), str(pts), "-o", str(tmp_path / "s.md")])


@pytest.mark.parametrize("text", [
    "x,y,z\n1,2,3\n4,5,6\n", "1;2;3\r\n4;5;6\r\n", "1 2 3\n\t4   5 6\n", "# c\n1,2\n\n3,4\n", "1,2,3\r4,5,6\r",
    "\ufeffx y\n1e300 -2.5e-300\n.5 -0.\n", "1, 2, 3\n4 ,5 ,6\n",
])
def test_the_fast_reader_agrees_with_the_line_by_line_one(tmp_path, text):
    """read_points takes numpy's C parser (O(n) memory) when it accepts the file; the
    line-by-line reader that names bad lines is the oracle."""
    from cagd.deviation_cli import _checked_points, _fast_points
    pts = tmp_path / "p.csv"
    pts.write_text(text, newline="")
    got = read_points(pts)
    content = text.lstrip("\ufeff")
    assert np.array_equal(got, _checked_points(pts))
    fast = _fast_points(pts, content)
    assert fast is None or np.array_equal(fast, got)


def test_many_rows_read_through_the_fast_path(tmp_path):
    rng = np.random.default_rng(3)
    X = rng.normal(size=(200_000, 3)) * 1e3
    pts = tmp_path / "big.csv"
    np.savetxt(pts, X, delimiter=",", header="x,y,z", comments="", fmt="%.17g")
    from cagd.deviation_cli import _fast_points
    assert _fast_points(pts, pts.read_text()) is not None
    assert np.array_equal(read_points(pts), X)


def test_reading_in_chunks(tmp_path, monkeypatch):
    """read_points streams the file (issue 14: a 10^7-row CSV was held whole as bytes
    and as text): with 64-byte reads the points, a late bad byte's line number and the
    line-by-line fallback agree with numpy's whole-file parse."""
    import cagd.deviation_cli as cli
    monkeypatch.setattr(cli, "_READ_BYTES", 64)
    rng = np.random.default_rng(3)
    X = rng.normal(size=(400, 3))
    pts = tmp_path / "p.csv"
    np.savetxt(pts, X, delimiter=",", header="x,y,z", comments="", fmt="%.17g")
    got = read_points(pts)
    assert np.array_equal(got, np.loadtxt(pts, delimiter=",", skiprows=1))
    assert np.array_equal(cli._checked_points(pts), got)
    raw = pts.read_bytes().splitlines(keepends=True)
    raw[300] = raw[300].replace(b",", b"\xff,", 1)
    bad = tmp_path / "bad.csv"
    bad.write_bytes(b"".join(raw))
    with pytest.raises(cagd.CagdError, match="byte 0xff on line 301"):
        read_points(bad)
    spaced = tmp_path / "spaced.csv"                 # numpy refuses "1 ,2": the fallback reads it
    spaced.write_text("".join(f"{float(a)!r} ,{float(b)!r} ,{float(c)!r}\n" for a, b, c in X))
    assert np.array_equal(read_points(spaced), X)


def test_per_point_table_beside_the_report(tmp_path):
    """The per-point CSV (issue 15): one row per point, the nearest face's index, the
    distance and bound of deviation() and the foot, each double round-tripped."""
    model = write_model(tmp_path, [{"name": "egg", "type": "ellipsoid", "a": 30, "b": 20, "c": 15}])
    patches = cagd.ellipsoid(30, 20, 15)
    rng = np.random.default_rng(7)
    X = rng.normal(0, 25, (500, 3))
    pts = tmp_path / "pts.csv"
    np.savetxt(pts, X, delimiter=",")
    assert main(["deviation", str(model), str(pts), "-o", str(tmp_path / "r.md")]) == 0
    table = tmp_path / "r.points.csv"
    assert table.read_text().splitlines()[0] == "x,y,z,face,distance,lower_bound,foot_x,foot_y,foot_z"
    T = np.loadtxt(table, delimiter=",", skiprows=1)
    from cagd.queries.deviation import deviation
    res = deviation(patches, X)
    assert T.shape == (500, 9)
    assert np.array_equal(T[:, :3], X) and np.array_equal(T[:, 3].astype(int), res.owner)
    assert np.array_equal(T[:, 4], res.distances) and np.array_equal(T[:, 6:], res.feet)
    assert np.all(T[:, 5] <= np.abs(T[:, 4]))
    assert "per point: `" in (tmp_path / "r.md").read_text()


def test_a_step_face_with_a_hole_is_measured_as_the_face(tmp_path):
    """cagd deviation FILE.step measures to the trimmed faces: a point above the hole's
    centre of a plate is as far as the hole's rim, not its height."""
    pytest.importorskip("OCP")
    from cagd.occ import write_step
    from trim_shapes import circle, rectangle, square_patch
    plate = cagd.TrimmedSurface(square_patch(1.0), [rectangle(0, 1, 0, 1), [circle((0.5, 0.5), 0.2, clockwise=True)]])
    write_step([("plate", plate)], tmp_path / "plate.step")
    pts = tmp_path / "p.csv"
    pts.write_text("0.5,0.5,0.03\n0.1,0.1,0.03\n")
    out = tmp_path / "r.md"
    assert main(["deviation", str(tmp_path / "plate.step"), str(pts), "-o", str(out), "--csv",
                 str(tmp_path / "t.csv")]) == 0
    d = np.abs(np.loadtxt(tmp_path / "t.csv", delimiter=",", skiprows=1)[:, 4])
    assert d == pytest.approx([np.hypot(0.2, 0.03), 0.03], rel=1e-9)


def _sphere_scan(tmp_path, n):
    """n points at known offsets from a sphere of radius 10 (model file, points file)."""
    model = write_model(tmp_path, [{"name": "ball", "type": "sphere", "radius": 10}])
    rng = np.random.default_rng(3)
    d = rng.normal(size=(n, 3))
    X = d / np.linalg.norm(d, axis=1)[:, None] * (10 + rng.uniform(-0.5, 0.5, (n, 1)))
    pts = tmp_path / "pts.csv"
    np.savetxt(pts, X, delimiter=",")
    return model, pts


def test_a_scan_beyond_the_default_table_size_writes_no_table_unless_asked(tmp_path, capsys, monkeypatch):
    """Issue 15: the per-point CSV is written beside the report only up to
    TABLE_DEFAULT_POINTS points; beyond, the report and stdout say so and give --csv;
    an explicit --csv PATH is always written (every row)."""
    import cagd.deviation_cli as dc
    assert dc.TABLE_DEFAULT_POINTS == 100_000
    monkeypatch.setattr(dc, "TABLE_DEFAULT_POINTS", 40)
    model, pts = _sphere_scan(tmp_path, 41)
    assert main(["deviation", str(model), str(pts), "-o", str(tmp_path / "r.md")]) == 0
    assert not (tmp_path / "r.points.csv").exists()
    said = "not written (41 points > 40 written by default; give --csv PATH"
    assert said in capsys.readouterr().out and said in (tmp_path / "r.md").read_text()
    assert main(["deviation", str(model), str(pts), "-o", str(tmp_path / "r2.md"), "--csv",
                 str(tmp_path / "all.csv")]) == 0
    T = np.loadtxt(tmp_path / "all.csv", delimiter=",", skiprows=1)
    assert T.shape == (41, 9)
    assert np.abs(T[:, 4]) == pytest.approx(np.abs(np.linalg.norm(T[:, :3], axis=1) - 10), abs=1e-9)
    assert not (tmp_path / "r2.points.csv").exists()
    (tmp_path / "at").mkdir()
    model40, pts40 = _sphere_scan(tmp_path / "at", 40)                # at the limit: written by default
    assert main(["deviation", str(model40), str(pts40), "-o", str(tmp_path / "at" / "r.md")]) == 0
    assert np.loadtxt(tmp_path / "at" / "r.points.csv", delimiter=",", skiprows=1).shape == (40, 9)


def test_no_csv_writes_no_table(tmp_path, capsys):
    model, pts = _sphere_scan(tmp_path, 20)
    assert main(["deviation", str(model), str(pts), "-o", str(tmp_path / "r.md"), "--no-csv"]) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.json", "pts.csv", "r.md", "r.png"]
    assert "per point: not written (--no-csv)" in (tmp_path / "r.md").read_text()


def test_no_png_writes_no_picture_and_needs_no_matplotlib(tmp_path, capsys, monkeypatch):
    """Without matplotlib the default colour map stops the command before any work and
    says how to go on; --no-png measures and reports without it (the report says no
    picture was drawn); --png and --no-png together are refused."""
    import builtins
    real_import = builtins.__import__

    def no_matplotlib(name, *args, **kwargs):
        if name == "matplotlib" or name.startswith("matplotlib."):
            raise ImportError(f"No module named {name!r}")
        return real_import(name, *args, **kwargs)

    model, pts = _sphere_scan(tmp_path, 20)
    monkeypatch.setattr(builtins, "__import__", no_matplotlib)
    monkeypatch.setattr("importlib.import_module", lambda name, *a: no_matplotlib(name))
    assert main(["deviation", str(model), str(pts), "-o", str(tmp_path / "r.md")]) == 2
    err = capsys.readouterr().err
    assert "needs matplotlib" in err and "--no-png" in err
    assert not (tmp_path / "r.md").exists()
    assert main(["deviation", str(model), str(pts), "-o", str(tmp_path / "r.md"), "--no-png"]) == 0
    monkeypatch.undo()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.json", "pts.csv", "r.md", "r.points.csv"]
    report = (tmp_path / "r.md").read_text()
    assert "colour map: not drawn (--no-png)" in report and "| points | 20 |" in report
    assert main(["deviation", str(model), str(pts), "-o", str(tmp_path / "s.md"), "--no-png", "--png",
                 str(tmp_path / "s.png")]) == 2
    assert "--png and --no-png" in capsys.readouterr().err
    assert not (tmp_path / "s.md").exists() and not (tmp_path / "s.png").exists()


def test_csv_and_no_csv_together_exit_2_before_any_work(tmp_path, capsys):
    model, pts = _sphere_scan(tmp_path, 5)
    assert main(["deviation", str(model), str(pts), "-o", str(tmp_path / "r.md"), "--no-csv", "--csv",
                 str(tmp_path / "t.csv")]) == 2
    assert "--csv and --no-csv" in capsys.readouterr().err
    assert not (tmp_path / "r.md").exists() and not (tmp_path / "t.csv").exists()


# --- issue 16, scan scale: --workers N and the progress bar -----------------------------------

LIDS = [{"name": "left", "type": "bezier_surface",
         "control_points": [[[20, 0, 0], [20, 10, 2], [20, 20, 0]], [[30, 0, 1], [30, 10, 4], [30, 20, 1]],
                            [[40, 0, 0], [40, 10, 2], [40, 20, 0]]]},
        {"name": "right", "type": "bezier_surface",
         "control_points": [[[40, 0, 0], [40, 10, 2], [40, 20, 0]], [[50, 0, -1], [50, 10, 0], [50, 20, -1]],
                            [[60, 0, 0], [60, 10, 3], [60, 20, 0]]]}]

#: `cagd deviation` in a child process with DEVIATION_CHUNK = 300 and TABLE_CHUNK = 250
#: (several chunks from a small scan; the parent process does the chunking, the workers
#: measure and format the per-point CSV)
SMALL_CHUNKS = ("import sys; from cagd.queries import deviation; import cagd.deviation_cli; "
                "sys.modules['cagd.queries.deviation'].DEVIATION_CHUNK = 300; "
                "sys.modules['cagd.deviation_cli'].TABLE_CHUNK = 250; "
                "from cagd.cli import main; raise SystemExit(main(sys.argv[1:]))")


def test_workers_write_the_serial_run_byte_for_byte(tmp_path):
    """`cagd deviation model.json scan.csv --workers 2` (a child process, as a user runs
    it: the pool's processes are spawned from it) writes the same per-point CSV and report,
    byte for byte, as the serial run; --progress draws one step per chunk on stderr."""
    import os
    import subprocess
    import sys
    from pathlib import Path
    # the child imports the cagd under test (the runs' working folders are elsewhere)
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(Path(cagd.__file__).parents[1]),
                                                        os.environ.get("PYTHONPATH", "")])}
    model = write_model(tmp_path, LIDS)
    rng = np.random.default_rng(11)
    n = 1300
    X = np.column_stack([rng.uniform(18, 62, n), rng.uniform(-2, 22, n), rng.normal(1, 1, n)])
    np.savetxt(tmp_path / "scan.csv", X, delimiter=",", fmt="%.17g")
    runs = {}
    for workers in ("1", "2"):
        out = tmp_path / f"w{workers}"
        out.mkdir()
        run = subprocess.run([sys.executable, "-c", SMALL_CHUNKS, "deviation", str(model), str(tmp_path / "scan.csv"),
                              "-o", "r.md", "--workers", workers, "--progress"],
                             cwd=out, env=env, capture_output=True, text=True, timeout=600)
        assert run.returncode == 0, run.stderr[-2000:]
        runs[workers] = run
        steps = [ln for ln in run.stderr.splitlines() if "points measured" in ln]
        assert len(steps) == 5 and steps[-1].endswith("5/5 1,300 of 1,300 points measured"), run.stderr
    for name in ("r.md", "r.points.csv"):
        assert (tmp_path / "w1" / name).read_bytes() == (tmp_path / "w2" / name).read_bytes(), name
    assert runs["1"].stdout == runs["2"].stdout
    table = np.loadtxt(tmp_path / "w2" / "r.points.csv", delimiter=",", skiprows=1)
    assert set(table[:, 3].astype(int).tolist()) == {0, 1}       # both patches are nearest somewhere
    np.testing.assert_array_equal(table[:, :3], X)                # in the order of the scan


def test_no_progress_bar_unless_asked_or_on_a_terminal(tmp_path, capsys):
    pts = tmp_path / "p.csv"
    pts.write_text("1,2,3\n4,5,6\n")
    assert main(["deviation", str(ball(tmp_path)), str(pts), "-o", str(tmp_path / "r.md")]) == 0
    assert "points measured" not in capsys.readouterr().err         # stderr is no terminal here
    assert main(["deviation", str(ball(tmp_path)), str(pts), "-o", str(tmp_path / "s.md"), "--progress"]) == 0
    assert "[########################] 1/1 2 of 2 points measured" in capsys.readouterr().err


@pytest.mark.parametrize("value", ["0", "-1"])
def test_bad_workers_exit_2_before_any_work(tmp_path, capsys, value):
    pts = tmp_path / "p.csv"
    pts.write_text("1,2,3\n")
    assert main(["deviation", str(ball(tmp_path)), str(pts), "-o", str(tmp_path / "r.md"), "--workers", value]) == 2
    one_line(capsys, "--workers", "at least 1")
    assert not (tmp_path / "r.md").exists()
