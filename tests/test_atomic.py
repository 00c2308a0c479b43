"""cagd._atomic: a write is complete or leaves the old file as it was; several outputs
are written all or nothing; every failure is a CagdError naming the path."""
import errno
import os
import stat

import pytest

from cagd import CagdError
from cagd._atomic import check_target, write_file, write_files


def test_write_replaces_the_file_and_keeps_its_permissions(tmp_path):
    target = tmp_path / "a.txt"
    target.write_text("old")
    os.chmod(target, 0o640)
    assert write_file(target, "new") == target
    assert target.read_text() == "new" and stat.S_IMODE(target.stat().st_mode) == 0o640
    write_file(tmp_path / "b.bin", b"\x00\x01")
    mask = os.umask(0)
    os.umask(mask)
    assert stat.S_IMODE((tmp_path / "b.bin").stat().st_mode) == 0o666 & ~mask    # not mkstemp's 0o600
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.txt", "b.bin"]


def test_a_symlink_target_replaces_the_file_it_points_to(tmp_path):
    real = tmp_path / "real.txt"
    real.write_text("old")
    (tmp_path / "link.txt").symlink_to(real)
    write_file(tmp_path / "link.txt", "new")
    assert (tmp_path / "link.txt").is_symlink() and real.read_text() == "new"


@pytest.mark.parametrize("step", ["fill", "fsync", "replace"])
def test_a_failure_at_any_step_leaves_every_old_file_and_no_temporary(tmp_path, monkeypatch, step):
    a, b = tmp_path / "a.txt", tmp_path / "b.txt"
    a.write_text("old a")
    b.write_text("old b")

    def boom(*args, **kwargs):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
    calls = {"n": 0}
    real_replace = os.replace

    def second_replace_fails(src, dst):
        calls["n"] += 1
        if calls["n"] == 2:
            boom()
        real_replace(src, dst)
    if step == "fsync":
        monkeypatch.setattr("cagd._atomic.os.fsync", boom)
    elif step == "replace":
        monkeypatch.setattr("cagd._atomic.os.replace", second_replace_fails)
    content_b = boom if step == "fill" else "new b"
    with pytest.raises(CagdError, match="cannot write .*No space left") as info:
        write_files([(a, "new a", "first"), (b, content_b, "second")])
    monkeypatch.undo()
    if step == "replace":                          # a rename cannot be undone: the message says what changed
        assert "already written" in str(info.value) and a.read_text() == "new a" and b.read_text() == "old b"
    else:
        assert a.read_text() == "old a" and b.read_text() == "old b"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.txt", "b.txt"]


def test_a_writer_exception_that_is_not_an_oserror_is_a_cagd_error_too(tmp_path):
    def bad(path):
        raise ValueError("Format 'xyz' is not supported")
    with pytest.raises(CagdError, match="picture: cannot write .*not supported"):
        write_file(tmp_path / "p.xyz", bad, "picture")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("make, words", [
    (lambda d: 42, "expected a file path"),
    (lambda d: b"x", "expected a file path"),
    (lambda d: str(d / "a\x00b"), "NUL"),
    (lambda d: str(d / "a\ud800b"), "cannot be encoded"),
    (lambda d: d, "is a folder"),
    (lambda d: d / "no" / "x", "does not exist"),
    (lambda d: d / ("n" * 256), "256 bytes"),
])
def test_check_target_names_the_problem(tmp_path, make, words):
    with pytest.raises(CagdError, match=words) as info:
        check_target(make(tmp_path), "--output")
    assert str(info.value).startswith("--output: ")


def test_unwritable_places_are_cagd_errors(tmp_path, monkeypatch):
    """PermissionError/OSError from the writers were raw; root ignores modes, so the
    permission answers are simulated where the process runs as root."""
    ro = tmp_path / "ro.txt"
    ro.write_text("keep")
    real_access = os.access
    monkeypatch.setattr("cagd._atomic.os.access", lambda p, mode: False if "ro" in str(p) else real_access(p, mode))
    with pytest.raises(CagdError, match="read-only"):
        write_file(ro, "new")
    (tmp_path / "rodir").mkdir()
    with pytest.raises(CagdError, match="not writable"):
        write_file(tmp_path / "rodir" / "x", "new")
    monkeypatch.undo()

    def denied(*a, **k):
        raise PermissionError(errno.EACCES, os.strerror(errno.EACCES))
    monkeypatch.setattr("cagd._atomic.tempfile.mkstemp", denied)
    with pytest.raises(CagdError, match="cannot write .*Permission denied"):
        write_file(tmp_path / "y.txt", "new")
    assert ro.read_text() == "keep"


def test_two_outputs_naming_one_file_are_refused(tmp_path):
    with pytest.raises(CagdError, match="same file"):
        write_files([(tmp_path / "a", "1", "one"), (tmp_path / "." / "a", "2", "two")])
    assert list(tmp_path.iterdir()) == []
