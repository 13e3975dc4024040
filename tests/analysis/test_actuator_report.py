"""report.json's actuator: the envelope at the output (driving quadrant, 0 .. no-load speed,
>= 50 samples) checked by hand from the README's conventions, and the checks of every reading."""

import json
import math

import numpy as np
import pytest

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
    analysis = run_analysis(params).analysis
    for model in ("seed", "full", "full_trot"):
        for j, motor in enumerate("AB"):
            c = report["results"][model][motor]["checks"]
            assert {"torque", "speed", "thermal", "verdict", "deciding_check"} <= set(c)
            # by hand: the torque the motor delivers (joint torque + tau_c clamp(w / 0.05) +
            # b w) over the peak of its quadrant: 5 N m driving, 5 / 0.9^2 braking
            tau = analysis.torques[model].total[:, j]
            w = analysis.samples.qd[:, j]
            delivered = tau + (m.coulomb_friction_Nm * np.clip(w / 0.05, -1, 1)
                               + m.viscous_friction_Nm_s * w)
            peak = np.where(delivered * w >= 0, 5.0, 5.0 / 0.9**2)
            assert c["torque"]["sf"] == pytest.approx(1 / np.max(np.abs(delivered) / peak),
                                                      rel=1e-12)
            k = int(np.argmax(np.abs(delivered) / peak))
            assert c["torque"]["quadrant"] == ("driving" if delivered[k] * w[k] >= 0
                                               else "braking")
            assert report["results"][model][motor]["safety_factor"] == pytest.approx(
                5.0 / np.max(np.abs(tau)), rel=1e-12)             # Table 5: the seed's
    md = (tmp_path / "report.md").read_text()
    assert "## Verdict: the actuator's checks" in md and "(the seed's Table 5)" in md
