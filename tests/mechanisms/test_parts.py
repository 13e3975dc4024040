"""One generic check per part of mechanisms/base.py, run over every registered mechanism on the
parts it names: kinematics (FK(IK) round trip in every mode, tool Jacobian against central
differences), statics (against Drake's tree inverse dynamics projected through the loops),
dynamics (a symmetric positive definite mass matrix whose Christoffel symbols give the bias
torques), Drake model (no loop gap at the tree coordinates of IK poses) and SDF elements (Drake
parses them into one actuator per motor and the tree's coordinates)."""

from collections.abc import Callable
import dataclasses
from dataclasses import dataclass
from functools import cache

import numpy as np
import pytest
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import AddMultibodyPlant, MultibodyPlantConfig
from pydrake.systems.framework import DiagramBuilder

from fivebar_drake.mechanisms import ballscrew_leg, scara
from fivebar_drake.mechanisms.base import SdfLook, missing_parts
from fivebar_drake.mechanisms.fivebar import LegLimits, sample_gait
from fivebar_drake.mechanisms.parallel4.mechanism import Parallel4
from fivebar_drake.mechanisms.registry import MECHANISMS
from fivebar_drake.robots.quadruped.closure import Ball, fixed_leg
from fivebar_drake.robots.quadruped.config import load_params
from fivebar_drake.robots.quadruped.inverse_dynamics import projected_inverse_dynamics
from fivebar_drake.robots.quadruped.leg_loads import full_model
from fivebar_drake.studies.ballscrew_leg.model import build_model
from fivebar_drake.studies.parallel4 import load_params as parallel4_params
from fivebar_drake.studies.parallel4.model import Parallel4Plant, gravity_load
from fivebar_drake.studies.scara.model import drake_terms


@dataclass
class Example:
    """A mechanism, tool points (n, d) it reaches in every mode, a load for static_torques and
    Drake's static torques (n, motors) of poses under that load."""

    mechanism: object
    points: np.ndarray
    load: object
    drake_static: Callable


def fivebar_leg() -> Example:
    loaded = load_params()      # the geometry's parts: without the leg's limits (test_limits.py)
    params = dataclasses.replace(loaded, leg=dataclasses.replace(loaded.leg, limits=LegLimits()))
    model = full_model(params)

    def drake(pose):
        plant, context, instance, idx = fixed_leg(params)
        rest = np.zeros(pose.q.shape)
        return projected_inverse_dynamics(plant, context, instance, params, "leg", idx, pose,
                                          rest, rest, model.foot_load_N)

    points = sample_gait(params.leg, params.gait).pose.f[::16]
    return Example(params.fivebar_leg, points, model, drake)


def ballscrew() -> Example:
    params = ballscrew_leg.load_params()
    lever = params.screw.lever_lengths_m[0]
    rig = build_model(params, lever, "bench")
    force = np.array([0.0, params.load.foot_force_N])

    def drake(pose):
        tau = rig.static_torques(rig.positions(pose), force)
        return tau * [1.0, 2.0 * np.pi / params.screw.lead_m]     # screw motor torque -> force

    points = np.array([[0.05, -0.3], [-0.1, -0.25], [0.0, -0.35]])
    return Example(ballscrew_leg.ball_screw_leg(params, lever), points, force, drake)


def scara_arm() -> Example:
    params = scara.load_params()
    inertia = scara.seed_inertia(params.links)

    def drake(pose):
        return drake_terms(params, inertia, pose.q, 0 * pose.q, 0 * pose.q)["gravity"]

    points = np.array([[0.25, 0.5, 0.4], [0.4, -0.2, 0.3], [-0.3, 0.35, 0.35]])
    return Example(scara.ScaraArm(params.kinematics, inertia), points, inertia, drake)


def parallel4() -> Example:
    params = parallel4_params(None)
    g, m = params.geometry, params.model

    def drake(pose):
        rig = Parallel4Plant(g, m, params.simulation.time_step_s)
        context, order = rig.plant.CreateDefaultContext(), rig.actuator_order()
        out = np.empty(pose.q.shape)
        for k, f in enumerate(pose.f):
            rig.plant.SetPositions(context, rig.positions(f))
            out[k, order] = rig.projected_static_forces(context)
        return out

    points = np.array([[0.1, 0.02, -0.3, 0.2], [-0.05, -0.03, -0.32, -0.4],
                       [0.0, 0.04, -0.31, 0.6]])
    mechanism = Parallel4(g)
    return Example(mechanism, points, lambda pose: gravity_load(g, m, pose.f), drake)


EXAMPLES = {"fivebar_leg": fivebar_leg, "ballscrew_leg": ballscrew, "scara": scara_arm,
            "parallel4": parallel4}


@cache
def example_of(name: str) -> Example:
    return EXAMPLES[name]()


def having(part: str) -> list[str]:
    """The registered mechanisms that name `part`."""
    return [name for name, cls in MECHANISMS.items() if part in cls.parts]


def poses(example: Example):
    """(mode, IK pose of the example's points, its forward branch) for every mode."""
    m = example.mechanism
    for mode in m.modes:
        pose = m.inverse(example.points, mode)
        branch = next(b for b in m.branches
                      if np.allclose(m.forward(pose.q, b).f, example.points, atol=1e-9))
        yield mode, pose, branch


def test_every_mechanism_has_an_example():
    assert set(EXAMPLES) == set(MECHANISMS)


@pytest.mark.parametrize("name", MECHANISMS)
def test_every_mechanism_implements_the_parts_it_names(name):
    mechanism = example_of(name).mechanism
    assert isinstance(mechanism, MECHANISMS[name])
    assert "kinematics" in mechanism.parts
    assert missing_parts(mechanism) == []


@pytest.mark.parametrize("name", having("kinematics"))
def test_kinematics_round_trip_in_every_mode(name):
    example = example_of(name)
    m = example.mechanism
    found = list(poses(example))       # StopIteration (an error) if no branch returns a point
    assert len(found) == len(m.modes)
    for _, pose, _ in found:
        assert pose.q.shape == example.points.shape[:-1] + (len(m.motors),)


@pytest.mark.parametrize("name", having("kinematics"))
def test_tool_jacobian_is_the_derivative_of_forward(name):
    example = example_of(name)
    m = example.mechanism
    for _, pose, branch in poses(example):
        h = 1e-6 * max(1.0, float(np.max(np.abs(pose.q))))
        steps = np.eye(len(m.motors)) * h
        fd = np.stack([(m.forward(pose.q + e, branch).f - m.forward(pose.q - e, branch).f)
                       / (2 * h) for e in steps], axis=-1)
        assert m.tool_jacobian(pose) == pytest.approx(fd, rel=1e-6, abs=1e-8)


@pytest.mark.parametrize("name", having("statics"))
def test_static_torques_agree_with_drake(name):
    example = example_of(name)
    m = example.mechanism
    pose = m.inverse(example.points, m.modes[0])
    load = example.load(pose) if callable(example.load) else example.load
    mine, drake = m.static_torques(load, pose), example.drake_static(pose)
    assert mine == pytest.approx(drake, rel=1e-9, abs=1e-9 * np.max(np.abs(drake)))


@pytest.mark.parametrize("name", having("dynamics"))
def test_bias_torques_are_the_christoffel_symbols_of_the_mass_matrix(name):
    example = example_of(name)
    m = example.mechanism
    rng = np.random.default_rng(20)
    n = len(m.motors)
    for _, pose, branch in poses(example):
        mass = m.mass_matrix(pose)
        assert mass == pytest.approx(np.swapaxes(mass, -1, -2), rel=1e-12, abs=1e-15)
        assert np.all(np.linalg.eigvalsh(mass) > 0)
        h = 1e-6
        dm = np.stack([(m.mass_matrix(m.forward(pose.q + e, branch))
                        - m.mass_matrix(m.forward(pose.q - e, branch))) / (2 * h)
                       for e in np.eye(n) * h], axis=-1)          # dm[..., i, j, k] = dM_ij/dq_k
        qd = rng.normal(size=pose.q.shape)
        # c_i = sum_jk (dM_ij/dq_k - dM_jk/dq_i / 2) qd_j qd_k
        want = (np.einsum("...ijk,...j,...k->...i", dm, qd, qd)
                - 0.5 * np.einsum("...jki,...j,...k->...i", dm, qd, qd))
        assert m.bias_torques(pose, qd) == pytest.approx(want, rel=1e-6,
                                                         abs=1e-7 * np.max(np.abs(want)))


@pytest.mark.parametrize("name", having("drake_model"))
def test_drake_model_closes_its_loops_at_ik_poses(name):
    example = example_of(name)
    m = example.mechanism
    for _, pose, _ in poses(example):
        gaps = m.loop_gaps(m.tree_positions(pose))
        assert np.all(np.abs(gaps) < 1e-12)


@pytest.mark.parametrize("name", having("sdf_elements"))
def test_sdf_elements_parse_into_one_actuator_per_motor(name):
    example = example_of(name)
    m = example.mechanism
    look = SdfLook(link_width_m=0.01, tool_xml="", effort_limit=1.0, drive_xml="")
    text = ("<sdf version='1.9' xmlns:drake='http://drake.mit.edu'><model name='m'>"
            "<link name='base'/><joint name='weld' type='fixed'><parent>world</parent>"
            f"<child>base</child></joint>{m.sdf_elements('m', 'base', 'base', Ball(), None, look)}"
            "</model></sdf>")
    config = MultibodyPlantConfig(time_step=1e-3, discrete_contact_approximation="sap")
    plant, _ = AddMultibodyPlant(config, DiagramBuilder())
    Parser(plant).AddModelsFromString(text, "sdf")
    plant.Finalize()
    assert plant.num_actuators() == len(m.motors)
    pose = m.inverse(example.points[0], m.modes[0])
    assert plant.num_positions() == m.tree_positions(pose).shape[-1]
