"""The one way to write SDFormat in this package: elements as text from their tag, children and
attributes, and the pieces every model generator needs (pose, inertial, visual, joint, ball
constraint, the document). Numbers are written with 12 significant digits."""

from __future__ import annotations

SDF_OPEN = "<sdf version='1.9' xmlns:drake='http://drake.mit.edu'>"


def fmt(*values) -> str:
    """Numbers as SDF text: space-separated, 12 significant digits (text is kept as written)."""
    return " ".join(v if isinstance(v, str) else f"{v:.12g}" for v in values)


def element(tag: str, *children: str, **attributes) -> str:
    """<tag name='value' ...>children</tag>: children are text (elements or values), attributes
    in the order given (values text or numbers); no children: <tag .../>."""
    attrs = "".join(f" {k}='{fmt(v)}'" for k, v in attributes.items())
    return f"<{tag}{attrs}>{''.join(children)}</{tag}>" if children else f"<{tag}{attrs}/>"


def pose(*xyz_rpy, relative_to: str | None = None) -> str:
    """<pose> of x y z (m) roll pitch yaw (rad); missing trailing values are 0."""
    values = fmt(*xyz_rpy, *(0,) * (6 - len(xyz_rpy)))
    return element("pose", values) if relative_to is None else \
        element("pose", values, relative_to=relative_to)


def inertial(mass_kg: float, moments_kg_m2, com_m=None, products_kg_m2=(0, 0, 0)) -> str:
    """<inertial>: mass, COM com_m (x, y, z) m in the link frame (None: no <pose>, the origin)
    and the inertia about the COM along the link frame's axes, moments (Ixx, Iyy, Izz) and
    products (Ixy, Ixz, Iyz) in kg*m^2."""
    names = ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")
    inertia = element("inertia", *(element(n, fmt(v)) for n, v in
                                    zip(names, (*moments_kg_m2, *products_kg_m2))))
    at = () if com_m is None else (pose(*com_m),)
    return element("inertial", *at, element("mass", fmt(mass_kg)), inertia)


def visual(name: str, geometry: str, rgba: str, *at: str) -> str:
    """<visual> of a geometry element (box, sphere, cylinder) with a diffuse colour "r g b a",
    placed by an optional <pose> `at`."""
    return element("visual", *at, element("geometry", geometry),
                   element("material", element("diffuse", rgba)), name=name)


def box(*size_m) -> str:
    return element("box", element("size", fmt(*size_m)))


def sphere(radius_m: float) -> str:
    return element("sphere", element("radius", fmt(radius_m)))


def cylinder(radius_m: float, length_m: float) -> str:
    return element("cylinder", element("radius", fmt(radius_m)), element("length", fmt(length_m)))


def axis(xyz: str, *children, tag: str = "axis") -> str:
    """<axis> (or <axis2>) along xyz ("0 0 1") with its other children (the limit)."""
    return element(tag, element("xyz", xyz), *children)


def limit(effort=None, lower=None, upper=None) -> str:
    """<limit> of a joint (inside its <axis>): its range lower .. upper (rad or m; None or
    infinite: that side left open) and its effort (N*m or N; None: not given, 0: no actuator)."""
    parts = [element(tag, fmt(v)) for tag, v in (("lower", lower), ("upper", upper))
             if v is not None and abs(v) != float("inf")]
    return element("limit", *parts, *(() if effort is None else (element("effort", fmt(effort)),)))


PASSIVE = limit(effort=0)   # a joint no actuator drives


def joint(name: str, kind: str, parent: str, child: str, *children) -> str:
    """<joint> of a type between two links (or frames), with its axes and other children."""
    return element("joint", element("parent", parent), element("child", child), *children,
                   name=name, type=kind)


def ball_constraint(body_a: str, p_ap, body_b: str, p_bq=(0, 0, 0)) -> str:
    """Drake's ball constraint: point p_ap (m) of body_a on point p_bq (m) of body_b."""
    return element("drake:ball_constraint",
                   element("drake:ball_constraint_body_A", body_a),
                   element("drake:ball_constraint_p_AP", fmt(*p_ap)),
                   element("drake:ball_constraint_body_B", body_b),
                   element("drake:ball_constraint_p_BQ", fmt(*p_bq)))


def document(model: str, *elements: str) -> str:
    """An SDFormat 1.9 document (Drake's namespace declared) holding one model."""
    return SDF_OPEN + element("model", *elements, name=model) + "</sdf>"
