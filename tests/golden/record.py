"""Record every built-in example's outputs into ``tests/golden/data/NAME.json.gz`` — what
``tests/test_golden.py`` holds the code to (README.md beside this file).

    .venv/bin/python -m tests.golden.record              # every example (make golden)
    .venv/bin/python -m tests.golden.record default flat # some of them

Only for a deliberate, reviewed change of the outputs: a recording replaces what the test
compares against, so a mistake recorded here is no longer found.  Run from the repository root.
"""
from __future__ import annotations

import argparse
import gzip
import json
import shutil
import sys
import tempfile
import time
from pathlib import Path

from .names import where
from .observe import DATA, FORMAT, ROOT, Observer, about


def data_path(name: str) -> Path:
    """Where example ``name``'s recording is stored."""
    return DATA / f"{name}.json.gz"


def load(name: str) -> dict:
    """The recording of example ``name``."""
    with gzip.open(data_path(name), "rt", encoding="utf-8") as f:
        rec = json.load(f)
    if rec.get("format") != FORMAT:
        raise ValueError(f"{data_path(name)}: recording format {rec.get('format')!r}, this test reads {FORMAT}")
    return rec


def save(observation: dict) -> Path:
    """Write an observation as its example's recording (gzip, byte-identical for the same data:
    no time stamp in the gzip header)."""
    DATA.mkdir(parents=True, exist_ok=True)
    path = data_path(observation["example"])
    text = json.dumps({**observation, "about": about()}, indent=0, sort_keys=True, ensure_ascii=False)
    tmp = path.with_suffix(".tmp")
    with open(tmp, "wb") as raw, gzip.GzipFile(fileobj=raw, mode="wb", compresslevel=9, mtime=0, filename="") as f:
        f.write(text.encode("utf-8"))
    tmp.replace(path)
    return path


def main(argv: list[str] | None = None) -> int:
    examples = list(where("examples"))  # type: ignore[call-overload]
    p = argparse.ArgumentParser(prog="python -m tests.golden.record", description=__doc__.split("\n\n")[0])
    p.add_argument("names", nargs="*", metavar="NAME", help=f"examples to record (default: all: {', '.join(examples)})")
    p.add_argument("--workers", type=int, help="command-line runs at a time (default: the number of CPUs, at most 4)")
    args = p.parse_args(argv)
    unknown = sorted(set(args.names) - set(examples))
    if unknown:
        p.error(f"no built-in example {', '.join(unknown)} (they are: {', '.join(examples)})")
    names = args.names or examples
    api = Path(sys.modules[where("api").__module__].__file__ or "").resolve()  # type: ignore[attr-defined]
    if not api.is_relative_to(ROOT):
        p.error(f"this recorder would record {api}, not this checkout ({ROOT}): run it from {ROOT}")
    folder = Path(tempfile.mkdtemp(prefix="cam-golden-"))
    observer = Observer(folder, args.workers)
    try:
        for name in names:
            observer.start(name)
        total = 0
        for name in names:
            t0 = time.monotonic()
            path = save(observer.observe(name))
            size = path.stat().st_size
            total += size
            print(f"{name}: {path.relative_to(Path.cwd()) if path.is_relative_to(Path.cwd()) else path} "
                  f"({size / 1024:.0f} KiB, {time.monotonic() - t0:.0f} s)", flush=True)
        stale = sorted(p.name for p in DATA.glob("*.json.gz") if p.name.removesuffix(".json.gz") not in examples)
        for name in stale:
            (DATA / name).unlink()
            print(f"removed {name}: no such example any more")
        print(f"recorded {len(names)} example(s), {total / 1024:.0f} KiB")
    finally:
        observer.close()
        shutil.rmtree(folder, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
