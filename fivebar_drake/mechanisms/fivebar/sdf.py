"""SDF elements of one 5-bar leg: its four links, the joints A, B (actuated, on the base) and
C, D (passive knees), and the loop cut at E with its closure.

The leg lives in a *leg-plane frame* whose x-y plane is the seed's leg plane (x, y) and whose z
axis is the hinge axis, so a joint angle about +z is the seed's counter-clockwise motor angle.
Each link's frame sits at its first joint with x along the link in the zero configuration; the
knee joints C and D measure the lower link relative to the upper one. The loop is cut at E
(loop_cut): E on CE meets E on DE, with frames `<prefix>_E_on_CE` and `<prefix>_E_on_DE` (z along
the hinge); the closure writes what joins them. Only the foot (the tool) collides. The leg's
limits give the joints their ranges (limits.joint_ranges: the motors' ranges at A and B, the
least knee angle at C and D).
"""

from __future__ import annotations

from fivebar_drake.core.sdf import axis, box, element, inertial, joint, limit, pose, visual
from fivebar_drake.mechanisms.base import Bushing, LoopCut, SdfLook
from fivebar_drake.mechanisms.fivebar.geometry import (LINK_NAMES, LegGeometry, LinkInertia,
                                                        physical_izz)
from fivebar_drake.mechanisms.fivebar.limits import joint_ranges

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
    w = look.link_width_m
    tool = look.tool_xml.replace("{pose}", pose(length)) if name == "DE" else ""
    return element("link", pose(*origin, relative_to=frame),
                   inertial(link.mass_kg, link_inertias(leg, links, w)[name], (link.com_m, 0, 0)),
                   visual("bar", box(length, w, w), COLORS[name], pose(length / 2)), tool,
                   name=f"{prefix}_{name}")


def _joint(prefix: str, name: str, parent: str, child: str, look: SdfLook | None,
           joint_range=(None, None)) -> str:
    """A revolute joint about the hinge within joint_range (lower, upper) rad (None: free);
    look: actuated (its effort limit and drive), None: passive."""
    effort, drive = (0, "") if look is None else (look.effort_limit, look.drive_xml)
    return joint(f"{prefix}_{name}", "revolute", parent, f"{prefix}_{child}",
                 axis("0 0 1", limit(effort, *joint_range)), drive)


def _loop_frame(prefix: str, link: str, length_m: float) -> str:
    """The frame at E on a lower link (z along the hinge)."""
    return element("frame", pose(length_m, relative_to=f"{prefix}_{link}"),
                   name=f"{prefix}_E_on_{link}", attached_to=f"{prefix}_{link}")


def loop_cut(leg: LegGeometry, prefix: str) -> LoopCut:
    """The loop's cut at E: the end of CE on the end of DE, at their frames E_on_CE, E_on_DE."""
    return LoopCut(f"{prefix}_CE", (leg.ce_m, 0.0, 0.0), f"{prefix}_E_on_CE",
                   f"{prefix}_DE", (leg.de_m, 0.0, 0.0), f"{prefix}_E_on_DE")


def sdf_elements(leg: LegGeometry, links: dict[str, LinkInertia], prefix: str, parent: str,
                 frame: str, closure, bushing: Bushing | None, look: SdfLook) -> str:
    """SDF elements of one leg: links placed in the leg-plane frame `frame`, motors A and B on
    the link `parent` (dressed by look), the loop at E closed by `closure` (base.SdfElements:
    None, or its sdf(loop_cut, bushing) element; bushing: the designed one)."""
    ax, ay = leg.motor_a_m
    bx, by = leg.motor_b_m
    ranges = joint_ranges(leg)
    free = (None, None)
    parts = [_link(leg, links, prefix, frame, "AC", (ax, ay), look),
             _link(leg, links, prefix, frame, "BD", (bx, by), look),
             _link(leg, links, prefix, frame, "CE", (ax + leg.ac_m, ay), look),
             _link(leg, links, prefix, frame, "DE", (bx + leg.bd_m, by), look),
             _joint(prefix, "A", parent, "AC", look, ranges.get("A", free)),
             _joint(prefix, "B", parent, "BD", look, ranges.get("B", free)),
             _joint(prefix, "C", f"{prefix}_AC", "CE", None, ranges.get("C", free)),
             _joint(prefix, "D", f"{prefix}_BD", "DE", None, ranges.get("D", free)),
             _loop_frame(prefix, "CE", leg.ce_m),
             _loop_frame(prefix, "DE", leg.de_m)]
    closing = "" if closure is None else closure.sdf(loop_cut(leg, prefix), bushing)
    return "\n".join(parts + ([closing] if closing else []))
