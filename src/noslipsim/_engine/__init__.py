"""Internal build steps between a scene and the compiled kernels (not public API).

A scene goes to the kernels in three steps: :mod:`.canonical` rewrites a
periodic scene the way the kernels run it fastest (same billiard),
:mod:`.table` packs it into arrays and variant flags once (:class:`.table.KernelTable`),
and :mod:`.run` makes the one call of the compiled event loop and checks that
the code that ran is the variant asked for.  :mod:`.lattice` (cell
bookkeeping), :mod:`.junctions` (the points where elements meet) and
:mod:`.memo` (values kept per scene) serve them.
"""
