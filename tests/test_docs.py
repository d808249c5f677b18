"""The documentation: it builds without a warning, and what it shows is true.

* The whole site (pages, API reference from the docstrings, the gallery, which
  runs every example) is built with ``sphinx -W`` into a temporary copy of
  the tree, so a broken page, docstring or example fails the suite.
* The getting-started page is run block by block and each output it shows is
  compared with the real one.
* No user-facing docstring points to a document users do not have.
"""
import contextlib
import io
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
GALLERY = ROOT / "examples" / "gallery"

#: Modules of the API reference (docs/api.rst) and the public names each must document.
API_MODULES = ["noslipsim", "noslipsim.tables", "noslipsim.experiments", "noslipsim.initial", "noslipsim.theory",
               "noslipsim.sphere3d", "noslipsim.reference", "noslipsim.analysis", "noslipsim.plot",
               "noslipsim.cluster", "noslipsim.analysis.log_portrait", "noslipsim.animation", "noslipsim.explorer"]
#: Generated and build folders of docs/ that a build must not find in its copy of the tree.
BUILD_PRODUCTS = ["_build", "generated", "auto_examples", "sg_execution_times.rst"]


def _copy_tree(dest):
    """What the build reads: docs/, the gallery, the benchmark figure it shows (not build products)."""
    shutil.copytree(DOCS, dest / "docs", ignore=shutil.ignore_patterns(*BUILD_PRODUCTS))
    shutil.copytree(GALLERY, dest / "examples" / "gallery", ignore=shutil.ignore_patterns("__pycache__"))
    (dest / "benchmarks" / "results").mkdir(parents=True)
    shutil.copy(ROOT / "benchmarks" / "results" / "work_precision.png", dest / "benchmarks" / "results")


@pytest.fixture(scope="module")
def built_docs(tmp_path_factory):
    tree = tmp_path_factory.mktemp("docs_tree")
    _copy_tree(tree)
    out = tree / "html"
    env = dict(os.environ, MPLBACKEND="Agg")
    run = subprocess.run([sys.executable, "-m", "sphinx", "-W", "--keep-going", "-b", "html", "-q",
                          str(tree / "docs"), str(out)], capture_output=True, text=True, env=env, timeout=900)
    return run, out


def test_docs_build_without_warnings(built_docs):
    run, out = built_docs
    assert run.returncode == 0, run.stdout + run.stderr
    assert "WARNING" not in run.stderr and "ERROR" not in run.stderr, run.stderr
    for page in ["index", "getting-started", "tutorial", "explorer", "conventions", "scenes", "datasets", "algorithm",
                 "analysis", "figures", "errata", "api"]:
        assert (out / f"{page}.html").is_file(), page


def test_every_gallery_example_ran_and_made_a_figure(built_docs):
    _run, out = built_docs
    examples = sorted(p.stem for p in GALLERY.glob("plot_*.py"))
    assert len(examples) >= 8
    images = out / "_images"
    for name in examples:
        assert (out / "auto_examples" / f"{name}.html").is_file(), name
        assert list(images.glob(f"sphx_glr_{name}_001.png")), f"{name} made no figure"
    gifs = list(images.glob("sphx_glr_plot_animation_spin_*.gif"))  # the gallery's animation, as a GIF
    assert gifs and gifs[0].name in (out / "auto_examples" / "plot_animation_spin.html").read_text()


def test_api_reference_documents_every_public_name(built_docs):
    import importlib

    _run, out = built_docs
    for modname in API_MODULES:
        mod = importlib.import_module(modname)
        names = getattr(mod, "__all__", None)
        if names is None:
            names = [n for n, v in vars(mod).items() if not n.startswith("_") and callable(v)
                     and getattr(v, "__module__", None) == modname]
        for name in names:
            obj = getattr(mod, name)
            if not callable(obj):
                continue
            assert (out / "generated" / f"{modname}.{name}.html").is_file(), f"{modname}.{name} has no API page"


# ---------------------------------------------------------------------------- offline
def test_the_site_loads_nothing_from_the_network(built_docs):
    """No script or style sheet from another host; MathJax is shipped in _static."""
    _run, out = built_docs
    external = re.compile(r"""<(?:script|link)[^>]+(?:src|href)=["'](?:https?:)?//""", re.I)
    offenders = {str(p.relative_to(out)) for p in out.rglob("*.html") if external.search(p.read_text())}
    assert not offenders, sorted(offenders)[:5]
    assert (out / "_static" / "mathjax" / "tex-chtml.js").is_file()
    assert "_static/mathjax/tex-chtml.js" in (out / "conventions.html").read_text()


def test_formulas_render_without_a_network(built_docs):
    """A page with formulas, opened from disk in Chromium with every network request refused, typesets them."""
    chromium = shutil.which("chromium")
    if chromium is None:
        pytest.skip("needs Debian's chromium (apt-get install chromium; .ci/run installs it)")
    sync_api = pytest.importorskip("playwright.sync_api", reason="needs playwright (the 'test' extra)")
    _run, out = built_docs
    refused = []
    with sync_api.sync_playwright() as p:
        browser = p.chromium.launch(executable_path=chromium, args=["--no-sandbox"])
        page = browser.new_page()

        def only_files(route):
            if route.request.url.startswith("file://"):
                return route.continue_()
            refused.append(route.request.url)
            return route.abort()

        page.route("**/*", only_files)
        page.goto((out / "conventions.html").as_uri())
        page.wait_for_function("() => document.querySelectorAll('mjx-container').length > 5", timeout=60_000)
        assert page.locator("mjx-container").count() > 5
        browser.close()
    assert refused == []


# ---------------------------------------------------------------------------- getting started
def _blocks(text):
    """``(kind, body)`` of every fenced block of a Markdown page, in order."""
    return [(m.group(1), m.group(2)) for m in re.finditer(r"^```(\w[\w-]*)\n(.*?)^```$", text, re.S | re.M)]


@pytest.mark.parametrize("page, least", [("getting-started", 4), ("tutorial", 8)])
def test_pages_show_the_real_outputs(page, least, tmp_path, monkeypatch):
    """Console and Python blocks run and print what the page shows; a YAML block headed ``# NAME.yaml`` is that file."""
    from noslipsim.cli import main

    shutil.copytree(ROOT / "examples", tmp_path / "examples")
    monkeypatch.chdir(tmp_path)
    blocks = _blocks((DOCS / f"{page}.md").read_text())
    namespace, checked = {}, 0
    for (kind, body), nxt in zip(blocks, [*blocks[1:], (None, None)]):
        name = re.match(r"# (\S+\.yaml)", body or "")
        if kind == "yaml" and name:
            (tmp_path / name.group(1)).write_text(body)
        elif kind == "console":
            command, *expected = body.splitlines()
            assert command.startswith("$ noslipsim ")
            out, err = io.StringIO(), io.StringIO()
            with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
                main(command.split()[2:])
            assert (out.getvalue() + err.getvalue()).splitlines() == expected, command
            checked += 1
        elif kind == "python":
            out = io.StringIO()
            with contextlib.redirect_stdout(out):
                exec(compile(body, f"{page}.md", "exec"), namespace)
            if nxt[0] == "text":
                assert [line.rstrip() for line in out.getvalue().splitlines()] == \
                       [line.rstrip() for line in nxt[1].splitlines()], body
                checked += 1
    assert checked >= least


# ---------------------------------------------------------------------------- docstrings
def test_docstrings_point_to_the_docs_not_to_the_design_notes():
    """Users have docs/, not the team's design notes."""
    src = ROOT / "src" / "noslipsim"
    offenders = [str(p.relative_to(src)) for p in src.rglob("*.py") if "DESIGN" in p.read_text()]
    assert not offenders, offenders
