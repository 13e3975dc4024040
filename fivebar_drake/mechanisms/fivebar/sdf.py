"""SDF elements of one 5-bar leg: its four links, the joints A, B (actuated, on the base) and
C, D (passive knees), and the loop cut at E with its closure.

The leg lives in a *leg-plane frame* whose x-y plane is the seed's leg plane (x, y) and whose z
axis is the hinge axis, so a joint angle about +z is the seed's counter-clockwise motor angle.
Each link's frame sits at its first joint with x along the link in the zero configuration; the
knee joints C and D measure the lower link relative to the upper one. The loop is cut at E:
frames `<prefix>_E_on_CE` and `<prefix>_E_on_DE` (z along the hinge) are joined by a
`<drake:linear_bushing_rpy>` (closure "bushing_rpy"), a `<drake:ball_constraint>` (closure
"ball"), or by two compliant SAP distance constraints that SDFormat cannot declare and the plant
builder adds (closure "bushing"). Only the foot (the tool) collides.
"""

from __future__ import annotations

from fivebar_drake.core.sdf import fmt, inertial
from fivebar_drake.mechanisms.base import Bushing, SdfLook
from fivebar_drake.mechanisms.fivebar.geometry import (LINK_NAMES, LegGeometry, LinkInertia,
                                                        physical_izz)

COLORS = {"AC": "0.85 0.35 0.2 1", "BD": "0.2 0.45 0.85 1", "CE": "0.95 0.6 0.3 1",
          "DE": "0.35 0.65 0.95 1"}


def link_inertias(leg: LegGeometry, links: dict[str, LinkInertia],
                  link_width_m: float) -> dict[str, tuple[float, float, float]]:
    """(Ixx, Iyy, Izz) about each link's COM in the link frame (x along the link, z hinge), in
    kg*m^2: Izz and Iyy are the seed's hinge value (thin-rod estimate where the seed says ~0),
    Ixx about the long axis is that of a square section of side link_width_m, m w^2 / 6; the
    triangle inequality holds since Ixx >= 0 and Iyy = Izz."""
    return {name: (links[name].mass_kg * link_width_m**2 / 6.0, izz, izz)
            for name, izz in zip(LINK_NAMES, physical_izz(leg, links))}


def _link(leg: LegGeometry, links, prefix: str, frame: str, name: str, origin,
          look: SdfLook) -> str:
    link = links[name]
    length = leg.link_length(name)
    ixx, iyy, izz = link_inertias(leg, links, look.link_width_m)[name]
    w = look.link_width_m
    tool = look.tool_xml.replace("{pose}", f"<pose>{fmt(length)} 0 0 0 0 0</pose>") \
        if name == "DE" else ""
    return (f"<link name='{prefix}_{name}'><pose relative_to='{frame}'>{fmt(*origin)} 0 0 0 0"
            f"</pose>{inertial(link.mass_kg, link.com_m, ixx, iyy, izz)}<visual name='bar'>"
            f"<pose>{fmt(length / 2)} 0 0 0 0 0</pose>"
            f"<geometry><box><size>{fmt(length, w, w)}</size></box></geometry><material>"
            f"<diffuse>{COLORS[name]}</diffuse></material></visual>{tool}</link>")


def _joint(prefix: str, name: str, parent: str, child: str, look: SdfLook | None) -> str:
    """A revolute joint about the hinge; look: actuated (its limit and drive), None: passive."""
    limit = ("<limit><effort>0</effort></limit></axis>" if look is None
             else look.actuated_joint_xml)
    return (f"<joint name='{prefix}_{name}' type='revolute'><parent>{parent}</parent>"
            f"<child>{prefix}_{child}</child><axis><xyz>0 0 1</xyz>{limit}</joint>")


def sdf_elements(leg: LegGeometry, links: dict[str, LinkInertia], prefix: str, parent: str,
                 frame: str, closure: str, bushing: Bushing | None, look: SdfLook) -> str:
    """SDF elements of one leg: links placed in the leg-plane frame `frame`, motors A and B on
    the link `parent`, the loop at E closed by `closure` (bushing: the bushing_rpy's stiffness
    and damping). look.actuated_joint_xml continues an actuated joint's <axis> after its <xyz>
    (it closes </axis>)."""
    ax, ay = leg.motor_a_m
    bx, by = leg.motor_b_m
    parts = [_link(leg, links, prefix, frame, "AC", (ax, ay), look),
             _link(leg, links, prefix, frame, "BD", (bx, by), look),
             _link(leg, links, prefix, frame, "CE", (ax + leg.ac_m, ay), look),
             _link(leg, links, prefix, frame, "DE", (bx + leg.bd_m, by), look),
             _joint(prefix, "A", parent, "AC", look),
             _joint(prefix, "B", parent, "BD", look),
             _joint(prefix, "C", f"{prefix}_AC", "CE", None),
             _joint(prefix, "D", f"{prefix}_BD", "DE", None),
             f"<frame name='{prefix}_E_on_CE' attached_to='{prefix}_CE'><pose "
             f"relative_to='{prefix}_CE'>{fmt(leg.ce_m)} 0 0 0 0 0</pose></frame>",
             f"<frame name='{prefix}_E_on_DE' attached_to='{prefix}_DE'><pose "
             f"relative_to='{prefix}_DE'>{fmt(leg.de_m)} 0 0 0 0 0</pose></frame>"]
    if closure == "ball":
        parts.append(
            f"<drake:ball_constraint><drake:ball_constraint_body_A>{prefix}_CE"
            f"</drake:ball_constraint_body_A><drake:ball_constraint_p_AP>{fmt(leg.ce_m)} 0 0"
            f"</drake:ball_constraint_p_AP><drake:ball_constraint_body_B>{prefix}_DE"
            f"</drake:ball_constraint_body_B><drake:ball_constraint_p_BQ>{fmt(leg.de_m)} 0 0"
            "</drake:ball_constraint_p_BQ></drake:ball_constraint>")
    if closure == "bushing_rpy":
        k, d = bushing.stiffness_N_m, bushing.damping_N_s_m
        parts.append(
            f"<drake:linear_bushing_rpy><drake:bushing_frameA>{prefix}_E_on_CE"
            f"</drake:bushing_frameA><drake:bushing_frameC>{prefix}_E_on_DE"
            "</drake:bushing_frameC><drake:bushing_torque_stiffness>0 0 0"
            "</drake:bushing_torque_stiffness><drake:bushing_torque_damping>0 0 0"
            "</drake:bushing_torque_damping>"
            f"<drake:bushing_force_stiffness>{fmt(k, k, k)}</drake:bushing_force_stiffness>"
            f"<drake:bushing_force_damping>{fmt(d, d, d)}</drake:bushing_force_damping>"
            "</drake:linear_bushing_rpy>")
    return "\n".join(parts)
