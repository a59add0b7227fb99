"""Why a lone fluid particle next to dummy walls trips the density guard (docs/validation.md).

    python -m tools.studies.lone_particle_wall               # a lone particle at a flat wall, Courant 0.25/0.125/0.0625
    python -m tools.studies.lone_particle_wall --dam-break   # trace the particle that stops the 2D dam break

The flat wall: one fluid particle dx/2 from a flat dummy wall (3 layers, dx = 0.02 m,
cubic spline, h = 1.3 dx, the dam break's water: c0 = 34.3 m/s), no gravity, no other
fluid, started towards the wall at 0.5 m/s. Its only neighbours are wall particles, so
its density follows its distance from the wall (continuity with the walls' zero
velocity), and the walls take its own pressure (Adami's extrapolation from one fluid
particle): a spring, undamped since neither the artificial viscosity (fluid pairs
only) nor density diffusion (fluid pairs only) acts on it. Printed: the largest |v_x|
and the density range in each fifth of 1 s, for each Courant number, and with the
artificial viscosity acting on wall pairs too (``ArtificialViscosity(walls=True)``).

--dam-break: cases/dam_break_probes_2d.toml at dx = 0.02 m with the cubic spline
(h = 1.3 dx), alpha = 0.1 and Courant 0.25 (the example's settings before this
investigation), the guard off; every 20 steps from t = 1.1 s the particle that tripped
the guard (id 1773) is traced on the host: its position, velocity, density, its fluid
and wall neighbours, the continuity rate from each, and rho - sum_w m_w W_iw (its
density less the walls' kernel sum), which stays constant if its density is set by
its distance from the wall alone.
"""

import argparse
import math

import numpy as np

import taisph
from taisph import Material, Scene
from taisph.terms import AdamiWall, ArtificialViscosity, Continuity, PressureGradient

DX = 0.02
H = 1.3 * DX
C0 = 10 * math.sqrt(2 * 9.81 * 0.6)
SIGMA = 10 / (7 * math.pi) / H**2  # the 2D cubic spline


def w(r):
    q = r / H
    return SIGMA * np.where(q < 1, 1 - 1.5 * q**2 + 0.75 * q**3, np.where(q < 2, 0.25 * (2 - q) ** 3, 0.0))


def grad_factor(r):
    q = r / H
    return SIGMA / H**2 * np.where(q < 1, -3 + 2.25 * q, np.where(q < 2, -0.75 * (2 - q) ** 2 / np.maximum(q, 1e-12), 0.0))


class Every:
    """A run writer calling `record(sim)` every `every` steps."""

    def __init__(self, every, record):
        self.every, self.record = every, record

    def on_start(self, sim):
        pass

    def on_frame(self, sim, k):
        pass

    def on_steps(self, sim):
        sim._snapshot_key = None  # a fresh download each time
        self.record(sim)


def flat_wall(courant, wall_viscosity=False, t_end=1.0):
    terms = [Continuity(walls=True), PressureGradient(walls=True),
             ArtificialViscosity(alpha=0.1, walls=wall_viscosity), AdamiWall()]
    scene = Scene(name="lone", dim=2, dx=DX, smoothing_length=H,
                  domain=(np.array([-0.5, -0.5]), np.array([0.2, 0.5])),
                  materials=[Material("water", rho0=1000.0, c0=C0, gamma=7.0)], terms=terms)
    ys = np.arange(-0.5, 0.5, DX) + DX / 2
    scene.add_fluid([[-DX / 2, 0.0]], velocity=[[0.5, 0.0]])
    scene.add_walls(np.array([[DX / 2 + k * DX, y] for k in range(3) for y in ys]))
    sim = taisph.Simulation(scene, courant=courant, max_density_error=0.0)
    rows = []
    sim.run(t_end, frames=1, writers=[Every(1, lambda s: rows.append(
        (s.device_time(), s.velocities()[0, 0], s.density()[0])))])
    sim.close()
    rows = np.array(rows)
    line = f"Courant {courant:<6g}{' + wall viscosity' if wall_viscosity else '':18s}{len(rows):6d} steps: "
    for a, b in zip(np.linspace(0, t_end, 6)[:-1], np.linspace(0, t_end, 6)[1:]):
        part = rows[(rows[:, 0] >= a) & (rows[:, 0] < b)]
        line += f" |vx| {np.abs(part[:, 1]).max():5.2f}, rho {part[:, 2].min():4.0f}..{part[:, 2].max():4.0f};"
    print(line, flush=True)


def dam_break(particle=1773):
    from taisph.formats.scenefile import load
    from taisph.scene.catalogue import find_scene_file

    scene, _ = load(find_scene_file("dam_break_probes_2d.toml"),
                    {"dx": DX, "kernel": "spline", "h_factor": 1.3, "physics.alpha": 0.1, "courant": 0.25})
    sim = taisph.Simulation(scene, max_density_error=0.0, courant=0.25)

    def record(s):
        x, v, rho, m, kind = s.positions(), s.velocities(), s.density(), s.masses(), s.kinds()
        r = np.linalg.norm(x[particle] - x, axis=1)
        near = (r < 2 * H) & (np.arange(len(x)) != particle)
        fluid, wall = near & (kind == taisph.FLUID), near & (kind == taisph.WALL)
        vij = v[particle] - np.where((kind == taisph.WALL)[:, None], 0.0, v)
        rate = m * grad_factor(r) * np.einsum("ij,ij->i", vij, x[particle] - x)
        print(f"t = {s.device_time():.4f} s  x = ({x[particle, 0]:.4f}, {x[particle, 1]:.4f})  "
              f"v = ({v[particle, 0]:+6.2f}, {v[particle, 1]:+5.2f})  rho = {rho[particle]:6.1f}  "
              f"neighbours: {fluid.sum()} fluid, {wall.sum():2d} wall  d rho/dt from fluid {rate[fluid].sum():+8.0f}, "
              f"walls {rate[wall].sum():+8.0f}  rho - sum_w m W = {rho[particle] - (m * w(r))[wall].sum():6.1f}",
              flush=True)

    sim.run(1.1, frames=1)
    sim.run(1.4, frames=1, writers=[Every(20, record)])
    sim.close()


def main():
    parser = argparse.ArgumentParser(prog="python -m tools.studies.lone_particle_wall",
                                     description=__doc__.splitlines()[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    parser.add_argument("--dam-break", action="store_true", help="trace the particle that stops the dam break")
    args = parser.parse_args()
    if args.dam_break:
        dam_break()
        return
    for courant in (0.25, 0.125, 0.0625):
        flat_wall(courant)
    flat_wall(0.25, wall_viscosity=True)


if __name__ == "__main__":
    main()
