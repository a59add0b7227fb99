"""Measures of two-phase flows: a drop's pressure jump, a bubble's centre, rise velocity and circularity."""

import numpy as np


def pressure_jump(sim, radius: float, centre=None) -> float:
    """The mean pressure of material 0 within radius/2 of `centre` (default: material 0's
    centroid) less the mean pressure of the other materials beyond 1.5 radius from it
    (periodic boxes: distances taken across the period)."""
    fluid = sim.fluid
    x, p, mat = sim.positions()[fluid], sim.pressure()[fluid], sim.materials()[fluid]
    c = x[mat == 0].mean(axis=0) if centre is None else np.asarray(centre, float)
    d = x - c
    lo, hi = (np.asarray(v, float) for v in sim.scene.domain)
    for axis, periodic in enumerate(sim.scene.periodic or ()):
        if periodic:
            span = hi[axis] - lo[axis]
            d[:, axis] -= span * np.round(d[:, axis] / span)
    r = np.linalg.norm(d, axis=1)
    inside = (mat == 0) & (r < 0.5 * radius)
    outside = (mat != 0) & (r > 1.5 * radius)
    return float(p[inside].mean() - p[outside].mean())


def bubble_state(sim, material: int = 1) -> tuple:
    """(height of the centre of mass, rise velocity) of `material`'s particles, volume
    weighted as Hysing et al. (2009) define them: y_c = int y dA / int dA,
    v_c = int v dA / int dA over the bubble."""
    fluid = sim.fluid
    sel = fluid & (sim.materials() == material)
    volume = sim.masses()[sel] / sim.density()[sel]
    y = sim.positions()[sel, 1]
    v = sim.velocities()[sel, 1]
    return float((volume * y).sum() / volume.sum()), float((volume * v).sum() / volume.sum())


# Hysing et al. (2009), Int. J. Numer. Meth. Fluids 60:1259, the benchmark quantities of their
# finest solutions (test case 1: table IV; test case 2: the first rise-velocity maximum of
# their figure 10 / table VIII, as the issue quotes them)
HYSING_1 = dict(max_rise_velocity=0.2417, time_of_max=0.921, centre_at_3=1.081, min_circularity=0.9013)
HYSING_2 = dict(first_max_rise_velocity=0.25, time_of_first_max=0.73)


def rising_bubble_history(dx: float, test_case: int = 1, t_end: float = 3.0, every: float = 0.02,
                          circularity: bool = True, **case) -> dict:
    """Run ``rising_bubble`` and sample, every `every` s, the bubble's centre height, rise
    velocity and (with `circularity`) circularity (:mod:`taisph.validation.interface`).
    Returns arrays ``time``, ``centre``, ``velocity``, ``circularity``, and ``mass``: each
    phase's total mass at the start and the end; ``wall``: seconds of wall time."""
    import time as clock

    import taisph
    from .interface import bubble_circularity

    scene = taisph.cases.rising_bubble(dx=dx, test_case=test_case, t_end=t_end, frames=1, **case)
    sim = taisph.Simulation(scene)
    masses = lambda: [float(sim.masses()[sim.fluid & (sim.materials() == k)].sum()) for k in (0, 1)]  # noqa: E731
    out = dict(time=[], centre=[], velocity=[], circularity=[], mass=[masses()])
    start = clock.perf_counter()
    n = int(round(t_end / every))
    for k in range(1, n + 1):
        sim.run(t_end=k * every)
        centre, velocity = bubble_state(sim)
        out["time"].append(sim.time)
        out["centre"].append(centre)
        out["velocity"].append(velocity)
        out["circularity"].append(bubble_circularity(sim)[0] if circularity else np.nan)
    out["wall"] = clock.perf_counter() - start
    out["mass"].append(masses())
    out["steps"] = sim.steps
    return {k: np.asarray(v) if isinstance(v, list) else v for k, v in out.items()}
