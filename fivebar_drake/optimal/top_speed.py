"""The top speed: how fast the legs and motors let the robot run a periodic gait (trot, bound,
pronk), for any controller, and what limits it.

The search. A gait's speed is its stance foot's speed relative to the hip, v = 2a f / beta
(half stride a, frequency f, duty factor beta). Over a grid of duty factors (DUTIES) and half
strides (STRIDE_SHARES of the longest the leg reaches at the gait's height and [limits]), the
frequency is bisected (FREQUENCY_STEPS) for the fastest that passes every check below (a slow
gait may fail where a faster one passes: _fastest_at); the top speed is the fastest over the
grid. It is the fastest the search found, a lower end: the true
top speed of the model lies between it and the no-load bound (speed_bound), and both are
reported.

The checks at one (beta, a, f), cheapest first:

1. Reach: the path (gaits/trot.py, the footholds at x_center, the body at its gait height)
   within the leg's reach and [limits] (config.with_gait).
2. Swing, with the leg's own dynamics: the swing is the trot path's quintic plus three shape
   terms (Trot.swing_*_m), chosen by Nelder-Mead to maximise the least envelope margin over the
   swing; the motor torques tau = (M(q) + N^2 J_rotor) q'' + c(q, q') + G(q) (the package's
   full model, no foot load) plus the friction at the joint speeds, within the actuator's
   envelope at those speeds in both quadrants (Motor.limits). The lift stays above the ground
   (|swing_lift_skew_m| <= b: the foot clears it by the gait's step height b at mid-swing).
3. Stance: the gait's floor (gait_floor: the body's sagittal dynamics, surge, heave and pitch
   within the pitch bound, friction cones, periodic), its stance torques plus the links' and
   rotors' inertia along the nominal stance plus the friction, within the envelope at the
   floor's stance joint speeds.

Neglected, each with its size in the result (TopSpeed.neglected): the body's acceleration on
the swing legs (their links' weight scaled by the floor's largest body acceleration over g,
reported as a torque), the stance legs' inertia on the floor's motion (evaluated on the nominal
course instead), the foot's size and the contact's compliance; the footholds' centre and the
gait's height are the parameter file's, not searched.
"""

from __future__ import annotations

import dataclasses
import math
import pickle
from collections import Counter
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import minimize

from fivebar_drake.core.validation import MAX_GAIT_FREQUENCY_HZ, ParameterError
from fivebar_drake.gaits import evaluate, foot_path
from fivebar_drake.mechanisms.fivebar import KNEES_OUT, limit_tests, past_any
from fivebar_drake.optimal.gait_floor import NoFloorMotion, gait_floor
from fivebar_drake.robots.quadruped.config import with_gait, with_path_defaults
from fivebar_drake.robots.quadruped.leg_loads import full_model
from fivebar_drake.robots.quadruped.legs import LEGS
from fivebar_drake.robots.quadruped.params import Params

GAITS = ("trot", "bound", "pronk")
# the duty factors searched, the likeliest first (a good speed early prunes the rest)
DUTIES = {"trot": (0.5, 0.4, 0.6), "bound": (0.5, 0.35, 0.65), "pronk": (0.5, 0.35, 0.65)}
STRIDE_SHARES = (0.75, 0.5, 0.3, 1.0)   # half strides: these shares of the longest one
LADDER_RATIO = 1.35                  # the frequencies tried first, this factor apart
FREQUENCY_STEPS = 4                  # then bisection steps (resolution 0.35/16: 2 %)
WINDOW_STEPS = 2                     # steps looking for a pass between too slow and too fast
#                                      (a window narrower than a quarter of a rung may be missed)
MIN_FREQUENCY_HZ = 0.25              # the slowest frequency tried
SWING_SAMPLES = 121                  # samples of the swing
SWING_EVALUATIONS = 150              # Nelder-Mead's evaluations of one swing at most
REACH_SAMPLES = 200                  # samples of a cycle checked for reach
STRIDE_STEPS = 12                    # bisection steps of the longest half stride
WORKSPACE_SAMPLES = 61               # per axis, for the no-load bound
CACHE_SIZE = 128                     # top speeds kept per process (each some kB)
HOPELESS_MARGIN = 0.2                # a check this far beyond the envelope (of the peak torque)


@dataclass(frozen=True)
class TopSpeed:
    """A gait's top speed (m/s; nan: no speed passes) at its frequency (Hz), duty factor,
    stride (2a, m) and swing shape (path: the optimum's FootPath), with its Froude number
    v^2 / (g h) (h the hip's height above the ground), mechanical cost of transport (the
    motors' mean |tau omega| summed, over m g v), each motor's (A, B) peak and worst RMS torque
    over the cycle (N*m), what stopped a faster one (limited_by), the no-load bound on the hips'
    speed (bound_m_s), the neglected terms' sizes (name -> N*m) and the checks run."""

    kind: str
    speed_m_s: float
    frequency_hz: float
    duty_factor: float
    stride_m: float
    froude: float
    cost_of_transport: float
    peak_Nm: tuple[float, float]
    rms_Nm: tuple[float, float]
    limited_by: str
    bound_m_s: float
    path: object
    neglected: dict
    checks: int

    def row(self) -> dict:
        """The JSON record (the path as its kind and fields)."""
        out = {f.name: getattr(self, f.name) for f in dataclasses.fields(self)
               if f.name != "path"}
        out["path"] = self.path.fields() if self.path is not None else None
        return out


@dataclass(frozen=True)
class Check:
    """One (beta, a, f) checked: passed, why not (the first check that failed), and where it
    passed the figures TopSpeed reports (figures: dict); hopeless where the swing's or the
    stance's torques lie more than HOPELESS_MARGIN beyond the envelope (a faster gait of the
    same stride and duty factor asks more: the search climbs no further); slow where the stance's
    balance failed, which a faster gait of the same stride and duty factor may pass (a diagonal
    pair or a pronk's four feet held long topple the body past the pitch bound)."""

    passed: bool
    why: str
    figures: dict | None = None
    hopeless: bool = False
    slow: bool = False          # failed as a slow gait can (no floor's motion balances it)


def top_speed(params: Params, kind: str, payload_kg: float = 0.0, duties=None,
              shares=STRIDE_SHARES) -> TopSpeed:
    """The gait's top speed (module docstring), cached per process by the design (but the
    gait's stride and frequency, which the search sets), gait kind, payload and grid (the
    CACHE_SIZE most recently used). ParameterError for a kind outside GAITS."""
    if kind not in GAITS:
        raise ParameterError(f"gait {kind!r}: the top speed is computed for {list(GAITS)}",
                             "gait", "top speed")
    duties = tuple(DUTIES[kind] if duties is None else duties)
    key = pickle.dumps((_design_key(params), kind, float(payload_kg), duties, tuple(shares)))
    found = _CACHE.pop(key, None)            # kept most recently used last
    if found is None:
        found = _search(params, kind, float(payload_kg), duties, tuple(shares))
        if len(_CACHE) >= CACHE_SIZE:
            _CACHE.pop(next(iter(_CACHE)))
    _CACHE[key] = found
    return found


_CACHE: dict[bytes, TopSpeed] = {}
SEARCHED_GAIT_FIELDS = ("a_m", "frequency_hz")   # set by every candidate (check): not the design's


def _design_key(params: Params) -> tuple:
    """What the search reads of params: all of it but the gait's stride and frequency, which
    each candidate sets (a scenario's own defaults there, 0.03 m and 2 Hz, searched anew)."""
    gait = {k: v for k, v in vars(params.gait).items() if k not in SEARCHED_GAIT_FIELDS}
    return tuple(getattr(params, f.name) for f in dataclasses.fields(params)
                 if f.name != "gait") + (tuple(sorted(gait.items())),)


def _search(params: Params, kind: str, payload_kg: float, duties, shares) -> TopSpeed:
    """top_speed, computed: the fastest pass (_fastest_at) over the grid of duty factors and
    half strides."""
    base = with_path_defaults(params, kind)
    bound = speed_bound(base)
    best, tally = None, _Tally()
    for beta in duties:
        longest = longest_half_stride(base, foot_path(kind).at_duty(beta, base.gait))
        for share in shares:
            a = share * longest
            found = _fastest_at(base, kind, beta, a, None if best is None else best[0], bound,
                                payload_kg, tally)
            if found is not None and (best is None or found[0] > best[0]):
                best = (*found, beta, a, share)
    if best is None:          # what failed, the commonest first
        failing = "no duty factor, stride and frequency passes: " + ", ".join(
            f"{why} ({n} of {tally.checks} checks)" for why, n in tally.reasons.most_common(3))
        return TopSpeed(kind, math.nan, math.nan, math.nan, math.nan, math.nan, math.nan,
                        (math.nan, math.nan), (math.nan, math.nan), failing, bound, None, {},
                        tally.checks)
    speed, f, passed, why, beta, a, share = best
    failing = why + ("; and the longest stride the leg reaches" if share == 1.0 else "")
    figures, g = passed.figures, params.robot.gravity_m_s2
    return TopSpeed(kind, speed, f, beta, 2.0 * a, speed**2 / (g * -base.gait.y_home_m),
                    figures["cost_of_transport"], figures["peak_Nm"], figures["rms_Nm"],
                    failing, bound, figures["path"], figures["neglected"], tally.checks)


@dataclass
class _Tally:
    """The search's checks so far and what failed them."""

    checks: int = 0
    reasons: Counter = field(default_factory=Counter)

    def check(self, base: Params, kind: str, beta: float, a: float, f: float,
              payload_kg: float) -> Check:
        self.checks += 1
        result = check(base, kind, beta, a, f, payload_kg)
        if not result.passed:
            self.reasons[result.why.split(" (")[0]] += 1
        return result


def _fastest_at(base: Params, kind: str, beta: float, a: float, faster_than: float | None,
                bound: float, payload_kg: float, tally: _Tally) -> tuple | None:
    """(speed m/s, frequency Hz, its Check, what failed just faster) of the fastest pass at duty
    factor beta and half stride a (m) faster than faster_than (m/s; None: any), or None: the
    ladder of frequencies (LADDER_RATIO apart, from faster_than's or MIN_FREQUENCY_HZ, to the
    no-load bound's and the gaits' highest) upwards to the first failure after a pass, then
    bisection (FREQUENCY_STEPS) between the last pass and that failure. A slow gait may fail
    where a faster one passes (Check.slow: no floor's motion balances it), so the ladder
    climbs past such failures; where it steps from one straight to a failure of a faster kind,
    the band between them is bisected for a pass (_window: the pronk's passes lie between
    about 3.4 and 3.9 Hz at a half stride of 70 mm, narrower than a rung), kept unless a higher
    rung passes. Before any pass the climb stops at a faster kind's failure once faster_than
    is set (a faster gait of this stride asks more) or where it is hopeless; with nothing in
    hand it goes on."""
    top = min(bound * beta / (2.0 * a), MAX_GAIT_FREQUENCY_HZ)
    start = (MIN_FREQUENCY_HZ if faster_than is None
             else min(faster_than * beta / (2.0 * a), top))
    ladder = start * LADDER_RATIO ** np.arange(
        max(1, math.ceil(math.log(top / start, LADDER_RATIO)) + 1))
    low = passed = slow = banded = None
    why = ("the no-load bound" if top < MAX_GAIT_FREQUENCY_HZ else
           f"the gaits' highest frequency, {MAX_GAIT_FREQUENCY_HZ:g} Hz")
    for f in np.minimum(ladder, top):
        result = tally.check(base, kind, beta, a, float(f), payload_kg)
        if result.passed:
            low, passed = float(f), result
        elif passed is not None:
            high, why = float(f), result.why
            break
        elif result.slow:
            slow = float(f)
        else:                   # too fast, nothing passed yet
            if slow is not None:    # a band between too slow and too fast?
                found = _window(base, kind, beta, a, slow, float(f), payload_kg, tally)
                if found[0] is not None:    # kept unless a higher rung passes
                    banded = (*found, float(f), result.why)
                slow = None
            if faster_than is not None or result.hopeless:
                break
    if passed is None and banded is not None:
        low, passed, high, why = banded
    if passed is None:
        return None
    if low < top:
        for _ in range(FREQUENCY_STEPS):
            middle = 0.5 * (low + high)
            result = tally.check(base, kind, beta, a, middle, payload_kg)
            if result.passed:
                low, passed = middle, result
            else:
                high, why = middle, result.why
    return 2.0 * a * low / beta, low, passed, why


def _window(base: Params, kind: str, beta: float, a: float, slow: float, fast: float,
            payload_kg: float, tally: _Tally) -> tuple:
    """(a passing frequency (Hz), its Check) or (None, None): bisection (WINDOW_STEPS) between
    a frequency too slow (the stance's balance failed) and one too fast (another check
    failed) for a frequency that passes both."""
    for _ in range(WINDOW_STEPS):
        middle = 0.5 * (slow + fast)
        result = tally.check(base, kind, beta, a, middle, payload_kg)
        if result.passed:
            return middle, result
        if result.slow:
            slow = middle
        else:
            fast = middle
    return None, None


def longest_half_stride(params: Params, path) -> float:
    """The longest half stride a (m) whose path (at the gait's height and centre) stays within
    the leg's reach and [limits] over its cycle (bisection, STRIDE_STEPS)."""
    low, high = 0.0, float(sum(params.leg.link_length(n) for n in ("AC", "CE")))
    for _ in range(STRIDE_STEPS):
        middle = 0.5 * (low + high)
        if _reaches(params, dataclasses.replace(params.gait, a_m=middle), path):
            low = middle
        else:
            high = middle
    if low <= 0.0:
        raise ParameterError(f"the {path.kind} path is out of the leg's reach at any stride",
                             "gait", "top speed")
    return low


def _reaches(params: Params, gait, path) -> bool:
    """Whether the path under gait stays within the leg's reach and [limits] over its cycle
    (REACH_SAMPLES)."""
    leg = params.fivebar_leg
    points = evaluate(gait, path, np.linspace(0.0, gait.period_s, REACH_SAMPLES, endpoint=False))
    pose = leg.inverse(points.pos, KNEES_OUT, strict=False)
    return bool(np.isfinite(pose.q).all()
                and not past_any(limit_tests(params.leg, pose), (REACH_SAMPLES,)).any())


def speed_bound(params: Params) -> float:
    """The no-load bound on the hips' speed over the ground (m/s): while a foot is down (level
    body, no slip) the hip moves at the foot's speed relative to it, J_F q', whose forward part
    is at most omega_0 (|J_x,A| + |J_x,B|) with each joint at most at the no-load speed omega_0;
    in flight it keeps its lift-off speed. The largest over the leg's reachable workspace within
    [limits] (a grid of WORKSPACE_SAMPLES per axis)."""
    leg = params.fivebar_leg
    span = float(sum(params.leg.link_length(n) for n in ("AC", "CE")))
    xs = np.linspace(-span, span, WORKSPACE_SAMPLES)
    ys = np.linspace(-span, 0.0, WORKSPACE_SAMPLES)
    points = np.stack(np.meshgrid(xs, ys), -1).reshape(-1, 2)
    pose = leg.inverse(points, KNEES_OUT, strict=False)
    ok = np.isfinite(pose.q).all(-1) & ~past_any(limit_tests(params.leg, pose), (len(points),))
    jf = leg.tool_jacobian(leg.inverse(points[ok], KNEES_OUT))
    return float(params.motor.no_load_speed_rad_s * np.abs(jf[:, 0, :]).sum(-1).max())


def check(base: Params, kind: str, beta: float, a: float, f: float,
          payload_kg: float = 0.0) -> Check:
    """The checks (module docstring) of the kind's path at duty factor beta, half stride a (m)
    and frequency f (Hz) on the design base (the kind's gait defaults applied)."""
    try:
        params = with_gait(base, a_m=a, frequency_hz=f)
    except ParameterError as error:
        return Check(False, f"the gait's bounds ({error.message})")
    path = foot_path(kind).at_duty(beta, params.gait)
    if not _reaches(params, params.gait, path):
        return Check(False, "the leg's reach or [limits] (the path at this duty factor)")
    stance = _stance_speeds(params, path)
    if np.abs(stance).max() >= params.motor.no_load_speed_rad_s:
        return Check(False, "the stance's joint speed (the no-load speed)")
    path, swing = _best_swing(params, path)
    if swing["margin"] < 0.0:
        return Check(False, f"the swing's {swing['bind']}",
                     hopeless=swing["margin"] < -HOPELESS_MARGIN)
    try:
        floor = gait_floor(params, dataclasses.replace(
            path, swing_reach_m=0.0, swing_skew_m=0.0, swing_lift_skew_m=0.0), payload_kg)
    except ParameterError as error:
        return Check(False, f"the stance's balance ({error.message})",
                     slow=isinstance(error, NoFloorMotion))
    held = _stance(params, path, floor)
    if held["margin"] < 0.0:
        return Check(False, f"the stance's {held['bind']}",
                     hopeless=held["margin"] < -HOPELESS_MARGIN)
    return Check(True, "", _figures(params, path, beta, swing, floor, held))


def _stance_speeds(params: Params, path) -> np.ndarray:
    """Joint speeds (samples, 2) rad/s along the nominal stance of the path."""
    gait, leg = params.gait, params.fivebar_leg
    u = np.linspace(1.0 - path.beta(gait), 1.0, 25, endpoint=False)
    points = evaluate(gait, path, u * gait.period_s)
    jf = leg.tool_jacobian(leg.inverse(points.pos, KNEES_OUT))
    return np.linalg.solve(jf, points.vel[..., None])[..., 0]


def _leg_motion(params: Params, path, t, phase_rad: float = 0.0):
    """(pose, q' (n, 2) rad/s, q'' (n, 2) rad/s^2) of the path at times t (n,) s for a leg at
    gait phase phase_rad: q' = J_F^-1 v exactly, q'' by central differences of q' (h = 1e-5 of
    the period)."""
    leg, gait = params.fivebar_leg, params.gait
    h = 1e-5 * gait.period_s

    def speeds(times):
        points = evaluate(gait, path, times, phase_rad)
        pose = leg.inverse(points.pos, KNEES_OUT, strict=False)
        jf = leg.tool_jacobian(pose)
        return pose, np.linalg.solve(jf, points.vel[..., None])[..., 0]

    pose, qd = speeds(t)
    qdd = (speeds(t + h)[1] - speeds(t - h)[1]) / (2.0 * h)
    return pose, qd, qdd


def _envelope(motor, torque, speed) -> tuple[float, str]:
    """(the least margin of the delivered torques (torque + friction) inside the envelope at
    their speeds, over the peak torque; what binds there: "torque" where the torque is past the
    peak, else "voltage (the no-load speed)")."""
    delivered = torque + motor.friction(speed)
    upper, lower = motor.limits(speed)
    margins = np.minimum(upper - delivered, delivered - lower)
    i = np.unravel_index(np.argmin(margins), margins.shape)
    peak = motor.peak_torque_Nm
    bind = ("torque" if abs(delivered[i]) >= min(peak, motor.braking_peak_torque_Nm) - 1e-9
            else "voltage (the no-load speed)")
    return float(margins[i] / peak), bind


def _swing_torques(params: Params, path):
    """(torques (n, 2) N*m, speeds (n, 2) rad/s) over the swing, or None out of reach or past
    [limits]."""
    gait = params.gait
    t = np.linspace(0.0, 1.0 - path.beta(gait), SWING_SAMPLES) * gait.period_s
    pose, qd, qdd = _leg_motion(params, path, t)
    if (not np.isfinite(pose.q).all() or not np.isfinite(qdd).all()
            or past_any(limit_tests(params.leg, pose), (t.size,)).any()):
        return None
    model = dataclasses.replace(full_model(params), foot_load_N=0.0)
    return params.fivebar_leg.torques(model, pose, qd, qdd).total, qd


def _best_swing(params: Params, path):
    """(the path with the swing shape of the largest least envelope margin, its figures:
    margin, bind, torques, speeds); Nelder-Mead from the plain quintic."""
    b = params.gait.b_m
    scale = max(params.gait.a_m, b)

    def shaped(c):
        return dataclasses.replace(path, swing_reach_m=float(c[0] * scale),
                                   swing_skew_m=float(c[1] * scale),
                                   swing_lift_skew_m=float(np.clip(c[2], -1.0, 1.0) * b))

    def cost(c):
        result = _swing_torques(params, shaped(c))
        if result is None:
            return 10.0
        return -_envelope(params.motor, *result)[0]

    found = minimize(cost, np.zeros(3), method="Nelder-Mead",
                     options={"maxfev": SWING_EVALUATIONS, "xatol": 1e-3, "fatol": 1e-4,
                              "initial_simplex": np.vstack([np.zeros(3), 0.3 * np.eye(3)])})
    c = found.x if found.fun <= cost(np.zeros(3)) else np.zeros(3)
    best = shaped(c)
    result = _swing_torques(params, best)
    if result is None:
        return best, {"margin": -1.0, "bind": "reach or [limits]"}
    margin, bind = _envelope(params.motor, *result)
    return best, {"margin": margin, "bind": bind, "torque": result[0], "speed": result[1]}


def _stance(params: Params, path, floor) -> dict:
    """The stance legs' motor torques (legs, knots, 2) N*m: the floor's plus the links' and
    rotors' inertia along the nominal stance (each leg at its phase), and their least margin
    in the envelope at the floor's joint speeds, with what binds."""
    t = floor.t
    extra = np.zeros_like(floor.torque_Nm)
    down = np.zeros(extra.shape[:2], dtype=bool)
    model = dataclasses.replace(full_model(params), foot_load_N=0.0)
    for i, name in enumerate(LEGS):
        phase = path.leg_phase(name)
        pose, qd, qdd = _leg_motion(params, path, t, phase)
        parts = params.fivebar_leg.torques(model, pose, qd, qdd)
        extra[i] = parts.inertial + parts.coriolis + parts.rotor
        down[i] = evaluate(params.gait, path, t, phase).stance
    torque = np.where(down[..., None], floor.torque_Nm + extra, 0.0)
    margin, bind = _envelope(params.motor, torque[down], floor.speed_rad_s[down])
    return {"margin": margin, "bind": bind, "torque": torque, "down": down}


def _figures(params: Params, path, beta: float, swing: dict, floor, stance: dict) -> dict:
    """The figures of a passing check: peak and worst RMS torque per motor over the cycle, the
    mechanical cost of transport and the neglected terms' sizes."""
    sw_t, sw_w = swing["torque"], swing["speed"]
    st_t, st_w = stance["torque"], floor.speed_rad_s
    peak = np.maximum(np.abs(sw_t).max(0), np.abs(st_t).max((0, 1)))
    # per leg: the stance's knots (zero in swing) and the swing's (1 - beta) of the period
    rms = np.sqrt((st_t**2).mean(1) + (1.0 - beta) * (sw_t**2).mean(0)).max(0)
    power = (np.abs(st_t * st_w).mean(1).sum()
             + len(LEGS) * (1.0 - beta) * np.abs(sw_t * sw_w).mean(0).sum())
    speed = path.stance_speed(params.gait)
    g = params.robot.gravity_m_s2
    dt = floor.t[1] - floor.t[0]
    accel = max(float(np.abs(np.roll(z, -1) - 2 * z + np.roll(z, 1)).max()) / dt**2
                for z in (floor.x_m, floor.z_m))
    weight = params.fivebar_leg.torques(
        dataclasses.replace(full_model(params), foot_load_N=0.0),
        *_leg_motion(params, path, np.linspace(0.0, 1.0 - beta, 11) * params.gait.period_s)
    ).link_weight
    return {"peak_Nm": tuple(float(v) for v in peak), "rms_Nm": tuple(float(v) for v in rms),
            "cost_of_transport": float(power / (floor.mass_kg * g * speed)), "path": path,
            "neglected": {"swing legs in the body's acceleration (N*m)":
                          float(np.abs(weight).max() * accel / g)}}
