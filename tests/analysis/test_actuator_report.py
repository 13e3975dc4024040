"""report.json's actuator: the envelope at the output (driving quadrant, 0 .. no-load speed,
>= 50 samples) checked by hand from the README's conventions, and the checks of every reading."""

import json
import math

import numpy as np

from fivebar_drake.pipeline import run_analysis, write_analysis


def test_envelope_and_checks_in_report(tmp_path, params):
    write_analysis(run_analysis(params), tmp_path)
    report = json.loads((tmp_path / "report.json").read_text())
    env = report["motor"]["envelope"]
    speed, torque = np.array(env["speed_rad_s"]), np.array(env["max_torque_Nm"])
    assert speed.size >= 50 and speed[0] == 0.0
    m = params.motor
    # by hand: N eta k_t min(I_peak, (V_bus / sqrt(3) - (k_t / 1.5) N w) / R), zero at the end
    n, kt = m.gear_ratio, m.torque_constant_Nm_per_A
    current = np.clip((m.bus_voltage_V / math.sqrt(3) - kt / 1.5 * n * speed)
                      / m.winding_resistance_ohm, 0.0, m.peak_current_A)
    np.testing.assert_allclose(torque, n * m.gear_efficiency * kt * current, atol=1e-12)
    assert torque[0] == 5.0 or abs(torque[0] - 5.0) < 1e-12          # the seed's 5 N m
    assert abs(speed[-1] - 4 * math.pi) < 1e-12 and abs(torque[-1]) < 1e-12   # 120 RPM
    for model in ("seed", "full", "full_trot"):
        for motor in "AB":
            c = report["results"][model][motor]["checks"]
            assert {"torque", "speed", "thermal", "verdict", "deciding_check"} <= set(c)
            assert c["torque"]["sf"] == report["results"][model][motor]["safety_factor"]
    md = (tmp_path / "report.md").read_text()
    assert "## Verdict: the actuator's checks" in md and "## Table 5" in md
