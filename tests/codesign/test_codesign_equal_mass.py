"""The co-design at equal actuator mass, cheaply (no simulation): the mass band of
requirements.actuator_mass against the catalogue's gearbox mass model computed here from its
figures, linked link lengths (one variable, both links), the spec's refusals, and the simulated
max jump in design.md."""

import math

import pytest

from fivebar_drake.cli import main
from fivebar_drake.codesign.designs import design_of, design_params
from fivebar_drake.codesign.predict import predict
from fivebar_drake.codesign.report import markdown, max_jumps
from fivebar_drake.codesign.spec import MASS, load_codesign_spec
from fivebar_drake.actuators.catalog import catalog, gearboxes
from fivebar_drake.core.parameter_files import packaged

MOTOR = "tmotor_mn5212_kv340"
SPEC = """\
variables:
  motor: [tmotor_mn5212_kv340]
  motor.gear_ratio: [1.5, 6.0]
  leg.ac_m=leg.bd_m: [0.06, 0.12]
requirements:
  envelope:
    config: {config}
    maneuvers:
      - {{name: trot, gait: trot, duration_s: 2.0}}
  accept: warn
  actuator_mass:
    equal_to: {{motor: tmotor_mn5212_kv340, gearbox: timing_belt, motor.gear_ratio: 3.0}}
    within: 0.02
  simulate_max_jump: true
objectives: [max_jump_height_m]
budget: {{trials: 2, finalists: 1}}
"""


def spec_file(folder, change=("", "")):
    """SPEC (on the packaged doggo.toml, with a change) in folder/spec.yaml."""
    text = SPEC.format(config=packaged("doggo.toml"))
    assert change[0] in text
    (folder / "spec.yaml").write_text(text.replace(*change))
    return folder / "spec.yaml"


@pytest.fixture(scope="module")
def spec(tmp_path_factory):
    return load_codesign_spec(spec_file(tmp_path_factory.mktemp("spec")))


def belt_mass(ratio):
    """The MN5212 and a one-stage timing belt (kg), from the catalogue's figures: the belt's
    mass grows with the actuator's peak output torque N eta k_t I_peak."""
    m, belt = catalog()[MOTOR], gearboxes()["timing_belt"]
    torque = (ratio * belt.efficiency.value * m.torque_constant_Nm_per_A.value
              * m.peak_current_A.value)
    return m.mass_kg.value + belt.mass_base_kg.value + belt.mass_per_Nm_kg.value * torque


def test_the_band_is_the_reference_designs_actuator_mass(spec):
    reference, within = spec.mass_band
    assert reference == pytest.approx(belt_mass(3.0)) and within == 0.02
    assert spec.simulate_max_jump


def test_a_design_is_held_within_the_mass_band(spec):
    m, belt = catalog()[MOTOR], gearboxes()["timing_belt"]
    slope = (belt.efficiency.value * m.torque_constant_Nm_per_A.value * m.peak_current_A.value
             * belt.mass_per_Nm_kg.value)           # kg per unit of ratio
    inside = 3.0 + 0.01 * belt_mass(3.0) / slope    # 1 % heavier: half the band
    outside = 3.0 - 0.03 * belt_mass(3.0) / slope   # 3 % lighter: beyond it
    assert outside > belt.ratio_min.value           # still a belt's ratio: only the band bars it
    designs = [design_of({"motor": MOTOR, "gearbox": "timing_belt", "motor.gear_ratio": r,
                          "leg.ac_m=leg.bd_m": 0.09}) for r in (inside, outside)]
    near, far = predict(spec, designs)
    assert near["maneuvers"][MASS]["margins"]["within"] == pytest.approx(2.0, rel=1e-6)
    assert far["maneuvers"][MASS]["margins"]["within"] == pytest.approx(2.0 / 3.0, rel=1e-6)
    assert far["short_of"] == f"{MASS} within" and not far["meets"]
    assert near["maneuvers"]["trot"]["level"] == "closed form"
    # the jump is still predicted outside the band (the search learns where the band lies)
    assert far["objectives"]["max_jump_height_m"] > 0.0


def test_linked_paths_set_both_links(spec):
    design = design_of({"motor": MOTOR, "gearbox": "timing_belt", "motor.gear_ratio": 3.0,
                        "leg.ac_m=leg.bd_m": 0.1})
    assert design["leg.ac_m"] == design["leg.bd_m"] == 0.1 and "leg.ac_m=leg.bd_m" not in design
    geometry = design_params(spec.envelope.maneuvers[0].params, design).fivebar_leg.geometry
    assert geometry.ac_m == geometry.bd_m == 0.1


@pytest.mark.parametrize("change, words", [
    (("within: 0.02", "within: 0.9"), ["requirements.actuator_mass.within"]),
    (("within: 0.02", "plus_minus: 0.02"), ["requirements.actuator_mass"]),
    (("motor.gear_ratio: 3.0}", "motor.gear_ratio: 9.0}"),
     ["requirements.actuator_mass.equal_to"]),
    (("leg.ac_m=leg.bd_m", "leg.ac_m=motor.gear_ratio"), ["variables.leg.ac_m=motor.gear_ratio"]),
    (("leg.ac_m=leg.bd_m", "leg.ac_m=leg.xx_m"), ["variables.leg.ac_m=leg.xx_m"]),
    (("objectives: [max_jump_height_m]", "objectives: [actuator_mass_kg]"),
     ["requirements.simulate_max_jump"]),
])
def test_bad_mass_bands_and_linked_paths_are_refused(tmp_path, capsys, change, words):
    assert main(["codesign", str(spec_file(tmp_path, change)), "--out",
                 str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert all(w in err for w in words), err
    assert not (tmp_path / "out").exists()


def test_design_md_sets_each_simulated_max_jump_beside_the_default(spec, tmp_path):
    from style_rules import violations

    def jump(height, landed):
        return {"max_jump": {"ceiling_m": 1.0, "planned_m": 0.8, "height_m": height,
                             "share_of_plan": height / 0.8, "verdict": "insufficient",
                             "landed": landed, "not_landed": "" if landed else "out of reach"}}

    report = {"default": {"actuator_mass_kg": 0.24}, "compared": [],
              "finalists": [{"key": "trial_3", "name": "longer legs",
                             "objectives": {"actuator_mass_kg": 0.27}}]}
    rows = max_jumps(report, {"default": jump(0.7, True), "trial_3": jump(0.9, False)})
    assert [(r["key"], r["height_m"], r["landed"]) for r in rows] == [
        ("default", 0.7, True), ("trial_3", 0.9, False)]
    text = markdown(spec, {**report, "finalists": [], "answer": "", "why": [], "recommended": None,
                           "default": {"actuator_mass_kg": 0.24, "simulated": None},
                           "max_jumps": rows, "not_simulated": [], "corrections": {},
                           "candidates": [], "trials": 0, "predicted_meeting": 0})
    table = text.split("## Max-effort jump simulated")[1]
    assert "| 900.0 |" in table and "| 700.0 |" in table
    assert "no, its landing not verified: out of reach" in table
    assert not math.isnan(rows[1]["share_of_plan"])
    (tmp_path / "design.md").write_text("Recommended: 2 of 3 pass.\n" + table)
    assert not violations(tmp_path / "design.md")       # the table's headers in the glossary


def test_pareto_png_draws_the_simulated_max_jumps(spec):
    from fivebar_drake.codesign.report import pareto_figure

    finalist = {"key": "trial_3", "name": "longer legs", "margin": 1.2,
                "objectives": {"actuator_mass_kg": 0.27, "max_jump_height_m": 1.2},
                "simulated": {"passes": True, "maneuvers": {}}}
    rows = [{"key": "default", "height_m": 0.7}, {"key": "trial_3", "height_m": 0.9}]
    fig = pareto_figure(spec, {"candidates": [], "finalists": [finalist], "compared": [],
                               "recommended": None, "max_jumps": rows,
                               "default": {"actuator_mass_kg": 0.24}})
    ax = fig.axes[0]
    labels = ax.get_legend_handles_labels()[1]
    assert "default: max jump simulated" in labels and "trial_3: max jump simulated" in labels
    # the finalist's simulated apex drawn at its measured height, joined to its prediction
    assert any(list(line.get_xdata()) == [1.2, 0.9] for line in ax.lines)


def test_a_max_jump_landing_is_verified_only_by_a_run_to_its_end_with_a_verdict():
    from fivebar_drake.codesign.run import landing_not_verified

    def summary(verdict, why=None):
        checks = {"achieved": {"passed": why is None, "why": why}}
        return {"verdict": verdict, "legs": {leg: {m: {"checks": checks} for m in "AB"}
                                             for leg in ("FL", "RR")}}

    assert landing_not_verified(summary("fail")) == ""      # a verdict: the landing was done
    assert landing_not_verified(summary("not_achieved", "the legs gave way")) == \
        "the legs gave way"
    assert landing_not_verified(summary("insufficient"), "foot target out of reach") == \
        "foot target out of reach"
    assert "summary.md" in landing_not_verified(summary("insufficient"))
