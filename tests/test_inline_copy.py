"""core.inline_copy: numba's inliner, copying a callee's scope once per copy, gives the same machine code."""
import collections
import copy
import os
import re
import subprocess
import sys

import numba
import pytest
from numba.core import inline_closurecall, ir

from noslipsim.core import inline_copy

pytestmark = pytest.mark.skipif(not inline_copy.APPLIES, reason="numba's inliner no longer copies block by block")

BRANCHES = 24


def _leaf(bias):
    """An inlined closure of many blocks (one ``if`` per step) with a constant branch on its cell."""
    lines = ["def leaf(x):", "    y = 0.0"]
    for k in range(BRANCHES):
        lines += [f"    if x > {k}.5:", f"        y += x * {k + 1}.0"]
    lines += ["    if BIAS:", "        y += 1.0", "    return y, x - y"]
    space = {"BIAS": bias}
    exec("\n".join(lines), space)
    return numba.njit(inline="always")(space["leaf"])


def _kernel(bias=True):
    """A non-inlined function calling an inlined step that calls the leaf twice in a loop (as the loop's steps)."""
    leaf = _leaf(bias)

    @numba.njit(inline="always")
    def step(x, n):
        total = 0.0
        for i in range(n):
            a, b = leaf(x + i)
            c, d = leaf(b)
            total += a + c - d
        return total

    def kernel(x, n):
        return step(x, n) + step(-x, n)

    return numba.njit(kernel)


def _llvm(dispatcher):
    """The optimised LLVM IR of the one compiled signature, with numba's per-function unique numbers removed."""
    text = dispatcher.inspect_llvm(dispatcher.signatures[0])
    text = re.sub(r"\s*;.*", "", text)  # comments (their alignment follows the label lengths)
    return re.sub(r"\$\d+|_\d{3,}|kernel\w*|\bB\d+|\[\d+ x i8\]", "N", text)  # names, labels, name lengths


def _scope_copies(monkeypatch):
    """For each inlining of one call site by numba, how many times it deep-copies each ``ir.Scope``."""
    copies = []  # one Counter per inlining: scope id -> copies
    numba_inline_ir = inline_copy._NUMBA_INLINE_IR

    def counted_scope_copy(self, memo):
        if copies and copies[-1] is not None:
            copies[-1][id(self)] += 1
        new = ir.Scope.__new__(ir.Scope)
        memo[id(self)] = new
        new.__dict__.update(copy.deepcopy(self.__dict__, memo))
        return new

    def counted_inline_ir(self, *args, **kwargs):
        copies.append(collections.Counter())
        try:
            return numba_inline_ir(self, *args, **kwargs)
        finally:
            copies.append(None)  # copies outside an inlining are not counted

    monkeypatch.setattr(ir.Scope, "__deepcopy__", counted_scope_copy, raising=False)
    monkeypatch.setattr(inline_copy, "_NUMBA_INLINE_IR", counted_inline_ir)
    monkeypatch.setattr(inline_closurecall.InlineWorker, "inline_ir", counted_inline_ir)
    return copies


def _most_copies(copies):
    """The most times one scope was copied within one inlining, and the number of inlinings."""
    inlinings = [c for c in copies if c is not None]
    return max(max(c.values()) for c in inlinings), len(inlinings)


def _compile(one_copy):
    kernel = _kernel()
    if one_copy:
        inline_copy.compile_with_one_copy(kernel)
    kernel(0.3, 5)  # (not against kernel.py_func: it would compile the steps outside a kernel)
    return kernel


def test_the_machine_code_is_numbas():
    one_copy, numba_copy = _compile(True), _compile(False)
    assert _llvm(one_copy) == _llvm(numba_copy)
    assert one_copy(0.3, 5) == numba_copy(0.3, 5) != 0.0


def test_the_scope_is_copied_once_per_copy_not_once_per_block(monkeypatch):
    copies = _scope_copies(monkeypatch)
    _compile(True)
    one_copy, inlinings = _most_copies(copies)
    copies.clear()
    _compile(False)
    per_block, numba_inlinings = _most_copies(copies)
    assert inlinings == numba_inlinings > 0
    assert one_copy == 1  # each scope once: the blocks of a copy share it
    assert per_block > BRANCHES  # numba's own: once for every block that refers to it


def test_installed_only_while_a_kernel_compiles():
    kernel = _kernel(bias=False)
    inline_copy.compile_with_one_copy(kernel)
    with pytest.raises(numba.core.errors.TypingError):
        kernel("not a number", 2)  # a compile that fails leaves numba as it was
    assert inline_closurecall.InlineWorker.inline_ir is inline_copy._NUMBA_INLINE_IR
    assert inline_closurecall.copy is copy
    kernel(0.5, 2)
    assert inline_closurecall.InlineWorker.inline_ir is inline_copy._NUMBA_INLINE_IR
    assert inline_closurecall.copy is copy


def test_the_core_compiles_with_it():
    from noslipsim.core import energy

    kernel = energy.settle  # any kernel of the core: jit.jit wraps its compile
    assert kernel.compile.__qualname__.startswith("compile_with_one_copy")


def test_it_can_be_turned_off():
    env = dict(os.environ, NOSLIPSIM_NUMBA_INLINE_COPY="numba")
    out = subprocess.run([sys.executable, "-c", "from noslipsim.core import inline_copy; print(inline_copy.APPLIES)"],
                         env=env, capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"
