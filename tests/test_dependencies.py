"""Every third-party module the package imports when it loads is one its install declares.

``pip install -e ".[workflow]" && snakemake -j2``, the README's first command, runs on a fresh machine
with the package's dependencies and the ``workflow`` extra only: a module-level import of anything else
(scipy was one, used by two conjecture experiments and declared only for the tests) breaks
``import noslipsim.experiments`` and the pipeline there, while every test passes in an environment
that has the test extras.  The explorer may import its own extra, ``explore``.
"""
import ast
import re
import sys
from pathlib import Path

import pytest

tomllib = pytest.importorskip("tomllib", reason="tomllib is in the standard library from Python 3.11")

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "src" / "noslipsim"
#: Import names whose distribution has another name, or that come with a declared distribution.
DISTRIBUTION = {"yaml": "pyyaml", "netCDF4": "netcdf4", "tornado": "bokeh"}
#: Subpackages that may import an extra of their own at module level.
EXTRAS = {"explorer": "explore"}


def _names(requirements):
    return {re.split(r"[\[<>=~!; ]", r, maxsplit=1)[0].lower() for r in requirements}


def _module_imports(path):
    """Top-level third-party names imported at module level (not in a function, not under ``try``)."""
    for node in ast.parse(path.read_text(encoding="utf-8")).body:
        if isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.level == 0:
            names = [node.module]
        else:
            continue
        for name in names:
            top = name.split(".")[0]
            if top not in sys.stdlib_module_names and top != "noslipsim":
                yield top


def test_module_level_imports_are_declared():
    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    core = _names(project["dependencies"])
    missing = []
    for path in sorted(PACKAGE.rglob("*.py")):
        part = path.relative_to(PACKAGE).parts[0]
        allowed = core | _names(project["optional-dependencies"].get(EXTRAS.get(part, ""), []))
        missing += [f"{path.relative_to(ROOT)}: {top}" for top in _module_imports(path)
                    if DISTRIBUTION.get(top, top).lower() not in allowed]
    assert not missing, "imported when the module loads, but not a declared dependency:\n" + "\n".join(missing)


def test_the_check_sees_an_undeclared_import(tmp_path):
    """The scan above is not vacuous: it finds the imports scipy's removal from the dependencies would break."""
    module = tmp_path / "m.py"
    module.write_text("import math\nimport numpy as np\nfrom scipy.optimize import brentq\n\n"
                      "def f():\n    import panel\n", encoding="utf-8")
    assert list(_module_imports(module)) == ["numpy", "scipy"]
