"""The envelope's sizing for any controller (envelope/report.sized_by_floor): the maneuver with
the largest floor, a maneuver beyond the motors first, the maneuvers without a floor named."""

from fivebar_drake.envelope.report import sized_by_floor


def entry(floor):
    return {"any_controller": None if floor == "none" else {"floor_Nm": floor}}


def test_the_largest_floor_sizes_the_motors():
    maneuvers = {"trot": entry(2.46), "drop": entry(3.24), "bound": entry("none")}
    s = sized_by_floor(maneuvers, 5.0)
    assert s["maneuver"] == "drop" and s["floor_Nm"] == 3.24
    assert abs(s["safety_factor"] - 5.0 / 3.24) < 1e-12 and s["without_floor"] == ["bound"]


def test_a_maneuver_beyond_the_motors_sizes_them_for_any_controller():
    s = sized_by_floor({"trot": entry(2.46), "jump": entry(None)}, 5.0)
    assert s["maneuver"] == "jump" and s["floor_Nm"] is None and s["safety_factor"] == 0.0


def test_without_any_floor_there_is_no_sizing():
    assert sized_by_floor({"walk": entry("none")}, 5.0) is None
