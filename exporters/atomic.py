"""Atomic file output: write to a temporary file beside the target, then rename.

An error never leaves a half-written or clobbered file.  :class:`OutputSet` commits several
files together as one cam's set in an output folder: they are written into a staging folder
that replaces the target in one atomic step, so a folder holds one spec's set — never a mix of
two, even when the process is killed (the next run removes what it left).  Which folder a run
may write into is :mod:`cam_workbench.exporters.output_rule`'s rule.
"""
from __future__ import annotations

import ctypes
import errno
import json
import os
import shutil
import tempfile
from contextlib import contextmanager
from pathlib import Path
from typing import Callable, Iterator

from .output_rule import MANIFEST, STAGING_TAG, Claim, admit, read_manifest


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _make_temp(folder: Path, name: str) -> Path:
    """A new empty temporary file in ``folder`` with the permissions a normal file gets."""
    fd, tmp = tempfile.mkstemp(prefix=f".{name}.", suffix=".tmp", dir=folder)
    os.close(fd)
    os.chmod(tmp, 0o666 & ~_umask())
    return Path(tmp)


@contextmanager
def atomic_path(path: str | os.PathLike[str]) -> Iterator[Path]:
    """Yield a temporary path in the target's folder; rename it onto ``path`` on success."""
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    tmp_path = _make_temp(target.parent, target.name)
    try:
        yield tmp_path
        os.replace(tmp_path, target)
    finally:
        if tmp_path.exists():
            tmp_path.unlink()


def write_text_atomic(path: str | os.PathLike[str], text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically."""
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return Path(path)


def write_bytes_atomic(path: str | os.PathLike[str], data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically."""
    with atomic_path(path) as tmp:
        tmp.write_bytes(data)
    return Path(path)


_RENAME_EXCHANGE = 2
_AT_FDCWD = -100


def _exchange(a: Path, b: Path) -> bool:
    """Swap two directory entries atomically (Linux renameat2 RENAME_EXCHANGE); False where the
    system cannot (then the caller falls back to two renames)."""
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        fn = libc.renameat2
    except (OSError, AttributeError):
        return False
    if fn(_AT_FDCWD, os.fsencode(str(a)), _AT_FDCWD, os.fsencode(str(b)), _RENAME_EXCHANGE) == 0:
        return True
    err = ctypes.get_errno()
    if err in (errno.ENOSYS, errno.EINVAL, errno.EOPNOTSUPP):
        return False
    raise OSError(err, os.strerror(err), str(b))


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def _remove_stale_staging(target: Path) -> None:
    """Staging folders of earlier runs that were killed (their process is gone)."""
    prefix = f".{target.name}{STAGING_TAG}"
    parent = target.parent if str(target.parent) else Path(".")
    if not parent.is_dir():
        return
    for p in parent.iterdir():
        if p.name.startswith(prefix):
            try:
                pid = int(p.name[len(prefix):].split("-")[0])
            except ValueError:
                continue
            if not _pid_alive(pid) or pid == os.getpid():
                shutil.rmtree(p, ignore_errors=True)


class OutputSet:
    """Several output files committed together as one cam's set in a folder.

    Usage::

        with OutputSet(out_dir, Claim("build", source, digest=spec_digest(spec))) as out:
            out.add("cam.step", lambda tmp: export_step(shape, tmp))
            out.add_text("report.json", text)
        # here the folder holds these files (and its manifest), or, if anything raised or the
        # folder was refused, what it held before

    Which folder a run may write into, and which earlier files stay, is
    :func:`cam_workbench.exporters.output_rule.admit`'s rule (checked on entering and again, with the files'
    names, on commit).  The files are written into a staging folder beside the target; on commit
    a manifest (``.cam-workbench.json``: the files, the command, the source, the spec and its
    digest) is added and the staging folder replaces the target in one atomic step (Linux
    ``renameat2(RENAME_EXCHANGE)``), so a folder never holds files of two specs, even when the
    process is killed; the next run removes what a killed one left.
    """

    def __init__(self, folder: str | os.PathLike[str], claim: Claim):
        self.folder = Path(folder)
        self.claim = claim
        self._pending: list[str] = []
        self._staging: Path | None = None

    def __enter__(self) -> "OutputSet":
        admit(self.folder, self.claim)
        _remove_stale_staging(self.folder)
        return self

    def _stage(self) -> Path:
        if self._staging is None:
            parent = self.folder.parent if str(self.folder.parent) else Path(".")
            parent.mkdir(parents=True, exist_ok=True)
            self._staging = parent / f".{self.folder.name}{STAGING_TAG}{os.getpid()}-{id(self):x}"
            self._staging.mkdir()
        return self._staging

    def _tmp_for(self, name: str) -> Path:
        target = self._stage() / name
        target.parent.mkdir(parents=True, exist_ok=True)
        return target

    def add(self, name: str, writer: Callable[[Path], object]) -> Path:
        """Run ``writer(path)`` now on the staged file; it becomes ``folder/name`` on commit."""
        tmp = self._tmp_for(name)
        self._pending.append(name)
        writer(tmp)
        return self.folder / name

    def add_text(self, name: str, text: str) -> Path:
        return self.add(name, lambda p: p.write_text(text, encoding="utf-8"))

    def add_bytes(self, name: str, data: bytes) -> Path:
        return self.add(name, lambda p: p.write_bytes(data))

    @property
    def names(self) -> list[str]:
        return list(self._pending)

    def _carry_over(self, staging: Path, kept: list[str]) -> None:
        """Hard-link (or copy) the earlier set's files that stay into the staging folder."""
        for name in kept:
            dst = staging / name
            dst.parent.mkdir(parents=True, exist_ok=True)
            try:
                os.link(self.folder / name, dst)
            except OSError:
                shutil.copy2(self.folder / name, dst)

    def _commit(self) -> None:
        staging = self._stage()
        # the rule with this run's files: nothing foreign appeared meanwhile, nothing contradicting stays
        kept = admit(self.folder, self.claim, {n.split("/")[0] for n in self._pending})
        earlier = read_manifest(self.folder) if kept else None
        self._carry_over(staging, kept)
        manifest = self.claim.manifest(set(self._pending) | set(kept), earlier)
        (staging / MANIFEST).write_text(json.dumps(manifest, indent=1) + "\n", encoding="utf-8")
        os.chmod(staging, 0o777 & ~_umask())
        if not self.folder.exists():
            os.rename(staging, self.folder)
        elif _exchange(staging, self.folder):
            shutil.rmtree(staging, ignore_errors=True)     # now the earlier set
        else:
            aside = staging.with_name(staging.name + "-old")
            os.rename(self.folder, aside)                 # no atomic swap here: a short window
            os.rename(staging, self.folder)
            shutil.rmtree(aside, ignore_errors=True)
        self._staging = None

    def __exit__(self, exc_type, exc, tb) -> None:
        try:
            if exc_type is None and self._pending:
                self._commit()
        finally:
            if self._staging is not None:
                shutil.rmtree(self._staging, ignore_errors=True)
                self._staging = None

