"""SDFormat models of the quadruped generated from the parameters: one fixed-hip leg, and the
whole robot. Each leg's links, joints and loop closure are its mechanism's SDF elements
(mechanisms/fivebar/sdf.py), placed in a leg-plane frame `<leg>_plane` at the hip; only the
foot spheres (and the body box) collide.
"""

from __future__ import annotations

from pathlib import Path
from xml.dom import minidom
import numpy as np

from fivebar_drake.core.files import write_atomic
from fivebar_drake.core.sdf import fmt
from fivebar_drake.mechanisms.base import Bushing, SdfLook
from fivebar_drake.robots.quadruped.params import Params


LEGS = ("FL", "FR", "RL", "RR")

# Body frame: x forward, y left, z up. Leg plane: x backwards, y up, z (hinge) to the left.
PLANE_RPY = (np.pi / 2, 0.0, np.pi)


def leg_sdf(params: Params, leg: str, parent: str, hip_xyz, closure: str,
            bushing: Bushing | None) -> str:
    """SDF of one leg attached to link `parent`: its leg-plane frame at hip_xyz (m) in the
    parent frame, then the mechanism's elements dressed with this robot's link width, foot pad
    and motors."""
    b, m = params.body, params.motor
    pad = (f"<geometry><sphere><radius>{b.foot_radius_m:.12g}</radius></sphere></geometry>")
    foot = (f"<collision name='foot'>{{pose}}{pad}<drake:proximity_properties><drake:mu_dynamic>"
            f"{b.foot_friction:.12g}</drake:mu_dynamic><drake:mu_static>{b.foot_friction:.12g}"
            f"</drake:mu_static><drake:point_contact_stiffness>{b.foot_stiffness_N_m:.12g}"
            f"</drake:point_contact_stiffness><drake:relaxation_time>"
            f"{b.foot_relaxation_time_s:.12g}</drake:relaxation_time></drake:proximity_properties>"
            f"</collision><visual name='foot'>{{pose}}{pad}<material><diffuse>0.1 0.1 0.1 1"
            "</diffuse></material></visual>")
    # The plant clamps actuation at the effort limit; the motor model (core.motor.MotorModel)
    # is the authority on saturation, and its output includes friction, which can add to it.
    effort = m.max_applied_torque_Nm
    drive = (f"<limit><effort>{effort:.12g}</effort></limit></axis>"
             f"<drake:rotor_inertia>{m.rotor_inertia_kg_m2:.12g}</drake:rotor_inertia>"
             f"<drake:gear_ratio>{m.gear_ratio:.12g}</drake:gear_ratio>")
    look = SdfLook(link_width_m=b.link_width_m, tool_xml=foot, actuated_joint_xml=drive)
    frame = (f"<frame name='{leg}_plane' attached_to='{parent}'><pose relative_to='{parent}'>"
             f"{fmt(*hip_xyz, *PLANE_RPY)}</pose></frame>")
    return frame + "\n" + params.mechanism.sdf_elements(leg, parent, f"{leg}_plane", closure,
                                                        bushing, look)


def hip_positions(params: Params) -> dict[str, tuple[float, float, float]]:
    """Leg-plane origins (m) in the body frame, legs FL, FR, RL, RR."""
    b = params.body
    return {leg: ((b.hip_x_m if leg[0] == "F" else -b.hip_x_m),
                  (b.hip_y_m if leg[1] == "L" else -b.hip_y_m), b.hip_z_m) for leg in LEGS}


def body_height(params: Params, foot_y):
    """Body height (m) at which feet at leg-plane height foot_y (m) touch flat ground."""
    return params.body.foot_radius_m - params.body.hip_z_m - np.asarray(foot_y)


def plane_to_body(hips_m, points_m) -> np.ndarray:
    """Body-frame positions (m) of leg-plane points (..., 2) m of legs whose plane origins are at
    hips_m (..., 3) m in the body frame (arrays broadcast): hip + R_body_plane [x, y, 0]."""
    return np.asarray(hips_m) + np.asarray(points_m) @ plane_rotation()[:, :2].T


def motor_positions(params: Params) -> np.ndarray:
    """Positions (8, 3) in m of the motor axes A and B of every leg in the body frame."""
    hips = np.array(list(hip_positions(params).values()))[:, None, :]
    return plane_to_body(hips, np.array([params.leg.motor_a_m, params.leg.motor_b_m])).reshape(-1, 3)


def plane_rotation() -> np.ndarray:
    """R_body_plane: columns are the leg plane's x (backwards), y (up), z (left) in the body."""
    return np.array([[-1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]])


def body_mass_properties(params: Params):
    """Mass (kg), COM (3,) in m and inertia (3, 3) about the COM in kg*m^2 of the body: the
    battery and structure as a uniform box, the 8 motors as point masses at their axes. The links
    are subtracted from the structure so the whole robot weighs robot.total_mass_kg (Params
    checks that they weigh less)."""
    r, b = params.robot, params.body
    links_kg = len(LEGS) * sum(link.mass_kg for link in params.links.values())
    box_kg = r.battery_electronics_kg + r.structure_kg - links_kg
    motors = motor_positions(params)
    motor_kg = r.motors_kg / len(motors)
    mass = box_kg + r.motors_kg
    com = motor_kg * motors.sum(0) / mass
    dims = np.array([b.length_m, b.width_m, b.height_m])
    inertia = np.diag(box_kg / 12.0 * (np.sum(dims**2) - dims**2))
    inertia += box_kg * (com @ com * np.eye(3) - np.outer(com, com))
    for p in motors - com:
        inertia += motor_kg * (p @ p * np.eye(3) - np.outer(p, p))
    return mass, com, inertia


def _body_link(params: Params) -> str:
    mass, com, inertia = body_mass_properties(params)
    b = params.body
    box = f"<geometry><box><size>{fmt(b.length_m, b.width_m, b.height_m)}</size></box></geometry>"
    return (f"<link name='body'><inertial><pose>{fmt(*com)} 0 0 0</pose><mass>{mass:.12g}</mass>"
            f"<inertia><ixx>{inertia[0, 0]:.12g}</ixx><iyy>{inertia[1, 1]:.12g}</iyy>"
            f"<izz>{inertia[2, 2]:.12g}</izz><ixy>{inertia[0, 1]:.12g}</ixy>"
            f"<ixz>{inertia[0, 2]:.12g}</ixz><iyz>{inertia[1, 2]:.12g}</iyz></inertia></inertial>"
            f"<visual name='box'>{box}<material><diffuse>0.6 0.6 0.65 1</diffuse></material>"
            f"</visual><collision name='box'>{box}</collision></link>")


def _document(name: str, body: str) -> str:
    text = (f"<sdf version='1.9' xmlns:drake='http://drake.mit.edu'><model name='{name}'>{body}"
            "</model></sdf>")
    pretty = minidom.parseString(text.replace("\n", "")).toprettyxml(indent="  ")
    return pretty.replace("?>", "?>\n<!-- Generated by fivebar_drake.robots.quadruped.sdf from the "
                          "parameter file (fivebar-drake models); do not edit. -->", 1)


def quadruped_sdf(params: Params, closure: str, bushing: Bushing | None) -> str:
    """The whole robot: a floating body and four legs (FL, FR, RL, RR)."""
    legs = [leg_sdf(params, leg, "body", hip, closure, bushing)
            for leg, hip in hip_positions(params).items()]
    return _document("quadruped", "\n".join([_body_link(params)] + legs))


def single_leg_sdf(params: Params, closure: str, bushing: Bushing | None) -> str:
    """One leg on a hip link welded to the world; the leg plane is the world x-z plane with the
    leg's y along world +z (gravity along the leg's -y)."""
    m = params.robot.motors_kg / (2 * params.robot.legs)
    hip = (f"<link name='hip'><inertial><mass>{m:.12g}</mass><inertia><ixx>1e-4</ixx>"
           "<iyy>1e-4</iyy><izz>1e-4</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia>"
           "</inertial></link><joint name='hip_weld' type='fixed'><parent>world</parent>"
           "<child>hip</child></joint>")
    return _document("leg", hip + "\n" + leg_sdf(params, "leg", "hip", (0, 0, 0), closure, bushing))

MODEL_FILES = {"leg.sdf": (single_leg_sdf, "bushing_rpy"),
               "quadruped.sdf": (quadruped_sdf, "bushing_rpy"),
               "quadruped_ball.sdf": (quadruped_sdf, "ball")}


def write_models(params: Params, bushing: Bushing, out_dir: Path) -> list[Path]:
    """Write the MODEL_FILES into out_dir, each atomically: the fixed-hip leg and the quadruped
    closed by the explicit bushing, and the quadruped closed by ball constraints."""
    out_dir.mkdir(parents=True, exist_ok=True)
    return [write_atomic(out_dir / name, make(params, closure, bushing))
            for name, (make, closure) in MODEL_FILES.items()]
