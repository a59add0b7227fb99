"""A scene described in a few lines, for the header of a run."""

from .solvers import dfsph_kept_terms


def describe(scene) -> str:
    """What :meth:`taisph.Scene.describe` prints."""
    if scene.solver == "dfsph":
        # DFSPH's step integrates with symplectic Euler whatever the scene's integrator (the
        # cases' default is pc, so refusing another would refuse them all): the header says so
        numerics = (f"solver dfsph (incompressible: pressure solve, symplectic Euler; the scene's "
                    f"integrator {scene.integrator} is not used)")
        kept = dfsph_kept_terms(scene)
        replaced = [t.name for t in scene.terms if t not in kept]
        effects = ", ".join(["DFSPH pressure" + (f" (in place of {', '.join(replaced)})" if replaced else "")]
                            + [t.describe() for t in kept])
    else:
        numerics = f"solver wcsph, integrator {scene.integrator}" + (
            f", Courant number {scene.courant:g}" if scene.courant is not None else "")
        effects = ", ".join(t.describe() for t in scene.terms)
    lines = [
        f"{scene.name}: {scene.description}".rstrip(": "),
        f"  {scene.dim}D, {scene.n_fluid} fluid + {scene.n_wall} wall particles, dx = {scene.dx:g} m, "
        f"h {'<=' if 'adaptive_h' in scene.terms_by_name else '='} {scene.smoothing_length:g} m "
        f"({scene.kernel} kernel), {numerics}",
        "  effects: " + effects,
    ]
    if any(scene.periodic):
        lines.append("  periodic along " + ", ".join("xyz"[k] for k, p in enumerate(scene.periodic) if p))
    if scene.open_faces:
        lines.append(f"  open at {', '.join(scene.open_faces)}: particles may leave and come back there")
    if scene.remove_escaped:
        lines.append("  particles that leave the domain" + (" elsewhere" if scene.open_faces else "")
                     + " are removed and counted, as are particles whose density leaves the guard's range "
                     "(up to max_out_of_range)")
    if scene.neighbour_skin > 0:
        lines.append(f"  neighbour lists with a skin of {scene.neighbour_skin:g} support radii")
    lines += [f"  open boundary {z.describe()}" for z in scene.open_boundaries]
    lines += [f"  {b.describe()}" for b in scene.bodies]
    return "\n".join(lines)
