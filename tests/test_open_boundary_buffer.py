"""An open boundary's buffer is kept at a lattice's spacing (taisph/terms/open_boundary_buffer.py):
the younger of a crowded pair is retired; with a summed density a hole gets a particle;
neither touches the fluid's mass."""

import numpy as np
import pytest

import taisph
from test_open_boundaries import DX, H, L, stream


def _without(scene, drop):
    """The scene with the particles of mask `drop` removed."""
    keep = ~drop
    for name in ("position", "velocity", "mass", "density", "kind", "material"):
        setattr(scene, name, getattr(scene, name)[keep])
    scene.quantities = {k: v[keep] for k, v in scene.quantities.items()}
    return scene


@pytest.mark.parametrize("summation", [True, False])
def test_a_crowded_pair_is_thinned_and_with_a_summed_density_a_hole_filled(summation):
    """Water at rest between equal pressures; one particle taken out of the inlet's buffer
    (second row, mid-height) and one of the outlet's moved to 0.3 dx from an older neighbour.
    After a step the outlet's younger particle of the pair is gone; with the density
    summed, the inlet's buffer has a particle at the hole's site (to round-off) and the
    outlet's the pair's old site, each as many particles as before; with the density
    evolved both holes stay (there filling fed mass in). The fluid's mass is unchanged
    (buffers are not fluid)."""
    scene = stream(u=0.0, summation=summation)
    zone = scene.quantities["open_zone"]
    x = scene.position
    hole = np.array([-1.5 * DX, H / 2 + 0.5 * DX])
    hole_index = np.argmin(np.where(zone == 1, np.linalg.norm(x - hole, axis=1), np.inf))
    assert np.linalg.norm(x[hole_index] - hole) < 1e-12
    n_inlet = int(np.sum(zone == 1))
    scene = _without(scene, np.arange(len(x)) == hole_index)
    zone, x = scene.quantities["open_zone"], scene.position
    pair = [np.argmin(np.where(zone == 2, np.linalg.norm(x - p, axis=1), np.inf))
            for p in ([L + 1.5 * DX, H / 4 + 0.5 * DX], [L + 1.5 * DX, H / 4 + 1.5 * DX])]
    older, younger = min(pair), max(pair)  # ids follow the order of the arrays
    site = x[younger].copy()
    crowded = x[older] + 0.3 * (site - x[older])  # 0.3 dx from the older one
    x[younger] = crowded
    sim = taisph.Simulation(scene)
    m0, n_fluid = sim.total_mass(), sim.n_fluid
    sim.run(sim.time + 1e-9, frames=0)  # one step
    buffer_x = sim.positions()[sim.buffer]
    inlet, outlet = buffer_x[buffer_x[:, 0] < 0], buffer_x[buffer_x[:, 0] > L]
    assert np.min(np.linalg.norm(outlet - crowded, axis=1)) > 0.29 * DX
    if summation:
        assert len(inlet) == n_inlet and np.min(np.linalg.norm(inlet - hole, axis=1)) < 1e-12
        assert len(outlet) == n_inlet and np.min(np.linalg.norm(outlet - site, axis=1)) < 1e-12
    else:
        assert len(inlet) == n_inlet - 1 and np.min(np.linalg.norm(inlet - hole, axis=1)) > 0.99 * DX
        assert len(outlet) == n_inlet - 1 and np.min(np.linalg.norm(outlet - site, axis=1)) > 0.69 * DX
    assert sim.total_mass() == m0 and sim.n_fluid == n_fluid
