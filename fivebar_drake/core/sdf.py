"""SDFormat text helpers shared by the mechanisms' and robots' model generators."""

from __future__ import annotations


def fmt(*values) -> str:
    """Numbers as SDF text: space-separated, 12 significant digits."""
    return " ".join(f"{v:.12g}" for v in values)


def inertial(mass_kg: float, com_x_m: float, ixx: float, iyy: float, izz: float) -> str:
    """<inertial> of a link frame with x along the link: COM at com_x_m (m) on x, principal
    moments (kg*m^2) about the COM along the frame's axes."""
    return (f"<inertial><pose>{com_x_m:.12g} 0 0 0 0 0</pose><mass>{mass_kg:.12g}</mass><inertia>"
            f"<ixx>{ixx:.12g}</ixx><iyy>{iyy:.12g}</iyy><izz>{izz:.12g}</izz>"
            "<ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia></inertial>")
