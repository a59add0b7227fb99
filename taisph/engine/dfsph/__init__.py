"""DFSPH, the implicit incompressible solver (``Scene(solver="dfsph")``): its method, what
the engine asks of it (:mod:`.method`), its step and host loop (:mod:`.solver`), its
kernel bodies (:mod:`.kernels`), what one neighbour adds to each sum (:mod:`.visitors`),
the per-step pair list (:mod:`.pairs`), its runtime parameters (:mod:`.parameters`) and
its account of a failed run (:mod:`.diagnosis`)."""
