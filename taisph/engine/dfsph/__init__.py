"""DFSPH, the implicit incompressible solver (``Scene(solver="dfsph")``): the method and
its host loop (:mod:`.solver`), its kernel bodies (:mod:`.kernels`), what one neighbour
adds to each sum (:mod:`.visitors`) and the per-step pair list (:mod:`.pairs`)."""
