"""An MJCF model of the quadruped (MuJoCo's format) generated from the parameters, for whoever
goes on to MuJoCo (to learn a controller, say): the same bodies, masses, inertias, joints and
motors as the SDF (sdf.py), written in the robot's standing pose.

MuJoCo closes a loop with an equality constraint: each leg's `connect` joins the end of CE to
DE at E. Its anchor on DE is computed at the model's reference pose, so the bodies are written
in the standing pose (the gait's home foot point, knees out) and each hinge's `ref` is its
angle there: qpos then reads as the SDF's joint angles (A, B from the leg plane's x axis, C, D
the lower link's angle from the upper one), the same numbers as Drake's plant. Each motor is a
`motor` actuator on its joint at the output (torque in N*m, ctrlrange the peak torque) with the
rotor reflected as the joint's armature (N^2 J) and the output friction as its frictionloss
(Coulomb) and damping (viscous). Not carried over: the actuator's torque-speed envelope (the
voltage line and the braking peak: a controller must keep within them), the bushing closure
(MuJoCo's soft constraint closes the loop instead) and the contact's stiffness (MuJoCo's own
soft contact, the feet's friction coefficient kept). Only the feet and the body's box collide.
"""

from __future__ import annotations

from xml.dom import minidom

import numpy as np
from scipy.spatial.transform import Rotation

from fivebar_drake.core.sdf import element, fmt
from fivebar_drake.mechanisms.fivebar import KNEES_OUT, joint_ranges, link_inertias
from fivebar_drake.robots.quadruped.legs import PLANE_RPY, hip_positions
from fivebar_drake.robots.quadruped.params import Params
from fivebar_drake.robots.quadruped.sdf import body_height, body_mass_properties

MJCF_FILE = "quadruped.xml"
COLLIDES = {"contype": "1", "conaffinity": "1"}


def _quat(rotation: np.ndarray) -> str:
    """MJCF's quat (w x y z) of a rotation matrix."""
    x, y, z, w = Rotation.from_matrix(rotation).as_quat()
    return fmt(w, x, y, z)


def _rz(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def home_pose(params: Params):
    """The standing pose's joints in the leg plane (m): A, B, C, D, E, F (2,) each."""
    leg, g = params.leg, params.gait
    pose = params.fivebar_leg.inverse(np.array([g.x_center_m, g.y_home_m]), KNEES_OUT)
    return {"A": np.array(leg.motor_a_m), "B": np.array(leg.motor_b_m), "C": pose.c,
            "D": pose.d, "E": pose.e, "F": pose.f}


def _leg(params: Params, name: str, hip) -> str:
    """A leg's bodies under the trunk: AC (hinge A) carrying CE (hinge C), BD (hinge B)
    carrying DE (hinge D) with the foot, each at the standing pose."""
    p, m, b = home_pose(params), params.motor, params.body
    plane = Rotation.from_euler("xyz", PLANE_RPY).as_matrix()
    angle = {link: float(np.arctan2(p[link[1]][1] - p[link[0]][1],
                                    p[link[1]][0] - p[link[0]][0]))
             for link in ("AC", "BD", "CE", "DE")}
    inertias = link_inertias(params.leg, params.links, b.link_width_m)
    ranges = joint_ranges(params.leg)

    def body(link, joint, ref, pos, rotation, children=""):
        """The link's body at pos (m) and rotation relative to its parent, its hinge at ref."""
        length = params.leg.link_length(link)
        lo, hi = ranges.get(joint, (-np.inf, np.inf))
        limited = {"range": fmt(lo, hi)} if np.isfinite([lo, hi]).all() else {}
        drive = ({"armature": fmt(m.reflected_inertia_kg_m2),
                  "frictionloss": fmt(m.coulomb_friction_Nm),
                  "damping": fmt(m.viscous_friction_Nm_s)} if joint in ("A", "B") else {})
        foot = (element("geom", name=f"{name}_foot", type="sphere", size=fmt(b.foot_radius_m),
                        pos=fmt(length, 0, 0), friction=fmt(b.foot_friction, 0.005, 0.0001),
                        rgba="0.1 0.1 0.1 1", **COLLIDES) if link == "DE" else "")
        return element(
            "body",
            element("inertial", pos=fmt(params.links[link].com_m, 0, 0),
                    mass=fmt(params.links[link].mass_kg), diaginertia=fmt(*inertias[link])),
            element("joint", name=f"{name}_{joint}", type="hinge", axis="0 0 1", ref=fmt(ref),
                    **limited, **drive),
            element("geom", type="box", size=fmt(length / 2, b.link_width_m / 2,
                                                 b.link_width_m / 2),
                    pos=fmt(length / 2, 0, 0), rgba="0.85 0.45 0.25 1"),
            foot, children, name=f"{name}_{link}", pos=fmt(*pos), quat=_quat(rotation))

    def upper(link, joint, lower, knee):
        """An upper link on the trunk at its motor, in the leg plane, carrying its lower one at
        its end (the knee's angle: the lower link's from the upper one's direction)."""
        low = body(lower, knee, angle[lower] - angle[link],
                   (params.leg.link_length(link), 0.0, 0.0), _rz(angle[lower] - angle[link]))
        return body(link, joint, angle[link], np.asarray(hip) + plane @ np.append(p[joint], 0.0),
                    plane @ _rz(angle[link]), low)

    return upper("AC", "A", "CE", "C") + upper("BD", "B", "DE", "D")


def quadruped_mjcf(params: Params, closure=None, bushing=None) -> str:
    """The MJCF document of the whole robot standing on a floor (module docstring); closure and
    bushing are the SDF models' (closure.MODEL_FILES) and unused: MuJoCo's connect closes the
    loops."""
    mass, com, inertia = body_mass_properties(params)
    b, m, r = params.body, params.motor, params.robot
    trunk = element(
        "body", element("freejoint", name="root"),
        element("inertial", pos=fmt(*com), mass=fmt(mass),
                fullinertia=fmt(*inertia[[0, 1, 2, 0, 0, 1], [0, 1, 2, 1, 2, 2]])),
        element("geom", name="box", type="box", size=fmt(b.length_m / 2, b.width_m / 2,
                                                         b.height_m / 2),
                rgba="0.6 0.6 0.65 1", **COLLIDES),
        *(_leg(params, leg, hip) for leg, hip in hip_positions(params).items()),
        name="body", pos=fmt(0, 0, float(body_height(params, params.gait.y_home_m))))
    connects = "".join(element("connect", body1=f"{leg}_CE", body2=f"{leg}_DE",
                               anchor=fmt(params.leg.ce_m, 0, 0))
                       for leg in hip_positions(params))
    motors = "".join(element("motor", name=f"{leg}_{j}", joint=f"{leg}_{j}", gear="1",
                             ctrlrange=fmt(-m.peak_torque_Nm, m.peak_torque_Nm))
                     for leg in hip_positions(params) for j in ("A", "B"))
    text = element(
        "mujoco",
        element("compiler", angle="radian", autolimits="true"),
        element("option", timestep="0.001", gravity=fmt(0, 0, -r.gravity_m_s2)),
        element("default", element("geom", contype="0", conaffinity="0")),
        element("worldbody",
                element("geom", name="floor", type="plane", size="0 0 1",
                        friction=fmt(b.foot_friction, 0.005, 0.0001), **COLLIDES),
                trunk),
        element("equality", connects), element("actuator", motors), model="quadruped")
    pretty = minidom.parseString(text.replace("\n", "")).toprettyxml(indent="  ")
    return pretty.replace("?>", "?>\n<!-- Generated by fivebar_drake.robots.quadruped.mjcf from "
                          "the parameter file (fivebar-drake models); do not edit. -->", 1)
