"""Atomic file output: write to a temporary file beside the target, then rename.

An error never leaves a half-written or clobbered file.  :class:`OutputSet` commits
several files together: nothing is renamed until every one of them is written, and
the output folder is only created once there is something to put in it.
"""
from __future__ import annotations

import os
import tempfile
from contextlib import contextmanager
from pathlib import Path
from typing import Callable, Iterator


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


class OutputSet:
    """Several output files committed together.

    Usage::

        with OutputSet(out_dir) as out:
            out.add("cam.step", lambda tmp: export_step(shape, tmp))
            out.add_text("report.json", text)
        # all renamed here, or none if anything raised
    """

    def __init__(self, folder: str | os.PathLike[str]):
        self.folder = Path(folder)
        self._pending: list[tuple[Path, Path]] = []
        self._created_folder = False

    def __enter__(self) -> "OutputSet":
        return self

    def _tmp_for(self, name: str) -> Path:
        if not self.folder.exists():
            self.folder.mkdir(parents=True)
            self._created_folder = True
        target = self.folder / name
        target.parent.mkdir(parents=True, exist_ok=True)
        return _make_temp(target.parent, target.name)

    def add(self, name: str, writer: Callable[[Path], object]) -> Path:
        """Run ``writer(tmp_path)`` now; the file is renamed to ``folder/name`` on commit."""
        tmp = self._tmp_for(name)
        self._pending.append((tmp, self.folder / name))
        writer(tmp)
        return self.folder / name

    def add_text(self, name: str, text: str) -> Path:
        return self.add(name, lambda p: p.write_text(text, encoding="utf-8"))

    def add_bytes(self, name: str, data: bytes) -> Path:
        return self.add(name, lambda p: p.write_bytes(data))

    @property
    def names(self) -> list[str]:
        return [t.name for _, t in self._pending]

    def __exit__(self, exc_type, exc, tb) -> None:
        if exc_type is None:
            for tmp, target in self._pending:
                os.replace(tmp, target)
            self._pending.clear()
            return
        for tmp, _ in self._pending:
            if tmp.exists():
                tmp.unlink()
        if self._created_folder:
            try:
                self.folder.rmdir()
            except OSError:
                pass
