"""Open boundaries' two algorithm options (OpenBoundaries.choose: uniform_inflow, fill_holes)
are declared, shown with the reason for their value, compiled only where on, and kept by
checkpoints' scene data."""

import pytest

import taisph
from taisph.engine import assembly, kernels
from taisph.messages import InputError
from taisph.scene import serialize
from taisph.terms import LaminarViscosity


def channel(**choices):
    scene = taisph.cases.channel(dx=1e-4)
    scene.terms_by_name["open_boundaries"].choose(**choices)
    scene.validate()
    return scene


def test_defaults_follow_the_scene_and_say_why():
    """The viscous channel (evolved density): no uniform inflow, no hole filling, each
    'default' with its reason; without its viscosity the extrapolated inlet gets uniform inflow."""
    described = channel().terms_by_name["open_boundaries"].describe()
    assert "uniform_inflow=off (default: laminar viscosity)" in described
    assert "fill_holes=off (default: evolved density)" in described
    inviscid = taisph.cases.channel(dx=1e-4)
    inviscid.terms = [t for t in inviscid.terms if not isinstance(t, LaminarViscosity)]
    inviscid.validate()
    assert "uniform_inflow=on (default: no viscosity)" in inviscid.terms_by_name["open_boundaries"].describe()


def test_a_chosen_option_is_compiled_in_and_shown():
    """Forcing uniform inflow on in the viscous channel traces its code (absent by default)
    and the header's description says it was chosen."""
    def traced(scene):
        assembly._cache.clear()
        kernels.TRACED.clear()
        taisph.Simulation(scene).step(2)
        return set(kernels.TRACED)

    assert ("open_boundaries", "uniform inflow") not in traced(channel())
    chosen = channel(uniform_inflow=True)
    assert ("open_boundaries", "uniform inflow") in traced(chosen)
    assert "uniform_inflow=on (chosen)" in chosen.terms_by_name["open_boundaries"].describe()


def test_bad_options_are_refused():
    with pytest.raises(InputError, match="no option fill"):
        channel(fill=True)
    with pytest.raises(InputError, match="must be true, false or none"):
        channel(fill_holes="yes")


def test_choices_survive_the_scene_data_of_a_checkpoint():
    data = serialize.scene_to_data(channel(fill_holes=True))
    restored = serialize.scene_from_data(*data) if isinstance(data, tuple) else serialize.scene_from_data(data)
    restored.validate()
    assert "fill_holes=on (chosen)" in restored.terms_by_name["open_boundaries"].describe()
