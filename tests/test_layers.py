"""Imports run one way: kernels below, the public API above them, analysis, experiments and plots on top.

The rank of each part of the package (README, "Layout"); a module may import
only parts of a lower rank (the package's ``__init__`` is the public facade
and may import anything).  A failure names the import that runs back up.
"""
import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "src" / "noslipsim"

RANKS = {
    "core": 0,                                   # numba kernels on plain arrays
    "_unit": 1, "_validate": 1, "_version": 1, "_metadata": 1, "_netcdf": 1,   # private helpers
    "outline": 1,                                # drawing primitives (plain coordinates), below elements
    "elements": 2,
    "_engine": 3,                                # scene -> kernels: canonical form, packing, the one call
    "scenes": 4,
    "simulate": 5, "tables": 5, "initial": 5, "theory": 5, "sphere3d": 5, "io": 5,
    "_chunkstore": 5, "_scheduler": 5,           # chunk files on disk; running chunk tasks (dask lives here)
    "ensemble": 6, "reference": 6,
    "analysis": 7, "plot": 7,                    # side by side: neither imports the other
    "experiments": 8,
    "animation": 8, "explorer": 8,               # beside experiments: the explorer app, animations
    "cli": 9, "cluster": 9,                      # cluster: runtime settings -> where ensembles run
}


def _part(module):
    """``noslipsim.x.y`` -> ``x`` (the part of the package a module belongs to)."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else None


def _imports(path, package=PACKAGE):
    """Absolute names of the noslipsim modules ``path`` imports (``from . import x`` resolved to ``x``)."""
    rel = path.relative_to(package.parent).with_suffix("")
    module = ".".join(rel.parts)
    package = module if path.name == "__init__.py" else module.rsplit(".", 1)[0]
    if path.name == "__init__.py":
        module = package
    out = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            if not target.startswith("noslipsim"):
                continue
            if target == "noslipsim":  # from .. import tables: the module tables
                out += [(f"noslipsim.{alias.name}", node.lineno) for alias in node.names]
            else:
                out.append((target, node.lineno))
        elif isinstance(node, ast.Import):
            out += [(alias.name, node.lineno) for alias in node.names if alias.name.startswith("noslipsim")]
    return module, out


def _modules():
    return sorted(p for p in PACKAGE.rglob("*.py") if "__pycache__" not in p.parts)


def test_every_part_of_the_package_has_a_rank():
    parts = {p.relative_to(PACKAGE).parts[0].removesuffix(".py") for p in _modules()} - {"__init__"}
    assert parts <= set(RANKS), f"parts without a rank (add them to RANKS and README's layout): {parts - set(RANKS)}"


def upward_imports(path, package=PACKAGE):
    """The imports of ``path`` that run to a part of the same or a higher rank, as messages."""
    module, imports = _imports(path, package)
    if module == "noslipsim":
        return []
    mine = _part(module)
    bad = []
    for target, line in imports:
        theirs = _part(target)
        if theirs is None or theirs == mine:
            continue
        if not RANKS[theirs] < RANKS[mine]:
            bad.append(f"{path.relative_to(package)}:{line} imports {target} ({theirs}, rank {RANKS[theirs]}) "
                       f"from {mine} (rank {RANKS[mine]})")
    return bad


@pytest.mark.parametrize("path", _modules(), ids=lambda p: p.relative_to(PACKAGE).as_posix())
def test_no_import_runs_back_up_a_layer(path):
    assert upward_imports(path) == []


def test_the_check_sees_an_import_that_runs_back_up(tmp_path):
    """The test above is not vacuous: a kernel importing the scenes, or analysis importing plots, is caught."""
    package = tmp_path / "noslipsim"
    (package / "core").mkdir(parents=True)
    (package / "analysis").mkdir()
    (package / "core" / "loop.py").write_text("from ..scenes import Scene\nfrom .jit import jit\n")
    (package / "analysis" / "x.py").write_text("from .. import plot\nfrom ..simulate import simulate\n")
    assert len(upward_imports(package / "core" / "loop.py", package)) == 1
    assert upward_imports(package / "analysis" / "x.py", package) == [
        "analysis/x.py:1 imports noslipsim.plot (plot, rank 7) from analysis (rank 7)"]
