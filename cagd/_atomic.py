"""Atomic file writes: a file is either written completely or left as it was.

Every writer of the toolkit (STEP, IGES, model JSON, reports, pictures) goes through
:func:`write_files`: each output is first written to a temporary file in the same
folder, flushed and fsync'ed, and only when all of them are complete are they moved
over their targets with ``os.replace`` (atomic on POSIX and Windows within one file
system). On any failure (a full disk, a read-only folder, a writer's exception) the
temporaries are removed, the old files are intact and a :class:`CagdError` names the
path. Targets that are not regular files (``/dev/null``, ``/dev/full``, pipes) are
written directly: they cannot be replaced, and hold no old content to keep.
"""
from __future__ import annotations

import os
import stat
import tempfile
from pathlib import Path
from typing import Any, Callable, List, Optional, Sequence, Tuple, Union

from .errors import CagdError

NAME_MAX_BYTES = 255       # bytes of one file name where the file system does not say (POSIX NAME_MAX)
SUFFIX_MAX = 16            # characters of the target's extension kept on its temporary file
Writer = Callable[[Path], Any]                    # writes the file at the path it is given
Output = Tuple[Union[str, "os.PathLike[str]"], Union[bytes, str, Writer], str]   # path, content, what


def _reason(exc: BaseException) -> str:
    return getattr(exc, "strerror", None) or str(exc) or type(exc).__name__


def check_target(path: Any, what: str = "path") -> Path:
    """``path`` as a Path if a file can be written there: a str or PathLike without NUL
    or unencodable characters, not a folder, in an existing writable folder, its name
    at most the file system's NAME_MAX bytes, not a read-only file.

    Raises:
        CagdError: naming ``what``, the path and the problem.
    """
    if isinstance(path, bytes) or not isinstance(path, (str, os.PathLike)):
        raise CagdError(f"{what}: expected a file path, got {type(path).__name__}")
    text = os.fspath(path)
    if not isinstance(text, str):
        raise CagdError(f"{what}: expected a text path, got {type(text).__name__}")
    if "\x00" in text:
        raise CagdError(f"{what}: {text!r} contains a NUL character")
    try:
        os.fsencode(text)
    except UnicodeEncodeError as exc:
        raise CagdError(f"{what}: {text!r} cannot be encoded as a file name ({exc.reason})") from None
    target = Path(text)
    parent = target.parent
    try:
        name_max = os.pathconf(parent if parent.is_dir() else ".", "PC_NAME_MAX")
    except (OSError, ValueError, AttributeError):
        name_max = NAME_MAX_BYTES
    for part in target.parts:
        length = len(os.fsencode(part))
        if length > name_max:
            raise CagdError(f"{what}: file name of {length} bytes, the file system allows {name_max}")
    try:
        if not target.name or target.is_dir():
            raise CagdError(f"{what}: {text!r} is a folder; give a file name")
        if not parent.is_dir():
            raise CagdError(f"{what}: folder {str(parent)!r} does not exist")
        regular = target.exists() and stat.S_ISREG(target.stat().st_mode)
    except OSError as exc:
        raise CagdError(f"{what}: cannot write {text!r}: {_reason(exc)}") from None
    if regular and not os.access(target, os.W_OK):
        raise CagdError(f"{what}: {text!r} is read-only")
    if not target.exists() and not os.access(parent, os.W_OK | os.X_OK):
        raise CagdError(f"{what}: folder {str(parent)!r} is not writable")
    return target


def _fill(temp: Path, content: Union[bytes, str, Writer]) -> None:
    if callable(content):
        content(temp)
        return
    data = content.encode("utf-8") if isinstance(content, str) else content
    with open(temp, "wb") as fh:
        fh.write(data)


def _sync(path: Path) -> None:
    with open(path, "rb+") as fh:
        os.fsync(fh.fileno())


def _sync_folder(folder: Path) -> None:
    """Make the renames durable (best effort: not every system can fsync a folder)."""
    try:
        fd = os.open(folder, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


def _mode(target: Path) -> int:
    """The permissions the new file gets: the old file's, else 0o666 less the umask."""
    if target.exists():
        return stat.S_IMODE(target.stat().st_mode)
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


def write_files(outputs: Sequence[Output]) -> List[Path]:
    """Write every output or none: ``outputs`` are (path, content, what) with content
    bytes, str (UTF-8) or a callable writing the file at the path it is given (it gets
    a temporary path with the target's extension). All temporaries are written and
    fsync'ed before the first rename.

    Raises:
        CagdError: naming ``what`` and the path that could not be written; no target
            has changed unless the message says so.
    """
    targets = [check_target(p, what) for p, _, what in outputs]
    targets = [Path(os.path.realpath(t)) if t.is_symlink() else t for t in targets]   # replace the file, not the link
    if len({os.path.abspath(t) for t in targets}) != len(targets):
        raise CagdError(f"{', '.join(w for _, _, w in outputs)}: two outputs name the same file")
    temps: List[Optional[Path]] = []
    try:
        for target, (_, content, what) in zip(targets, outputs):
            if target.exists() and not stat.S_ISREG(target.stat().st_mode):
                temps.append(None)                          # a device or pipe: written in the second pass
                continue
            try:
                fd, name = tempfile.mkstemp(dir=target.parent, prefix=".cagd-",
                                            suffix=".tmp" + target.suffix[:SUFFIX_MAX])
                os.close(fd)
                made = Path(name)
                temps.append(made)
                _fill(made, content)
                os.chmod(made, _mode(target))
                _sync(made)
            except CagdError:
                raise
            except (OSError, ValueError, RuntimeError, MemoryError) as exc:
                raise CagdError(f"{what}: cannot write {str(target)!r}: {_reason(exc)}") from None
        done: List[Path] = []
        # devices and pipes first (a full device fails before any file is replaced), then the renames
        for target, made_or_none, (_, content, what) in sorted(zip(targets, temps, outputs),
                                                                 key=lambda x: x[1] is not None):
            try:
                if made_or_none is None:
                    _fill(target, content)
                else:
                    os.replace(made_or_none, target)
            except (OSError, ValueError, RuntimeError) as exc:
                already = f" ({', '.join(map(str, done))} already written)" if done else ""
                raise CagdError(f"{what}: cannot write {str(target)!r}: {_reason(exc)}{already}") from None
            done.append(target)
        for folder in {t.parent for t in targets}:
            _sync_folder(folder)
        return targets
    finally:
        for left in temps:
            if left is not None and left.exists():
                left.unlink()


def write_file(path: Any, content: Union[bytes, str, Writer], what: str = "path") -> Path:
    """One output of :func:`write_files`: written completely, or the old file is intact."""
    return write_files([(path, content, what)])[0]
