"""``cam-workbench freecad install|uninstall``: register the workbench with FreeCAD."""
from __future__ import annotations

import argparse
from pathlib import Path

from . import EXIT_CHECK_FAILED, EXIT_OK
from ..freecad import install as inst


def _targets(args: argparse.Namespace) -> tuple[list[Path], list[inst.FreeCADInfo]]:
    if args.mod_dir is not None:
        return [args.mod_dir.expanduser()], []
    exes = [args.freecad] if args.freecad else inst.find_freecad_commands()
    infos = []
    for exe in exes:
        try:
            infos.append(inst.query_freecad(exe))
        except inst.InstallError as exc:
            if args.freecad:
                raise
            print(f"warning: {exc}")
    dirs: list[Path] = []
    for info in infos:
        if info.mod_dir not in dirs:
            dirs.append(info.mod_dir)
    return dirs, infos


def run_install(args: argparse.Namespace) -> int:
    dirs, infos = _targets(args)
    if not dirs:
        dirs = inst.default_mod_dirs()[:1]
        print("no FreeCAD found to ask (freecadcmd not on PATH; use --freecad EXE or --mod-dir DIR); "
              f"using the conventional folder {dirs[0]}")
    root = inst.source_root()
    for d in dirs:
        target, mode = inst.install_into(d, root, copy=args.copy)
        print(f"installed: {target} ({mode} to {root})")
    for info in infos:
        print(f"  FreeCAD {info.version} ({info.executable}, Python {info.python}) uses {info.mod_dir}")
    status = EXIT_OK
    if not args.no_verify:
        for info in infos:
            ok, detail = inst.verify(info)
            if ok:
                where, _, versions = detail.partition(" ")
                print(f"  checked: FreeCAD {info.version} imports generators from {where} and designs "
                      f"the default cam ({versions})")
            else:
                status = EXIT_CHECK_FAILED
                print(f"error: FreeCAD {info.version} ({info.executable}) cannot use the workbench: "
                      f"{detail}\n  FreeCAD's Python needs numpy ≥ 1.24 and scipy ≥ 1.10.")
    if status == EXIT_OK:
        print("restart FreeCAD and choose the 'Cam Workbench' workbench")
    return status


def run_uninstall(args: argparse.Namespace) -> int:
    dirs, _infos = _targets(args)
    if args.mod_dir is None:
        for d in inst.default_mod_dirs():
            if d not in dirs:
                dirs.append(d)
    removed = [t for t in (inst.uninstall_from(d) for d in dirs) if t is not None]
    for t in removed:
        print(f"removed: {t}")
    if not removed:
        print("the workbench was not installed in: " + ", ".join(str(d) for d in dirs))
    return EXIT_OK


#: ``freecad ACTION`` → what runs it
ACTIONS = {"install": run_install, "uninstall": run_uninstall}


def run(args: argparse.Namespace) -> int:
    """``freecad install`` or ``freecad uninstall``, as the command line names it."""
    return ACTIONS[args.action](args)
