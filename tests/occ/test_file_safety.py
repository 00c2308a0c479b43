"""Issue 14, files: inputs OCCT's readers die on (SIGSEGV) are refused before OCCT
sees them, names that break files are refused on write, writes are atomic, nothing
is dropped silently. Every read of a damaged file runs in a child process, and the
tests assert that the child was not killed by a signal."""
import errno
import json
import os
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("OCP")
from cagd import BezierCurve, BSplineSurface, CagdError  # noqa: E402
from cagd._validate import MAX_NAME_LENGTH, MAX_NESTING, validate_iges, validate_step  # noqa: E402
from cagd.occ import read_iges, read_step, write_iges, write_step  # noqa: E402
from cagd.occ.files import MIN_EXTENT  # noqa: E402

CHILD_TIMEOUT = 240.0      # seconds; a hang guard for the child process only
from corpus import CAD as REAL  # noqa: E402
SURFACE = BSplineSurface(np.random.default_rng(0).random((4, 4, 3)) * 10.0, 3, 3)
CURVE = BezierCurve(np.random.default_rng(1).random((4, 3)) * 10.0)


def run_child(code: str, *args: str) -> subprocess.CompletedProcess:
    """Run ``code`` in a fresh interpreter; fail the test if OCCT killed it."""
    run = subprocess.run([sys.executable, "-c", textwrap.dedent(code), *args], capture_output=True, text=True,
                         timeout=CHILD_TIMEOUT)
    assert run.returncode >= 0, f"the child died of signal {-run.returncode}: {run.stderr[-500:]}"
    return run


READ_ALL = """
    import json, sys, warnings
    from cagd import CagdError
    from cagd.occ import read_iges, read_step
    out = {}
    for path in sys.argv[1:]:
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                got = (read_iges if path.endswith(".igs") else read_step)(path)
            out[path] = ["read", len(got), got.message]
        except CagdError as exc:
            out[path] = ["CagdError", str(exc)]
    print(json.dumps(out))
"""


def damaged(folder: Path) -> dict:
    """name -> (file, expected words of the CagdError)."""
    write_iges([("surf", SURFACE), ("crv", CURVE)], folder / "good.igs")
    write_step([("surf", SURFACE), ("crv", CURVE)], folder / "good.step")
    data = (folder / "good.igs").read_bytes()
    lines = data.decode().splitlines(True)
    cases = {}
    for pct in (50, 90, 99):
        p = folder / f"trunc{pct}.igs"
        p.write_bytes(data[:len(data) * pct // 100])
        cases[f"iges cut at {pct}%"] = (p, "columns")
    whole = [ln for ln in lines if ln[72] != "T"]             # cut at a record boundary: the T record is gone
    (folder / "noT.igs").write_text("".join(whole[:len(whole) * 9 // 10]))
    cases["iges cut between records"] = (folder / "noT.igs", "no T section")
    p_lines = [i for i, ln in enumerate(lines) if ln[72] == "P"]
    corrupt = list(lines)
    mid = p_lines[len(p_lines) // 2]
    corrupt[mid] = "#@!" * 24 + lines[mid][72:]
    (folder / "corruptP.igs").write_text("".join(corrupt))
    cases["iges parameter section corrupted"] = (folder / "corruptP.igs", "parameter")
    # found by fuzzing: a string where the B-spline surface's indices belong (OCCT's ReadFile: SIGSEGV)
    first128 = next(i for i, ln in enumerate(lines) if ln[72] == "P" and ln.startswith("128,"))
    shifted = list(lines)
    shifted[first128] = lines[first128].replace("128,3,3,3,", "128,3H3,3,", 1)
    assert shifted != lines
    (folder / "string128.igs").write_text("".join(shifted))
    cases["iges string in a b-spline surface"] = (folder / "string128.igs", "holds numbers only")
    fewer = list(lines)
    fewer[first128] = lines[first128].replace("128,3,3,3,3,", "128,9,3,3,3,", 1)    # 10 x 4 poles claimed
    (folder / "count128.igs").write_text("".join(fewer))
    cases["iges b-spline surface with too few fields"] = (folder / "count128.igs", "needs")
    # found by fuzzing a real file (OCC8842_cylinder_Ideas.igs): one knot of a curve made larger than the next
    # (OCCT's transfer: SIGSEGV)
    knots = list(lines)
    first126 = next(i for i, ln in enumerate(lines) if ln[72] == "P" and ln.startswith("126,"))
    zero, nine = "0.0000000000000000E+00,", "9.0000000000000000E+00,"
    knots[first126] = lines[first126].replace("126,3,3,0,0,1,0," + zero, "126,3,3,0,0,1,0," + nine, 1)
    assert knots != lines
    (folder / "knots126.igs").write_text("".join(knots))
    cases["iges b-spline curve with decreasing knots"] = (folder / "knots126.igs", "knots decrease")
    (folder / "noD.igs").write_text("".join(ln for ln in lines if ln[72] != "D"))
    cases["iges without D section"] = (folder / "noD.igs", "no D section")
    # what write_iges of a name with a newline used to write: the 406 name property split over two records
    named = [ln for ln in lines if "4Hsurf" in ln][0]
    broken = data.decode().replace(named, named.replace("4Hsurf", "4Hs\nrf", 1)[:-1])
    (folder / "newline.igs").write_text(broken)
    cases["iges with a newline in a name"] = (folder / "newline.igs", "columns")
    step = (folder / "good.step").read_text()
    deep = step.replace("DATA;\n", "DATA;\n#999999=FOO(" + "(" * 100_000 + ")" * 100_000 + ");\n", 1)
    (folder / "nest.step").write_text(deep)
    cases["step nested 100,000 deep"] = (folder / "nest.step", f"nested more than {MAX_NESTING}")
    bad_surface = step.replace("B_SPLINE_SURFACE_WITH_KNOTS('',3,3,(", "B_SPLINE_SURFACE_WITH_KNOTS(3,3,(", 1)
    assert bad_surface != step
    (folder / "entity.step").write_text(bad_surface)
    cases["step b-spline surface missing a parameter"] = (folder / "entity.step", "crashes on")
    (folder / "cut.step").write_text(step[:len(step) // 2])
    cases["step cut in half"] = (folder / "cut.step", "truncated")
    return cases


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    folder = tmp_path_factory.mktemp("damaged")
    cases = damaged(folder)
    run = run_child(READ_ALL, *(str(p) for p, _ in cases.values()))
    assert run.returncode == 0, run.stderr[-2000:]
    got = json.loads(run.stdout.strip().splitlines()[-1])
    return {name: (got[str(p)], words) for name, (p, words) in cases.items()}


CASES = ["iges cut at 50%", "iges cut at 90%", "iges cut at 99%", "iges cut between records",
         "iges parameter section corrupted", "iges without D section", "iges string in a b-spline surface",
         "iges b-spline surface with too few fields",
         "iges b-spline curve with decreasing knots", "iges with a newline in a name",
         "step nested 100,000 deep", "step b-spline surface missing a parameter", "step cut in half"]


@pytest.mark.parametrize("case", CASES)
def test_a_damaged_file_is_a_cagd_error_naming_the_file_not_a_crash(results, case):
    """Each of these killed the interpreter (SIGSEGV in OCCT) or read half a file; now a
    CagdError naming the file and the problem, in a child process that survives."""
    got, words = results[case]
    assert got[0] == "CagdError", got
    assert "path:" in got[1] and ("IGES file" in got[1] or "STEP file" in got[1]), got[1]
    assert words in got[1], got[1]


def test_the_good_files_still_read(tmp_path):
    write_iges([("surf", SURFACE), ("crv", CURVE)], tmp_path / "good.igs")
    write_step([("surf", SURFACE), ("crv", CURVE)], tmp_path / "good.step")
    for back in (read_iges(tmp_path / "good.igs"), read_step(tmp_path / "good.step")):
        assert [i.name for i in back] == ["surf", "crv"] and back.complete and not back.unread


@pytest.mark.skipif(not REAL.is_dir(), reason="real CAD files not present")
def test_every_real_file_passes_validation():
    files = sorted(p for p in REAL.glob("*/*") if p.suffix.lower() in (".igs", ".iges", ".stp", ".step"))
    assert len(files) == 33
    for p in files:
        (validate_iges if p.suffix.lower() in (".igs", ".iges") else validate_step)(p)


def test_a_step_entity_of_unknown_type_is_reported_not_dropped_silently(tmp_path):
    """OCCT drops the item whose curve has a misspelt type: one item of two comes
    back; ``unread`` and ``message`` say which entities were not read, with a warning."""
    write_step([("surf", SURFACE), ("crv", CURVE)], tmp_path / "good.step")
    text = (tmp_path / "good.step").read_text()
    last = text.rindex("B_SPLINE_CURVE_WITH_KNOTS(")
    (tmp_path / "typo.step").write_text(text[:last] + "B_SPLINE_CURVE_WITH_KNOTZ(" + text[last + 26:])
    run = run_child(READ_ALL, str(tmp_path / "typo.step"))
    (kind, count, message), = json.loads(run.stdout.strip().splitlines()[-1]).values()
    assert (kind, count) == ("read", 1)
    assert "2 entities of the file were not read" in message and "TRIMMED_CURVE" in message
    with pytest.warns(RuntimeWarning, match="were not read"):
        back = read_step(tmp_path / "typo.step")
    assert len(back) == 1 and [(k.name, k.kind) for k in back.skipped] == [("crv", "item")]   # the empty item
    assert back.unread[0].startswith("entity ") and "TRIMMED_CURVE" in back.unread[0]
    assert "B_SPLINE_CURVE_WITH_KNOTZ" in back.unread[1] and "does not read" in back.unread[1]


def test_an_iges_entity_of_unknown_type_is_reported_not_dropped_silently(tmp_path):
    """Entity type 127 (none) for the curve: OCCT keeps the surface and drops the curve."""
    write_iges([("surf", SURFACE), ("crv", CURVE)], tmp_path / "good.igs")
    lines = (tmp_path / "good.igs").read_text().splitlines(True)
    out = []
    for ln in lines:
        if ln[72] == "D" and ln.startswith("     126"):
            ln = "     127" + ln[8:]
        if ln[72] == "P" and ln.startswith("126,"):
            ln = "127," + ln[4:]
        out.append(ln)
    assert out != lines
    (tmp_path / "unknown.igs").write_text("".join(out))
    run = run_child(READ_ALL, str(tmp_path / "unknown.igs"))
    (kind, count, message), = json.loads(run.stdout.strip().splitlines()[-1]).values()
    assert (kind, count) == ("read", 1) and "type 127" in message
    with pytest.warns(RuntimeWarning, match="1 entities of the file were not read"):
        back = read_iges(tmp_path / "unknown.igs")
    assert [i.name for i in back] == ["surf"] and back.unread == ("entity 3 (type 127): an entity type OCCT does "
                                                                  "not read",)


@pytest.mark.parametrize("old, new", [
    (".F.,(4,4),(4,4),(0.0000000000000000E+00,", ".F.,(4,4),(4,4),(2.0000000000000000E+00,"),   # knots decrease
    (".F.,(4,4),(4,4),", ".F.,(4,3),(4,4),"),                                                   # multiplicities
])
def test_a_step_item_whose_geometry_does_not_transfer_is_reported(tmp_path, old, new):
    """OCCT transfers a B-spline surface with decreasing knots (or multiplicities that do
    not add up) as an empty item: read_step returned the other item only, silently."""
    write_step([("surf", SURFACE), ("crv", CURVE)], tmp_path / "good.step")
    text = (tmp_path / "good.step").read_text()
    assert old in text
    (tmp_path / "bad.step").write_text(text.replace(old, new, 1))
    run = run_child(READ_ALL, str(tmp_path / "bad.step"))
    (kind, count, message), = json.loads(run.stdout.strip().splitlines()[-1]).values()
    assert (kind, count) == ("read", 1) and "'surf'" in message and "did not transfer" in message
    with pytest.warns(RuntimeWarning, match="did not transfer"):
        back = read_step(tmp_path / "bad.step")
    assert [i.name for i in back] == ["crv"] and not back.complete
    assert [(k.name, k.kind) for k in back.skipped] == [("surf", "item")]


@pytest.mark.parametrize("name, words", [("a\nb", "control character"), ("tab\there", "control character"),
                                         ("bad\ud800", "surrogate"), ("x" * (MAX_NAME_LENGTH + 1), "at most"),
                                         (" padded", "leading"), ("", "non-empty")])
def test_a_name_that_breaks_a_file_is_refused_on_write(tmp_path, name, words):
    """write_iges of "a\\nb" wrote a file OCCT then died reading; "\\ud800" was a raw
    TypeError from write_step. Nothing is written."""
    for write, ext in ((write_step, "step"), (write_iges, "igs")):
        with pytest.raises(CagdError, match=words):
            write([(name, SURFACE)], tmp_path / f"x.{ext}")
        assert not (tmp_path / f"x.{ext}").exists()


def test_write_step_argument_errors_are_cagd_errors(tmp_path):
    """Each was a raw exception: ValueError (NUL), Standard_NullObject (schema None),
    a surrogate in the path."""
    with pytest.raises(CagdError, match="NUL"):
        write_step([SURFACE], str(tmp_path / "a\x00b.step"))
    with pytest.raises(CagdError, match="schema"):
        write_step([SURFACE], tmp_path / "x.step", schema=None)  # type: ignore[arg-type]
    with pytest.raises(CagdError, match="schema"):
        write_step([SURFACE], tmp_path / "x.step", schema="AP999")
    with pytest.raises(CagdError, match="encoded"):
        write_step([SURFACE], str(tmp_path / "a\ud800.step"))
    with pytest.raises(CagdError, match="file name of 256 bytes"):
        write_step([SURFACE], tmp_path / ("n" * 251 + ".step"))
    with pytest.raises(CagdError, match="no such file"):
        read_step(str(tmp_path / "a\x00b.step"))
    with pytest.raises(CagdError, match="no such file"):
        read_iges(tmp_path / ("n" * 300 + ".igs"))
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("scale", [0.0, 1e-9])
def test_a_collapsed_or_tiny_surface_is_refused_on_write(tmp_path, scale):
    """A surface collapsed to a point, or 1.6e-8 mm across, wrote to STEP without error
    and read back as nothing."""
    tiny = BSplineSurface(SURFACE.control_points * scale + 1.0, 3, 3)
    with pytest.raises(CagdError, match="'speck'.*returns nothing"):
        write_step([("speck", tiny)], tmp_path / "x.step")
    assert not (tmp_path / "x.step").exists()
    small = BSplineSurface(SURFACE.control_points * (10 * MIN_EXTENT / 10.0), 3, 3)   # a little over the limit
    write_step([("small", small)], tmp_path / "y.step")
    assert len(read_step(tmp_path / "y.step")) == 1


def _fail_fsync(fd):
    raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))


@pytest.mark.parametrize("ext", ["step", "igs"])
def test_a_failed_write_leaves_the_old_file_intact(tmp_path, monkeypatch, ext):
    """On a full disk write_step/write_iges replaced the good file by a fragment with a
    raw OSError. Now: CagdError naming the path, the old bytes intact, no temporary left."""
    write = write_step if ext == "step" else write_iges
    target = tmp_path / f"model.{ext}"
    write([("old", SURFACE)], target)
    before = target.read_bytes()
    monkeypatch.setattr("cagd._atomic.os.fsync", _fail_fsync)
    with pytest.raises(CagdError, match=f"cannot write .*model.{ext}.*No space left"):
        write([("new", CURVE)], target)
    monkeypatch.undo()
    assert target.read_bytes() == before
    assert [p.name for p in tmp_path.iterdir()] == [target.name]


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="no /dev/full")
def test_writing_to_a_full_device_is_a_cagd_error():
    with pytest.raises(CagdError, match="/dev/full.*No space left"):
        write_step([SURFACE], "/dev/full")


def test_the_child_process_check_sees_a_crash():
    """The guard of these tests works: a child killed by SIGSEGV fails the assertion."""
    with pytest.raises(AssertionError, match=f"signal {int(signal.SIGSEGV)}"):
        run_child("import os, signal; os.kill(os.getpid(), signal.SIGSEGV)")


@pytest.mark.skipif(not (REAL / "iges" / "OCC8842_cylinder_Ideas.igs").is_file(), reason="real CAD files not present")
def test_an_iges_entity_occt_rejects_is_transferred_in_a_child_first(tmp_path):
    """Found by fuzzing: a face (510) claiming 111 loops. OCCT's parser flags it, its
    transfer dies (SIGSEGV); the probe in a child process turns that into a CagdError."""
    text = (REAL / "iges" / "OCC8842_cylinder_Ideas.igs").read_text()
    bad = text.replace("510,25,1,1,29;    ", "510,25,111,29;    ", 1)
    assert bad != text
    (tmp_path / "face.igs").write_text(bad)
    run = run_child(READ_ALL, str(tmp_path / "face.igs"))
    (kind, message), = json.loads(run.stdout.strip().splitlines()[-1]).values()
    assert kind == "CagdError" and "crashes on (signal" in message and "type 510" in message


def test_occt_reads_the_validated_bytes_not_the_file_again(tmp_path, monkeypatch):
    """The file may be replaced between the check and OCCT's read: OCCT reads a private
    copy of the validated bytes, removed afterwards."""
    import cagd.occ.files as files
    write_step([("surf", SURFACE)], tmp_path / "a.step")
    check = files.validate_step

    def check_then_replace(path, data=None):
        check(path, data)
        (tmp_path / "a.step").write_text("garbage")             # replaced after validation
    monkeypatch.setattr(files, "validate_step", check_then_replace)
    assert [i.name for i in read_step(tmp_path / "a.step")] == ["surf"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.step"]
