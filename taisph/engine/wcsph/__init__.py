"""WCSPH, the weakly compressible solver (``Scene(solver="wcsph")``, the default): the
scene's terms and equation of state, the scene's integrator, and the step of the
engine's kernels (:mod:`.method`)."""
