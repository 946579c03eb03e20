"""The layering of docs/layout.md, checked: importing and running `generators` loads no CAD kernel,
file-format or upper-layer module; `cam_workbench/freecad` never imports OCP/cadquery/build123d."""
import ast
import re
import subprocess
import sys

from .conftest import ROOT

FORBIDDEN = ["OCP", "cadquery", "build123d", "FreeCAD", "Part", "ezdxf", "matplotlib",
             "rich", "tqdm", "nlopt", "dask", "distributed", "pyarrow"]
#: of the one import name, the generators may load the package's own __init__ and themselves
OWN = ("cam_workbench", "cam_workbench.generators")
#: The only module allowed to import nlopt (lazily, inside the functions that run a solver).
NLOPT_ALLOWED = ("generators/optimise/driver.py",)


def test_generators_imports_no_cad_or_file_format_module():
    code = (
        "import sys, cam_workbench.generators.optimise, cam_workbench.generators.studies.sweep\n"
        "from cam_workbench.generators import default_spec, design_cam\n"
        "d = design_cam(default_spec()); d.summary()\n"
        "from cam_workbench.generators.studies.grid import Grid, parse_vary\n"
        "from cam_workbench.generators.studies.sweep import run_sweep\n"
        "from cam_workbench.generators.studies.sizing import SizingSettings\n"
        "run_sweep(default_spec(), Grid((parse_vary('motion[1].law=harmonic,cycloidal'),)), sizing=SizingSettings(tol=1.0))\n"
        f"bad = [m for m in {FORBIDDEN!r} if m in sys.modules]\n"
        f"bad += [m for m in sys.modules if m.startswith('cam_workbench') and m not in {OWN!r}\n"
        "        and not m.startswith('cam_workbench.generators.')]\n"
        "print(','.join(bad))\n"
    )
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT)
    assert res.returncode == 0, res.stderr
    assert res.stdout.strip() == "", f"generators loaded: {res.stdout.strip()}"


def test_no_upward_imports_in_source():
    pattern = re.compile(r"^\s*(import|from)\s+(cadquery|build123d|OCP|FreeCAD|Part|ezdxf|matplotlib|"
                         r"cam_workbench(?!\.generators\b)|exporters|generators|dask|distributed|pyarrow)\b",
                         re.M)
    for path in (ROOT / "generators").rglob("*.py"):
        assert not pattern.search(path.read_text()), path
    freecad = ROOT / "cam_workbench" / "freecad"
    if freecad.exists():
        bad = re.compile(r"^\s*(import|from)\s+(cadquery|build123d|OCP)\b", re.M)
        for path in freecad.rglob("*.py"):
            assert not bad.search(path.read_text()), path
    # exporters may use the kernel (which imports only generators), nothing else of cam_workbench
    exp = re.compile(r"^\s*(import|from)\s+(cam_workbench(?!\s+import\s+kernel\b|\.kernel\b"
                     r"|\.generators\b|\.exporters\b)|generators|exporters|cadquery|build123d)\b", re.M)
    for path in (ROOT / "exporters").rglob("*.py"):
        assert not exp.search(path.read_text()), path


def test_only_the_adaptor_imports_ocp():
    """Every OCP name the project uses comes from cam_workbench/kernel/ocp.py, the one module that
    knows OCP's versions (issue 12): no other source, test or benchmark imports OCP."""
    ocp = re.compile(r"^\s*(import|from)\s+OCP\b", re.M)
    adaptor = "cam_workbench/kernel/ocp.py"
    offenders = []
    for top in ("cam_workbench", "exporters", "generators", "tests", "benchmarks"):
        for path in (ROOT / top).rglob("*.py"):
            rel = path.relative_to(ROOT).as_posix()
            if rel != adaptor and ocp.search(path.read_text(encoding="utf-8")):
                offenders.append(rel)
    assert not offenders, offenders
    text = (ROOT / adaptor).read_text(encoding="utf-8")
    assert ocp.search(text)
    # a leaf: of the project, only generators' error types
    tree = ast.parse(text)
    imported = {a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names}
    imported |= {n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom) and n.module}
    project = sorted(m for m in imported if m.split(".")[0] in ("cam_workbench", "exporters", "generators"))
    assert project == ["cam_workbench.generators.errors"], project


def test_importing_the_package_loads_no_ocp():
    """``import cam_workbench`` (and the command line's parser and commands' modules) loads no
    OCP, cadquery or build123d: they are loaded when a solid is asked for."""
    code = ("import sys, cam_workbench, cam_workbench.cli, cam_workbench.kernel.ocp\n"
            "from cam_workbench.commands.dispatch import RUNNERS\n"
            "cam_workbench.cli.build_parser()\n"
            "runners = [load() for load in RUNNERS.values()]   # every command's module\n"
            "print(','.join(m for m in ('OCP', 'cadquery', 'build123d') if m in sys.modules))\n")
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT)
    assert res.returncode == 0, res.stderr
    assert res.stdout.strip() == ""


def test_only_the_optimiser_imports_nlopt():
    """nlopt is allowed in the optimiser's solver module only, and there only lazily (inside a
    function), so that `import generators` works on Pythons without it."""
    any_import = re.compile(r"^\s*(import|from)\s+nlopt\b", re.M)
    top_level = re.compile(r"^(import|from)\s+nlopt\b", re.M)
    # the checkout's own files: not its hidden folders (.venv, .git, .cache with the FreeCAD
    # root filesystems of `make test`)
    own = [p for top in sorted(ROOT.iterdir()) if not top.name.startswith(".")
           for p in ([top] if top.suffix == ".py" else top.rglob("*.py") if top.is_dir() else [])]
    for path in own:
        rel = path.relative_to(ROOT).as_posix()
        if rel.startswith((".venv/", "tests/")):
            continue
        text = path.read_text(encoding="utf-8")
        if rel in NLOPT_ALLOWED:
            assert any_import.search(text) and not top_level.search(text), rel
        else:
            assert not any_import.search(text), f"{rel} imports nlopt"


def test_only_the_parallel_module_imports_dask():
    """Dask is the upper layer's engine (issue 16): ``cam_workbench/parallel.py`` is the one module
    that imports ``dask``/``distributed`` (lazily, like every optional dependency); generators gets an
    executor passed in, and the FreeCAD workbench never loads Dask."""
    any_import = re.compile(r"^\s*(import|from)\s+(dask|distributed)\b", re.M)
    top_level = re.compile(r"^(import|from)\s+(dask|distributed)\b", re.M)
    offenders = []
    for top in ("cam_workbench", "exporters", "generators"):
        for path in (ROOT / top).rglob("*.py"):
            rel = path.relative_to(ROOT).as_posix()
            text = path.read_text(encoding="utf-8")
            if rel == "cam_workbench/parallel.py":
                assert any_import.search(text) and not top_level.search(text), rel
            elif any_import.search(text):
                offenders.append(rel)
    assert not offenders, offenders
    code = ("import sys, cam_workbench.cli, cam_workbench.studies, cam_workbench.parallel\n"
            "from cam_workbench.commands.dispatch import RUNNERS\n"
            "cam_workbench.cli.build_parser()\n"
            "runners = [load() for load in RUNNERS.values()]   # every command's module\n"
            "print(','.join(m for m in ('dask', 'distributed', 'pyarrow') if m in sys.modules))\n")
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT)
    assert res.returncode == 0, res.stderr
    assert res.stdout.strip() == ""


def test_one_import_name():
    """The distribution's one import name is ``cam_workbench``: no source, test or benchmark
    imports the folders ``generators`` or ``exporters`` as top-level packages (in a checkout
    they would load a second copy of every module beside ``cam_workbench.generators``)."""
    top = re.compile(r"^\s*(import|from)\s+(generators|exporters)\b", re.M)
    offenders = [path.relative_to(ROOT).as_posix()
                 for folder in ("cam_workbench", "exporters", "generators", "tests", "benchmarks")
                 for path in (ROOT / folder).rglob("*.py") if top.search(path.read_text(encoding="utf-8"))]
    assert not offenders, offenders
