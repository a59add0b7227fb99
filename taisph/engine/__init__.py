"""The engine: how a scene's terms become Taichi kernels and how a step runs.

In the order of a step: :mod:`layout` (what is stored per particle),
:mod:`neighbours` (uniform grid, counting sort, neighbour lists),
:mod:`smoothing` (kernels W), :mod:`assembly` (kernels assembled from the terms),
:mod:`integrators`, :mod:`timestep` (dt), :mod:`guards`, :mod:`runtime` (Taichi's
process-wide settings). See docs/architecture.md.
"""
