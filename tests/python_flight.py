"""A flight module's Python source, for the tests that run the cell search as Python (``search.cell_search``).

``python_flight(module)`` is a module holding every function of ``module``'s flight protocol as its
Python function (``py_func``; the functions they call stay as they are, compiled or patched) and its
constants, so ``search.cell_search(python_flight(m), compile=lambda f: f)`` is the search's source
calling that source.
"""
import types

#: The names of the flight protocol (search.py's docstring).
PROTOCOL = ("start", "at_start", "window", "window_box", "shift", "element_exit", "state_at", "face_exit",
            "line_exit")
CONSTANTS = ("INLINE", "GIVES_UP")


def python_flight(module):
    """``module``'s flight protocol as Python functions (a new module object each call)."""
    out = types.ModuleType(f"{module.__name__}_py")
    for name in PROTOCOL:
        if hasattr(module, name):
            func = getattr(module, name)
            setattr(out, name, getattr(func, "py_func", func))
    for name in CONSTANTS:
        setattr(out, name, getattr(module, name))
    return out
