"""A copy of ``src/noslipsim`` at some commit, importable under another name beside the current package.

The package imports itself only relatively, so a copy under another name is a
second, independent package with its own numba cache (numba keys the cache on
the source file's path): benchmarks compile an old kernel and the current one in
one process and time them interleaved.
"""
import os
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def package_copy(commit, name, where, fresh=False):
    """Extract ``src/noslipsim`` at ``commit`` to ``where/name`` (unless there, or ``fresh``); ``where`` goes on sys.path.

    Returns the package's directory.
    """
    pkg = os.path.join(where, name)
    if fresh and os.path.isdir(pkg):
        shutil.rmtree(pkg)
    if not os.path.isdir(pkg):
        tmp = tempfile.mkdtemp()
        archive = subprocess.run(["git", "-C", ROOT, "archive", commit, "src/noslipsim"], check=True,
                                 capture_output=True).stdout
        subprocess.run(["tar", "-x", "-C", tmp], input=archive, check=True)
        os.makedirs(where, exist_ok=True)
        shutil.move(os.path.join(tmp, "src", "noslipsim"), pkg)
        shutil.rmtree(tmp)
    if where not in sys.path:
        sys.path.insert(0, where)
    return pkg
