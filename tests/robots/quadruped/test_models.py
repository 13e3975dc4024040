"""The SDF models: generated from the one parameter file, loadable without warnings, physical."""

import gc
from pathlib import Path

import numpy as np
import pytest
from pydrake.multibody.plant import DiscreteContactApproximation, MultibodyPlant
from pydrake.visualization import ModelVisualizer

from fivebar_drake.robots.quadruped.closure import CLOSURES, MODEL_FILES
from fivebar_drake.robots.quadruped.plant import add_model
from fivebar_drake.simulation.scenario import load_scenario
from fivebar_drake.robots.quadruped.sdf import body_mass_properties
from fivebar_drake.simulation.builder import closure_design

SDF = Path(__file__).parents[3] / "sdf"


def test_committed_models_match_the_parameter_file(params):
    bushing = closure_design(load_scenario(closure="bushing_rpy"), params).bushing
    for name, (make, closure) in MODEL_FILES.items():
        assert (SDF / name).read_text() == make(params, closure, bushing), \
            f"sdf/{name} is stale: run `fivebar-drake models`"


@pytest.mark.parametrize("name", sorted(MODEL_FILES))
def test_models_load_in_model_visualizer_without_warnings(name):
    visualizer = ModelVisualizer(publish_contacts=False)
    visualizer.parser().plant().set_discrete_contact_approximation(
        DiscreteContactApproximation.kSap)                   # ball constraints need SAP
    visualizer.parser().SetStrictParsing()      # any parser warning becomes an error
    visualizer.AddModels(SDF / name)
    visualizer.Run(loop_once=True)
    # Drake's Meshcat must be destroyed on the thread that made it: left to the garbage
    # collector, a collection that happens to run on another thread (a Dask client's event loop
    # of an earlier test) aborts the process (seen once in a CI run)
    del visualizer
    gc.collect()


@pytest.mark.parametrize("closure", ["bushing", "bushing_rpy", "ball"])
def test_quadruped_plant_is_physical(params, closure):
    plant = MultibodyPlant(1e-3)
    plant.set_discrete_contact_approximation(DiscreteContactApproximation.kSap)
    instance, legs = add_model(plant, params, "quadruped", CLOSURES[closure](),
                               closure_design(load_scenario(closure="bushing"), params).bushing)
    plant.Finalize()
    context = plant.CreateDefaultContext()
    assert plant.CalcTotalMass(context) == pytest.approx(params.robot.total_mass_kg, rel=1e-12)
    assert plant.num_actuators() == 8                         # knees C, D are passive
    for leg in legs:
        for joint in ("C", "D"):
            assert not plant.HasJointActuatorNamed(f"{leg}_{joint}", instance)
    for body in plant.GetBodyIndices(instance):
        inertia = plant.get_body(body).default_rotational_inertia()
        assert inertia.CouldBePhysicallyValid(), plant.get_body(body).name()
    n_bushings = plant.num_force_elements() - 1               # minus gravity
    assert n_bushings == (4 if closure == "bushing_rpy" else 0)
    assert plant.num_constraints() == {"ball": 4, "bushing": 8, "bushing_rpy": 0}[closure]
    if closure == "bushing":                                  # two springs per leg, as designed
        springs = plant.GetDefaultDistanceConstraintParams().values()
        assert len(springs) == 8
        assert all(np.isfinite(c.stiffness()) and c.stiffness() > 0 and c.damping() > 0
                   for c in springs)


def test_body_mass_layout(params):
    mass, com, inertia = body_mass_properties(params)
    links = 4 * sum(link.mass_kg for link in params.links.values())
    assert mass + links == pytest.approx(params.robot.total_mass_kg)
    assert np.allclose(com, 0.0, atol=1e-12)                  # symmetric layout
    assert np.all(np.linalg.eigvalsh(inertia) > 0)
