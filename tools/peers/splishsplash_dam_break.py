"""SPlisHSPlasH's DFSPH on taisph's 2D dam break: run in a Python with ``pysplishsplash``.

    LD_PRELOAD=libGL.so.1 /path/to/splash-venv/bin/python \
        -m tools.peers.splishsplash_dam_break --dx 0.01 --tf 0.2      # from the repository root

Writes a 2D scene (``"sim2D": true``): the 1 m x 2 m water column at the left wall of
a 4 m x 4 m tank (SPlisHSPlasH's UnitBox.obj scaled (4, 4, 1) and translated
(2, 2, 0), an inverted wall), particle radius dx/2, DFSPH (simulationMethod 4) with
maxError = maxErrorV = 0.1 %, volume-map boundaries (boundaryHandlingMethod 2),
CFL (cflMethod 1: dt = factor 0.4 (2 r) / max |v|, factor 1 unless ``--cfl-factor``;
step at most 0.005 s), standard viscosity 0.01; runs it
headless to tf and prints one JSON line from its log (``log/SPH_log.txt``): fluid
particles, steps, the mean time step, the summed simulation-step time ("Time sum:
SimStep") and the wall time of the run. Used by ``python -m tools.benchmarks.bench --compare-splishsplash``
(tools/peers/compare_splishsplash.py, which runs this file by its path); SPlisHSPlasH is not a taisph dependency.
"""

import argparse
import glob
import json
import os
import re
import sys
import tempfile
import time


MAP_RESOLUTION = [20, 20, 20]  # the volume map's grid (SPlisHSPlasH's default)


def scene(dx, box_obj, tf, map_resolution=MAP_RESOLUTION, max_error=0.1, max_error_v=0.1, cfl_factor=1.0):
    """The scene file of the run (SPlisHSPlasH 2.19's format: the DFSPH settings inside
    "Configuration", as in its own data/Scenes/DamBreakModel.json; at the top level
    they are ignored and its defaults, a 0.01 % density error, apply)."""
    return {
        "Configuration": {
            "pause": False, "sim2D": True, "particleRadius": dx / 2, "numberOfStepsPerRenderUpdate": 4,
            "simulationMethod": 4, "gravitation": [0, -9.81, 0], "cflMethod": 1, "cflFactor": cfl_factor,
            "cflMaxTimeStepSize": 0.005, "boundaryHandlingMethod": 2, "enableVTKExport": False,
            "enablePartioExport": False, "stopAt": tf,
            "DFSPH": {"minIterations": 2, "maxIterations": 100, "maxError": max_error, "maxIterationsV": 100,
                      "maxErrorV": max_error_v, "enableDivergenceSolver": True},
        },
        "Materials": [{"id": "Fluid", "density0": 1000, "viscosityMethod": 1,
                       "Standard viscosity": {"viscosity": 0.01}}],
        "RigidBodies": [{"geometryFile": box_obj, "translation": [2.0, 2.0, 0], "rotationAxis": [1, 0, 0],
                         "rotationAngle": 0, "scale": [4, 4, 1], "isDynamic": False, "isWall": True,
                         "mapInvert": True, "mapThickness": 0.0, "mapResolution": list(map_resolution)}],
        "FluidBlocks": [{"denseMode": 0, "start": [0.0, 0.0, -1], "end": [1.0, 2.0, 1], "translation": [0, 0, 0],
                         "scale": [1, 1, 1]}],
    }


def read_log(path):
    text = open(path).read()
    sim_step = re.findall(r"Time sum:\s*SimStep\s*:?\s*([0-9.eE+-]+)\s*ms", text)
    dt = re.findall(r"Total number:\s*Time step size\s*:?\s*([0-9.eE+-]+)", text)
    avg = re.findall(r"Average\s*:?\s*Time step size\s*:?\s*([0-9.eE+-]+)", text)
    return text, (float(sim_step[-1]) / 1e3 if sim_step else None), dt, avg


def main():
    ap = argparse.ArgumentParser(prog="python -m tools.peers.splishsplash_dam_break",
                                 description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dx", type=float, default=0.01)
    ap.add_argument("--tf", type=float, default=0.2)
    ap.add_argument("--out", default=None, help="output folder (default: a temporary one)")
    ap.add_argument("--map-resolution", type=int, nargs=3, default=MAP_RESOLUTION,
                    help="the walls' volume map grid (default: SPlisHSPlasH's 20 20 20)")
    ap.add_argument("--max-error", type=float, default=0.1, help="the density solve's mean error, %% (default 0.1)")
    ap.add_argument("--max-error-v", type=float, default=0.1, help="the divergence solve's, %% (default 0.1)")
    ap.add_argument("--cfl-factor", type=float, default=1.0,
                    help="cflFactor: dt = factor x 0.4 particle diameters / max |v| (default 1)")
    args = ap.parse_args()
    import pysplishsplash as sph  # noqa: F401  (needs the system libGL: LD_PRELOAD, see above)
    import pysplishsplash.Exec as Exec

    data = os.path.join(os.path.dirname(sys.executable), "data")
    box = os.path.join(data, "models", "UnitBox.obj")
    out = args.out or tempfile.mkdtemp(prefix="splash-dam-break-")
    os.makedirs(out, exist_ok=True)
    path = os.path.join(out, "dam_break_2d.json")
    with open(path, "w") as f:
        description = scene(args.dx, box, args.tf, args.map_resolution, args.max_error, args.max_error_v,
                            args.cfl_factor)
        json.dump(description, f, indent=1)
    base = Exec.SimulatorBase()
    base.init(["SPlisHSPlasH", "--no-gui", "--no-initial-pause", "--stopAt", str(args.tf), "--output-dir", out, path],
              "SPlisHSPlasH")
    start = time.perf_counter()
    base.run()
    wall = time.perf_counter() - start
    log = sorted(glob.glob(os.path.join(out, "log", "*.txt")))[-1]
    text, sim_step, _, _ = read_log(log)
    fluid = re.findall(r"Number of fluid particles:\s*([0-9]+)", text)
    mean_dt = re.findall(r"Average number:\s*Time step size:\s*([0-9.eE+-]+)", text)
    iterations = re.findall(r"Average number:\s*DFSPH - iterations:\s*([0-9.eE+-]+)", text)
    iterations_v = re.findall(r"Average number:\s*DFSPH - iterationsV:\s*([0-9.eE+-]+)", text)
    dt_mean = float(mean_dt[-1]) if mean_dt else None
    print(json.dumps(dict(code="SPlisHSPlasH DFSPH", dx=args.dx, cfl_factor=args.cfl_factor, sim_time=args.tf, wall=wall, sim_step_s=sim_step,
                          steps=round(args.tf / dt_mean) if dt_mean else None, dt_mean=dt_mean,
                          fluid=int(fluid[0]) if fluid else None,
                          density_iterations=float(iterations[-1]) if iterations else None,
                          divergence_iterations=float(iterations_v[-1]) if iterations_v else None, log=log)))


if __name__ == "__main__":
    main()
