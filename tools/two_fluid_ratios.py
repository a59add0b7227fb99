"""Which density ratios the two-fluid formulation holds (docs/stability.md).

    python tools/two_fluid_ratios.py RATIO same|stiff [DX]

Runs `two_fluids` (heavy over light) to t = 1.5 s at DX (default 0.04) with the lower
fluid's c0 the same as the upper's ("same") or c0 sqrt(RATIO), the same stiffness B
("stiff"); prints whether a guard tripped, the max density error at 15 frames, particles
outside the box, the mass change and the heavy fluid's centre of mass height.
"""
import math
import sys

import numpy as np

import taisph
from taisph.simulation import SimulationError

ratio = float(sys.argv[1]); mode = sys.argv[2]; dx = float(sys.argv[3]) if len(sys.argv) > 3 else 0.04
c0 = 10.0 * math.sqrt(2.0 * 9.81 * 2.0)  # the case's default
lower_c0 = c0 * math.sqrt(ratio) if mode == "stiff" else None  # equal B = rho0 c0^2 / gamma
sc = taisph.cases.two_fluids(dx=dx, density_ratio=ratio, lower_c0=lower_c0)
sim = taisph.Simulation(sc)
m0 = sim.masses()[sim.fluid].sum(); mat = sim.materials()
rec = dict(err=0.0, out=0)
def cb(s):
    f = s.fluid
    rho0 = np.array([m.rho0 for m in s.scene.materials])[s.materials()[f]]
    rec["err"] = max(rec["err"], np.abs(s.density()[f] / rho0 - 1).max())
    x = s.positions()[f]
    rec["out"] = max(rec["out"], int(((x[:, 0] < 0) | (x[:, 0] > 1) | (x[:, 1] < 0)).sum()))
try:
    summ = sim.run(1.5, frames=15, callback=cb)
    status = "ok"
except SimulationError as e:
    status = "FAIL " + str(e).splitlines()[0][:150]
heavy = sim.fluid & (sim.materials() == 0)
print(f"ratio {ratio} {mode}: {status}; steps {sim.steps}, t {sim.time:.3f}, max density err {rec['err']*100:.2f}%, outside {rec['out']}, mass drift {sim.masses()[sim.fluid].sum()-m0:.3g}, heavy com y {sim.positions()[heavy,1].mean():.3f}")
