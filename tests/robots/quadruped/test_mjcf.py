"""The MJCF model (robots/quadruped/mjcf.py) in MuJoCo itself: generated from the parameter file
and committed current, the same robot as Drake's plant (mass, joint angles, closed loops), and
standing in MuJoCo's own physics on the torques the package's statics give."""

from pathlib import Path

import mujoco
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from fivebar_drake.mechanisms.fivebar import KNEES_OUT
from fivebar_drake.optimal.stand_up import static_torques
from fivebar_drake.robots.quadruped.legs import LEGS, PLANE_RPY, hip_positions
from fivebar_drake.robots.quadruped.mjcf import MJCF_FILE, quadruped_mjcf

SDF = Path(__file__).parents[3] / "sdf"


@pytest.fixture(scope="module")
def model(params):
    return mujoco.MjModel.from_xml_string(quadruped_mjcf(params))


def _ids(model, kind, names):
    return np.array([mujoco.mj_name2id(model, kind, n) for n in names])


def test_the_committed_mjcf_matches_the_parameter_file(params):
    assert (SDF / MJCF_FILE).read_text() == quadruped_mjcf(params), \
        f"sdf/{MJCF_FILE} is stale: run `fivebar-drake models --out sdf`"


def test_it_is_the_same_robot(model, params):
    """The robot's mass, 8 motors on A and B only, a loop closure per leg that holds at the
    reference pose, and the reference pose's joint angles the package's IK of the standing
    foot point (Drake's joint coordinates)."""
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    assert model.body_mass.sum() == pytest.approx(params.robot.total_mass_kg, rel=1e-12)
    assert model.nu == 8 and model.neq == len(LEGS)
    assert {mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, j) for j in
            model.actuator_trnid[:, 0]} == {f"{leg}_{m}" for leg in LEGS for m in "AB"}
    assert np.abs(data.efc_pos[:data.ne]).max() < 1e-12              # E meets E
    g = params.gait
    pose = params.fivebar_leg.inverse(np.array([g.x_center_m, g.y_home_m]), KNEES_OUT)
    joints = _ids(model, mujoco.mjtObj.mjOBJ_JOINT, [f"{leg}_{m}" for leg in LEGS for m in "AB"])
    assert np.allclose(model.qpos0[model.jnt_qposadr[joints]], np.tile(pose.q, len(LEGS)),
                       atol=1e-12)
    feet = _ids(model, mujoco.mjtObj.mjOBJ_GEOM, [f"{leg}_foot" for leg in LEGS])
    assert np.allclose(data.geom_xpos[feet][:, 2], params.body.foot_radius_m, atol=1e-12)


def test_it_stands_in_mujoco_on_the_packages_static_torques(model, params):
    """Held by a joint PD at the reference pose for 3 s of MuJoCo's physics (its own soft
    contact, the loops closed by its own constraint), the robot stands level and each motor's
    mean torque over the last second is the package's static torque (the links' weight and
    J_F^T of the vertical ground force) at the pose and the ground force MuJoCo settled at,
    within 5 % (what the statics leave out: the feet's friction forces, the joints' dry friction,
    the body's pitch of a degree)."""
    data = mujoco.MjData(model)
    names = [f"{leg}_{m}" for leg in LEGS for m in "AB"]
    joints = _ids(model, mujoco.mjtObj.mjOBJ_JOINT, names)
    q, v = model.jnt_qposadr[joints], model.jnt_dofadr[joints]
    target, held = model.qpos0[q].copy(), []
    for k in range(3000):
        data.ctrl[:] = 60.0 * (target - data.qpos[q]) - 1.5 * data.qvel[v]
        mujoco.mj_step(model, data)
        if k >= 2000:
            held.append(data.actuator_force.copy())
    held = np.mean(held, 0).reshape(len(LEGS), 2)
    body = data.xmat[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "body")].reshape(3, 3)
    assert np.degrees(np.arccos(body[2, 2])) < 2.0                   # level
    plane = Rotation.from_euler("xyz", PLANE_RPY).as_matrix()
    feet, loads = [], []
    for leg, hip in hip_positions(params).items():
        foot = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, f"{leg}_foot")
        hip_w = data.xpos[1] + body @ np.asarray(hip)
        feet.append((plane.T @ body.T @ (data.geom_xpos[foot] - hip_w))[:2])
        force, total = np.zeros(6), 0.0
        for i in range(data.ncon):
            if foot in (data.contact[i].geom1, data.contact[i].geom2):
                mujoco.mj_contactForce(model, data, i, force)
                total += force[0]
        loads.append(total)
    weight = params.robot.total_mass_kg * params.robot.gravity_m_s2
    assert sum(loads) == pytest.approx(weight, rel=1e-3)              # the feet carry it
    expected = static_torques(params, np.array(feet), np.array(loads))
    assert np.abs(held - expected).max() <= 0.05 * np.abs(expected).max()
