"""numba's inliner with the callee's IR copied once per copy, not once per block: the core's compile time.

numba inlines an ``inline="always"`` function by copying the callee's IR (``InlineWorker.inline_ir`` in
``numba.core.inline_closurecall``) twice per call site, one ``copy.deepcopy`` per block; every block
refers to the function's whole scope, so each copy costs ``blocks x variables`` (numba issue #8989, open
in 0.68): half of a kernel's compile (docs/algorithm.md, "One kernel call, ...", *Compile time*;
measured: benchmarks/RESULTS.md).  :func:`one_copy_inlining` makes every ``deepcopy`` of one
``inline_ir`` call share one memo, so the scope is copied once per copy; nothing else of the inliner
changes, and the machine code is the same (``tests/test_inline_copy.py``).  It is installed only while
a core kernel compiles (:func:`jit.jit`), under numba's compiler lock, and only where numba's inliner
still copies block by block (:data:`APPLIES`); ``NOSLIPSIM_NUMBA_INLINE_COPY=numba`` turns it off.
"""
import contextlib
import copy
import inspect
import os

from numba.core import inline_closurecall as _inliner
from numba.core.compiler_lock import global_compiler_lock

#: The statement of numba's ``inline_ir`` that copies one block on its own memo.
_PER_BLOCK_COPY = "copy.deepcopy(the_ir.blocks[block_label])"
_NUMBA_INLINE_IR = _inliner.InlineWorker.inline_ir


def _applies():
    if os.environ.get("NOSLIPSIM_NUMBA_INLINE_COPY") == "numba":
        return False
    try:
        source = inspect.getsource(_NUMBA_INLINE_IR)
    except (OSError, TypeError):  # no source to check against: leave numba as it is
        return False
    return _PER_BLOCK_COPY in source and getattr(_inliner, "copy", None) is copy


#: numba's inliner copies block by block, and the replacement is not turned off.
APPLIES = _applies()


class _OneMemo:
    """The ``copy`` module as numba's inliner sees it during one ``inline_ir``: one memo for every deepcopy."""

    def __init__(self):
        self.memo = {}

    def deepcopy(self, x, memo=None):
        return copy.deepcopy(x, self.memo if memo is None else memo)

    def __getattr__(self, name):
        return getattr(copy, name)


def _inline_ir_one_copy(self, *args, **kwargs):
    """numba's ``InlineWorker.inline_ir``, its block copies sharing one memo."""
    previous = _inliner.copy
    _inliner.copy = _OneMemo()
    try:
        return _NUMBA_INLINE_IR(self, *args, **kwargs)
    finally:
        _inliner.copy = previous


_depth = 0


@contextlib.contextmanager
def one_copy_inlining():
    """Compile with :func:`_inline_ir_one_copy` as numba's inliner (a no-op where it does not apply).

    Holds numba's compiler lock, so no other thread compiles with it; nested
    uses (a kernel compiling the kernels it calls) install it once.
    """
    global _depth
    if not APPLIES:
        yield
        return
    with global_compiler_lock:
        _depth += 1
        if _depth == 1:
            _inliner.InlineWorker.inline_ir = _inline_ir_one_copy
        try:
            yield
        finally:
            _depth -= 1
            if _depth == 0:
                _inliner.InlineWorker.inline_ir = _NUMBA_INLINE_IR


def compile_with_one_copy(dispatcher):
    """Make every compile of ``dispatcher`` (called from Python or typed in a caller) use :func:`one_copy_inlining`."""
    numba_compile = dispatcher.compile

    def compile(sig):
        with one_copy_inlining():
            return numba_compile(sig)

    dispatcher.compile = compile
