"""SDFormat models generated from the parameters: one fixed-hip leg, and the quadruped.

Every leg lives in a *leg-plane frame* `<leg>_plane` whose x-y plane is the seed's leg plane
(x, y) and whose z axis is the hinge axis, so a joint angle about +z is the seed's
counter-clockwise motor angle. Each link's frame sits at its first joint with x along the link
in the zero configuration; the knee joints C and D measure the lower link relative to the upper
one. The loop E is cut: frames `<leg>_E_on_CE` and `<leg>_E_on_DE` (z along the hinge) are joined
by a `<drake:linear_bushing_rpy>` (closure "bushing_rpy"), a `<drake:ball_constraint>` (closure
"ball"), or by two compliant SAP distance constraints that SDFormat cannot declare and the plant
builder adds (closure "bushing", see plant_model.add_model). Only the foot spheres (and the body
box) collide.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from xml.dom import minidom
import numpy as np

from fivebar_drake.core.files import write_atomic
from fivebar_drake.mechanisms.fivebar.geometry import LINK_NAMES, physical_izz
from fivebar_drake.robots.quadruped.params import Params


LEGS = ("FL", "FR", "RL", "RR")

# Body frame: x forward, y left, z up. Leg plane: x backwards, y up, z (hinge) to the left.
PLANE_RPY = (np.pi / 2, 0.0, np.pi)


@dataclass(frozen=True)
class Bushing:
    """Linear bushing closing the loop at E: force stiffness (N/m) and damping (N*s/m)."""

    stiffness_N_m: float
    damping_N_s_m: float


def _fmt(*values) -> str:
    return " ".join(f"{v:.12g}" for v in values)


def _inertia(mass, ixx, iyy, izz) -> str:
    return (f"<inertial><pose>{{com}} 0 0 0 0 0</pose><mass>{mass:.12g}</mass><inertia>"
            f"<ixx>{ixx:.12g}</ixx><iyy>{iyy:.12g}</iyy><izz>{izz:.12g}</izz>"
            "<ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia></inertial>")


def link_inertias(params: Params) -> dict[str, tuple[float, float, float]]:
    """(Ixx, Iyy, Izz) about each link's COM in the link frame (x along the link, z hinge), in
    kg*m^2: Izz and Iyy are the seed's hinge value (thin-rod estimate where the seed says ~0),
    Ixx about the long axis is that of a square section of side link_width_m, m w^2 / 6; the
    triangle inequality holds since Ixx >= 0 and Iyy = Izz."""
    w = params.body.link_width_m
    return {name: (params.links[name].mass_kg * w**2 / 6.0, izz, izz)
            for name, izz in zip(LINK_NAMES, physical_izz(params.leg, params.links))}


def _link(params: Params, leg: str, name: str, origin, color: str) -> str:
    link = params.links[name]
    length = params.leg.link_length(name)
    ixx, iyy, izz = link_inertias(params)[name]
    w = params.body.link_width_m
    inertial = _inertia(link.mass_kg, ixx, iyy, izz).replace("{com}", f"{link.com_m:.12g}")
    extra = ""
    if name == "DE":
        r = params.body.foot_radius_m
        foot = f"<pose>{_fmt(length)} 0 0 0 0 0</pose><geometry><sphere><radius>{r:.12g}</radius></sphere></geometry>"
        extra = (f"<collision name='foot'>{foot}<drake:proximity_properties><drake:mu_dynamic>"
                 f"{params.body.foot_friction:.12g}</drake:mu_dynamic><drake:mu_static>"
                 f"{params.body.foot_friction:.12g}</drake:mu_static><drake:point_contact_stiffness>"
                 f"{params.body.foot_stiffness_N_m:.12g}</drake:point_contact_stiffness>"
                 f"<drake:relaxation_time>{params.body.foot_relaxation_time_s:.12g}"
                 "</drake:relaxation_time></drake:proximity_properties>"
                 f"</collision><visual name='foot'>{foot}<material><diffuse>0.1 0.1 0.1 1</diffuse>"
                 "</material></visual>")
    return (f"<link name='{leg}_{name}'><pose relative_to='{leg}_plane'>{_fmt(*origin)} 0 0 0 0"
            f"</pose>{inertial}<visual name='bar'><pose>{_fmt(length / 2)} 0 0 0 0 0</pose>"
            f"<geometry><box><size>{_fmt(length, w, w)}</size></box></geometry><material>"
            f"<diffuse>{color}</diffuse></material></visual>{extra}</link>")


def _joint(params: Params, leg: str, name: str, parent: str, child: str, motor: bool) -> str:
    m = params.motor
    # The plant clamps actuation at the effort limit; the motor model (systems.MotorModel) is the
    # authority on saturation, and its output includes friction, which can add to the torque.
    effort = m.peak_torque_Nm + m.coulomb_friction_Nm + m.viscous_friction_Nm_s * m.no_load_speed_rad_s
    limit = (f"<limit><effort>{effort:.12g}</effort></limit></axis>"
             f"<drake:rotor_inertia>{m.rotor_inertia_kg_m2:.12g}</drake:rotor_inertia>"
             f"<drake:gear_ratio>{m.gear_ratio:.12g}</drake:gear_ratio>" if motor
             else "<limit><effort>0</effort></limit></axis>")
    return (f"<joint name='{leg}_{name}' type='revolute'><parent>{parent}</parent>"
            f"<child>{leg}_{child}</child><axis><xyz>0 0 1</xyz>{limit}</joint>")


def leg_sdf(params: Params, leg: str, parent: str, hip_xyz, closure: str,
            bushing: Bushing | None) -> str:
    """SDF elements of one leg attached to link `parent`, leg-plane origin at hip_xyz (m) in
    the parent frame."""
    g = params.leg
    ax, ay = g.motor_a_m
    bx, by = g.motor_b_m
    parts = [f"<frame name='{leg}_plane' attached_to='{parent}'><pose relative_to='{parent}'>"
             f"{_fmt(*hip_xyz, *PLANE_RPY)}</pose></frame>",
             _link(params, leg, "AC", (ax, ay), "0.85 0.35 0.2 1"),
             _link(params, leg, "BD", (bx, by), "0.2 0.45 0.85 1"),
             _link(params, leg, "CE", (ax + g.ac_m, ay), "0.95 0.6 0.3 1"),
             _link(params, leg, "DE", (bx + g.bd_m, by), "0.35 0.65 0.95 1"),
             _joint(params, leg, "A", parent, "AC", True),
             _joint(params, leg, "B", parent, "BD", True),
             _joint(params, leg, "C", f"{leg}_AC", "CE", False),
             _joint(params, leg, "D", f"{leg}_BD", "DE", False),
             f"<frame name='{leg}_E_on_CE' attached_to='{leg}_CE'><pose relative_to='{leg}_CE'>"
             f"{_fmt(g.ce_m)} 0 0 0 0 0</pose></frame>",
             f"<frame name='{leg}_E_on_DE' attached_to='{leg}_DE'><pose relative_to='{leg}_DE'>"
             f"{_fmt(g.de_m)} 0 0 0 0 0</pose></frame>"]
    if closure == "ball":
        parts.append(
            f"<drake:ball_constraint><drake:ball_constraint_body_A>{leg}_CE"
            f"</drake:ball_constraint_body_A><drake:ball_constraint_p_AP>{_fmt(g.ce_m)} 0 0"
            f"</drake:ball_constraint_p_AP><drake:ball_constraint_body_B>{leg}_DE"
            f"</drake:ball_constraint_body_B><drake:ball_constraint_p_BQ>{_fmt(g.de_m)} 0 0"
            "</drake:ball_constraint_p_BQ></drake:ball_constraint>")
    if closure == "bushing_rpy":
        k, d = bushing.stiffness_N_m, bushing.damping_N_s_m
        parts.append(
            f"<drake:linear_bushing_rpy><drake:bushing_frameA>{leg}_E_on_CE</drake:bushing_frameA>"
            f"<drake:bushing_frameC>{leg}_E_on_DE</drake:bushing_frameC>"
            "<drake:bushing_torque_stiffness>0 0 0</drake:bushing_torque_stiffness>"
            "<drake:bushing_torque_damping>0 0 0</drake:bushing_torque_damping>"
            f"<drake:bushing_force_stiffness>{_fmt(k, k, k)}</drake:bushing_force_stiffness>"
            f"<drake:bushing_force_damping>{_fmt(d, d, d)}</drake:bushing_force_damping>"
            "</drake:linear_bushing_rpy>")
    return "\n".join(parts)


def hip_positions(params: Params) -> dict[str, tuple[float, float, float]]:
    """Leg-plane origins (m) in the body frame, legs FL, FR, RL, RR."""
    b = params.body
    return {leg: ((b.hip_x_m if leg[0] == "F" else -b.hip_x_m),
                  (b.hip_y_m if leg[1] == "L" else -b.hip_y_m), b.hip_z_m) for leg in LEGS}


def body_height(params: Params, foot_y):
    """Body height (m) at which feet at leg-plane height foot_y (m) touch flat ground."""
    return params.body.foot_radius_m - params.body.hip_z_m - np.asarray(foot_y)


def motor_positions(params: Params) -> np.ndarray:
    """Positions (8, 3) in m of the motor axes A and B of every leg in the body frame."""
    rot = plane_rotation()
    points = []
    for hip in hip_positions(params).values():
        for p in (params.leg.motor_a_m, params.leg.motor_b_m):
            points.append(np.asarray(hip) + rot @ np.array([p[0], p[1], 0.0]))
    return np.array(points)


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
    box = f"<geometry><box><size>{_fmt(b.length_m, b.width_m, b.height_m)}</size></box></geometry>"
    return (f"<link name='body'><inertial><pose>{_fmt(*com)} 0 0 0</pose><mass>{mass:.12g}</mass>"
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
