"""A 0.2 m water disc hitting the floor at 15 m/s with dummy-particle walls (docs/stability.md).

    python tools/drop_impact.py DX C0_OVER_V [DELTA] [MAX_DENSITY_ERROR]

e.g. `python tools/drop_impact.py 0.01 15 0.1` (c0 = 15 x 15 m/s, delta-SPH 0.1): runs to
0.1 s with 20 frames and prints the guard result, max density error and lowest y.
"""
import sys, numpy as np, taisph
from taisph.geometry import lattice, wall_layers
from taisph.terms import AdamiWall, ArtificialViscosity, Continuity, Gravity, PressureGradient, DensityDiffusion
from taisph.simulation import SimulationError
dx, radius, speed = float(sys.argv[1]), 0.2, 15.0
c0 = float(sys.argv[2]) * speed
delta = float(sys.argv[3]) if len(sys.argv) > 3 else 0
terms = [Continuity(walls=True), PressureGradient(walls=True), ArtificialViscosity(alpha=0.1), Gravity(), AdamiWall()]
if delta: terms.append(DensityDiffusion(delta=delta))
layers = 3
scene = taisph.Scene("drop", dim=2, dx=dx, smoothing_length=1.3 * dx, domain=([-4*dx, -4*dx], [2+4*dx, 2.0]),
                     materials=[taisph.Material(c0=c0)], terms=terms)
pts = lattice([1 - radius, 0.1], [1 + radius, 0.1 + 2 * radius], dx)
pts = pts[np.linalg.norm(pts - [1.0, 0.1 + radius], axis=1) < radius]
scene.add_fluid(pts, velocity=[0.0, -speed])
scene.add_walls(wall_layers([0, 0], [2, 1.5], dx, layers))
sim = taisph.Simulation(scene, max_density_error=float(sys.argv[4]) if len(sys.argv) > 4 else 0.2)
err = []; ymin = []
try:
    sim.run(0.1, frames=20, callback=lambda s: (err.append(np.abs(s.density()[s.fluid]/1000-1).max()), ymin.append(s.positions()[s.fluid,1].min())))
    st = "ok"
except SimulationError as e:
    st = "FAIL " + str(e).splitlines()[0][:120]
print(f"dx {dx} c0 {c0} delta {delta}: {st}; max drho {max(err, default=0)*100:.1f}%, min y {min(ymin, default=0):.4f}, steps {sim.steps}")
