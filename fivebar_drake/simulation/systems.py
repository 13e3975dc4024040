"""The leg controllers as variants (Controller, registered by kind in CONTROLLERS) and the foot/leg
controller's block; the gait source is simulation/gait_source.GaitSource, the motor model
simulation/motor_model.MotorModel.

Legs are ordered FL, FR, RL, RR; per leg the motors A, B and foot coordinates (x, y) in the leg
plane (m). Torque vectors (8) are in the plant's actuation order (LegIndices.actuators).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar
import numpy as np
from pydrake.systems.framework import LeafSystem

from fivebar_drake.core.compiled import bound
from fivebar_drake.gaits import REFERENCES_PER_LEG
from fivebar_drake.core.validation import check_number, require
from fivebar_drake.core.variants import Variant, documented, known, registrar
from fivebar_drake.mechanisms.fivebar import LINK_NAMES, com_fractions, physical_izz
from fivebar_drake.robots.quadruped.control_law import (CONTACT_LOAD_SHARE, FOREVER_S,
                                                        SUPPORT_FIELDS, ControlGains,
                                                        LawConstants, LegPlan, foot_loads,
                                                        leg_plan, leg_torques)
from fivebar_drake.robots.quadruped.stance_laws import STANCE_LAWS
from fivebar_drake.robots.quadruped.params import Params
from fivebar_drake.robots.quadruped.plant import RobotLayout
from fivebar_drake.robots.quadruped.legs import plane_rotation
from fivebar_drake.robots.quadruped.sdf import body_height


MIN_BANDWIDTH_HZ = 0.1            # a loop this slow cannot follow any gait
CONTROL_SAMPLES_PER_BANDWIDTH = 20  # a digital loop samples >= 20x its bandwidth, or its gains
#                                     (derived as if continuous) lose their phase margin
MAX_DELAY_BANDWIDTH_PHASE = 0.25  # delay * swing bandwidth < 1/4: a quarter period of delay
#                                   costs the swing loop 90 deg of phase, all its margin
MAX_DAMPING_RATIO = 2.0           # well past critical (1): more only slows the loops
MAX_CATCH_GAIN = 10.0             # the reflex saturates at the step height long before
MAX_CATCH_RATE_S = 1.0            # a velocity lead longer than a gait cycle anticipates nothing
MIN_TIME_STEP_S = 1e-6            # any step or period: the explicit bushing needs ~34 us; nothing
#                                   in the robot is faster

CONTROLLERS: dict[str, type[Controller]] = {}   # the leg controllers by kind
register_controller = registrar(CONTROLLERS, "controller")


@dataclass(frozen=True)
class Controller(Variant):
    """A leg controller (register with register_controller): a block with the input ports
    "foot_references" (GaitSource) and "plant_state" (nx) and the output port "torque_command"
    (8, N*m, actuation order), updated every control_period_s (s; the gait source samples at the
    same period), optionally the input port "contact_impulse" (nv, the integral of the plant's
    generalized contact forces: connected when the block has it), and optionally the attribute
    `gains` (a NamedTuple, summary.json's controller_gains; null without it). The builder
    puts Drake's DiscreteTimeDelay of control_delay_periods ticks between the block and the
    motor model. The default controller's fields are also scenario fields (the scenario's flat
    names); another's are given in its mapping (scenario.controller)."""

    control_period_s: float = documented(0.002, "update period of the leg controller")
    control_delay_periods: int = documented(0, "extra controller periods before a command is "
                                               "released (0: it reaches the motor model's next "
                                               "sample)")

    def check(self, field: str) -> None:
        check_number(f"{field}.control_period_s", self.control_period_s, MIN_TIME_STEP_S)
        check_number(f"{field}.control_delay_periods", self.control_delay_periods, 0,
                     integer=True)

    def check_scenario(self, scenario) -> None:
        """Check that this controller can drive the scenario (its gait, phases, ...), raising
        ParameterError naming the scenario's field; any scenario by default."""

    def add_to(self, builder, params: Params, layout: RobotLayout, scenario) -> LeafSystem:
        """Add the controller's block (named "leg_controller") to the DiagramBuilder for the
        scenario (simulation/scenario.Scenario: its gait, load_transfer_s over which a foot takes
        up its load, payload, stand and ramp times)."""
        raise NotImplementedError


def derive_gains(mass_kg: float, inertia_kg_m2, leg_inertia_kg_m2: float, swing_hz: float,
                 body_hz: float, damping_ratio: float) -> ControlGains:
    """Gains that place a second-order mode at the given frequency and damping ratio: a swing
    joint of inertia leg_inertia (kg*m^2, links and reflected rotor about the motor axis) at
    swing_hz; the body's height, roll and pitch (mass kg, inertia (3, 3) kg*m^2 about the COM)
    at body_hz; the forward speed as a first-order loop at body_hz."""
    ws, wb, z = 2 * np.pi * swing_hz, 2 * np.pi * body_hz, damping_ratio
    i_att = np.array([inertia_kg_m2[0][0], inertia_kg_m2[1][1]])
    return ControlGains(kp=float(leg_inertia_kg_m2 * ws**2),
                        kd=float(2 * z * leg_inertia_kg_m2 * ws), kz=float(mass_kg * wb**2),
                        dz=float(2 * z * mass_kg * wb), dx=float(mass_kg * wb),
                        k_att=i_att * wb**2, d_att=2 * z * i_att * wb)


class FootLegController(LeafSystem):
    """Foot targets, stance schedule and the sampled plant state -> motor torque commands.

    Input ports: "foot_references" (GaitSource), "plant_state" (nx). Output port:
    "torque_command" (8) N*m in actuation order. Every knobs.control_period_s the controller
    samples its inputs and computes a command, held until the next tick (a delay is Drake's
    block after it, Controller). Input port "contact_impulse" (nv): the integral of the
    plant's generalized contact forces over every plant step; its change over a controller
    period is the feet's mean ground force in that period (what a foot-force sensor measures).

    - Swing (weight 1 - w per leg): joint PD to the closed-form IK of the target (knees out) with
      the full model's inverse dynamics (M q'' + c + G of the links, reflected rotor inertia) of
      the target's motion as feed-forward.
    - Stance (weight w): the links' weight at the measured pose, and the stance law
      (knobs.stance_law, robots/quadruped/stance_laws.py); the default is a virtual-model
      controller. The body's targets follow from the stance feet's targets: height z = foot
      radius - hip z - y, vertical speed -y', forward speed the feet's x' (leg-plane x points
      backwards). The wrench on the body, in the body frame,
      F_x = m dx (v_x* - v_x), F_z = m (g + z*'') + kz (z* - z) + dz (z*' - z'),
      M_roll,pitch = -k_att angle - d_att rate, is shared by the stance feet: the in-plane ground
      forces of least weighted norm (weights w) that produce it, vertical forces >= 0 and
      horizontal ones inside the friction cone. That split already gives each foot its share
      (none at w = 0), so each motor pair adds -J_F(q)^T F in full, not blended by w: the feet
      deliver the whole wrench while a foot takes up or gives off its load.
    - A foot takes load only once it is measured on the ground, its weight rising from
      contact over load_transfer_s (control_law.support_weights); with touchdown_detection a
      swing foot that has been in the air and lands early joins the support the same way and
      stays where it landed; its swing path never guides the body. A foot due on the ground
      and not there reaches further down at SEARCH_SPEED_M_S until it is.
    - Feet land on the ground as it is: while some foot guides the body, every foot target is
      moved by the difference between its planned height above the ground and its height
      above z = 0 with the body where it is (tilt and height), so a swing ends on the ground
      at its planned speed whatever the body does.
    - Swing legs catch the body (catch_gain > 0): under a hip that the body's rotation sinks,
      the swing foot reaches a little further down (control_law.catch_offset). The legs are
      planar and cannot step sideways: with a diagonal pair alone on the ground nothing else
      stops the body tipping about the diagonal.
    - The links' weight is compensated on every leg."""

    def __init__(self, params: Params, layout: RobotLayout, gains: ControlGains, knobs: FootLeg,
                 transfer_s: float, early_touchdown: bool = True):
        super().__init__()
        self._mechanism, self._layout = params.fivebar_leg, layout
        self.constants = LawConstants(
            state=layout.state,
            hips_m=np.ascontiguousarray(layout.hips_m, dtype=float),
            com_m=np.asarray(layout.com_m, dtype=float), mass_kg=float(layout.mass_kg),
            plane=plane_rotation(), geom=params.leg.core,
            com_fraction=com_fractions(params.leg, params.links),
            masses=np.array([params.links[n].mass_kg for n in LINK_NAMES]),
            izz=np.array(physical_izz(params.leg, params.links)), gravity=params.robot.gravity_m_s2,
            reflected_inertia=params.motor.reflected_inertia_kg_m2, gains=gains,
            foot_radius_m=params.body.foot_radius_m,
            stand_offset_m=float(body_height(params, 0.0)), mu=params.body.foot_friction,
            catch_gain=float(knobs.catch_gain), catch_rate_s=float(knobs.catch_rate_s),
            catch_limit_m=params.gait.b_m, touchdown=bool(knobs.touchdown_detection and early_touchdown),
            support=-np.asarray(layout.gravity_m_s2, dtype=float),
            contact_N=float(CONTACT_LOAD_SHARE * layout.mass_kg
                            * np.linalg.norm(layout.gravity_m_s2) / len(layout.legs)),
            transfer_s=float(transfer_s))
        n = layout.state.q_index.size
        self._period = knobs.control_period_s
        self._forces = STANCE_LAWS[knobs.stance_law].forces
        self._references = self.DeclareVectorInputPort(
            "foot_references", REFERENCES_PER_LEG * layout.state.q_index.shape[0])
        self._state = self.DeclareVectorInputPort("plant_state", layout.nx)
        self._impulse = self.DeclareVectorInputPort("contact_impulse", layout.nv)
        self._command = self.DeclareDiscreteState(n)         # the output, held between ticks
        # the tick's memory, one group: the feet's support (control_law.support_weights), every
        # foot standing before the run, then the contact impulse at the last tick
        support = self.standing_support().ravel()
        self._support_size = support.size
        self._memory = self.DeclareDiscreteState(np.concatenate([support, np.zeros(layout.nv)]))
        self.DeclarePeriodicDiscreteUpdateEvent(knobs.control_period_s, 0.0, self._update)
        self.DeclareStateOutputPort("torque_command", self._command)
        # the kernels that take the constants, for the argument types a tick passes (bound)
        k, legs, state = self.constants, layout.state.q_index.shape[0], np.zeros(layout.nx)
        self._leg_plan = bound(leg_plan, k, np.zeros(REFERENCES_PER_LEG * legs), state,
                           np.zeros(legs), self.standing_support(), 0.0)
        self._foot_loads = bound(foot_loads, k, state, np.zeros(layout.nv))
        plan = self._leg_plan(k, np.zeros(REFERENCES_PER_LEG * legs), state, np.zeros(legs),
                          self.standing_support(), 0.0)      # its fields' types (values: nan)
        self._forces = bound(self._forces, k, plan.body, plan.weights, plan.share, plan.fx,
                             plan.fy, state, plan.r_wb)

    @property
    def gains(self) -> ControlGains:
        return self.constants.gains

    def standing_support(self) -> np.ndarray:
        """The support memory (legs, SUPPORT_FIELDS) of feet that stood on the ground before
        the run began (the start of every run: a foot scheduled in swing leaves it)."""
        memory = np.zeros((self._layout.state.q_index.shape[0], SUPPORT_FIELDS))
        memory[:, 0], memory[:, 2], memory[:, 3] = 1.0, -FOREVER_S, 0.0
        return memory

    def command(self, references, state, loads_N=None, support=None,
                t: float = 0.0, gait_s: float | None = None) -> np.ndarray:
        """Torque command (8) in actuation order at time t (s) from the foot references
        (GaitSource), the plant state vector (nx,), the feet's measured normal forces (legs,)
        in N (default: every foot on the ground) and their support memory (legs,
        SUPPORT_FIELDS; default: standing_support; updated in place)
        (control_law.leg_plan, the stance law's forces, control_law.leg_torques); gait_s (s,
        default t): the gait's clock, which the references were taken at (a controller variant
        may let it lag t: TrackingController). Raises UnreachableError naming the target or pose
        where the legs cannot close."""
        memory = self.standing_support() if support is None else support
        n = memory.shape[0]
        loads = np.full(n, np.inf) if loads_N is None else np.ascontiguousarray(loads_N, float)
        state = np.ascontiguousarray(state, dtype=float)
        require(memory.flags.c_contiguous and memory.dtype == float, "support", memory.dtype,
                "a C-contiguous float array (it is updated in place)")
        plan = self._leg_plan(self.constants, np.ascontiguousarray(references, dtype=float),
                              state, loads, memory, float(t))
        out, finite = leg_torques(self.constants.state.actuators, *self.stance_torques(
            plan, state, float(t), float(t if gait_s is None else gait_s)))
        if not finite:                        # name the reason, if it is a reach
            self._mechanism.inverse(plan.goal)
            self._mechanism.forward(state[self._layout.state.q_index])
        return out

    def stance_torques(self, plan: LegPlan, state: np.ndarray, t: float,
                       gait_s: float) -> tuple:
        """(base (8) N*m in actuation order, the foot Jacobians (legs, 2, 2), the feet's ground
        forces (legs, 2) N in their leg planes) of a tick's command (control_law.leg_torques) at
        time t (s), the gait's clock at gait_s (s): the plan's base and the stance law's forces.
        A controller variant changes them here."""
        forces = self._forces(self.constants, plan.body, plan.weights, plan.share, plan.fx,
                              plan.fy, state, plan.r_wb)
        return plan.base, plan.jf, forces

    def tick_inputs(self, context) -> tuple:
        """What a tick at the context's time computes from (the arguments of command): the
        foot references, the plant state, the feet's measured normal forces over the last
        period (N), a copy of the support memory and the time (s)."""
        return (self._references.Eval(context), *self._tick(context)[:4])

    def _tick(self, context) -> tuple:
        """What every tick reads but the references (a controller variant may take them at
        another time): the plant state, the feet's measured normal forces over the last period
        (N), a copy of the support memory, the time (s) and the contact impulse now (nv,)."""
        state = self._state.Eval(context)
        impulse = self._impulse.Eval(context)
        memory = context.get_discrete_state(self._memory).get_value()
        last = memory[self._support_size:]
        return (state, self._foot_loads(self.constants, state, (impulse - last) / self._period),
                memory[:self._support_size].reshape(-1, SUPPORT_FIELDS).copy(),
                context.get_time(), impulse)

    def _update(self, context, discrete_state):
        state, loads, memory, t, impulse = self._tick(context)
        new = self.command(self._references.Eval(context), state, loads, memory, t)
        self._store(discrete_state, memory, impulse, new)

    def _store(self, discrete_state, memory, impulse, command) -> None:
        """Keep a tick's support memory (as command updated it), the contact impulse now and
        the command."""
        discrete_state.set_value(self._memory, np.concatenate([memory.ravel(), impulse]))
        discrete_state.set_value(self._command, command)


@register_controller
@dataclass(frozen=True)
class FootLeg(Controller):
    """The foot/leg controller (FootLegController) with its knobs; gains from the robot's
    numbers (gains)."""

    kind: ClassVar[str] = "foot_leg"
    swing_bandwidth_hz: float = documented(15.0, "swing legs' joint PD bandwidth")
    body_bandwidth_hz: float = documented(3.0, "stance legs' body (height, speed, attitude) "
                                               "bandwidth")
    damping_ratio: float = documented(0.7, "damping ratio of both loops")
    catch_gain: float = documented(1.0, "swing legs' catch reflex: gain on the reach ahead of "
                                        "a sinking hip (0 = off)")
    catch_rate_s: float = documented(0.05, "catch reflex: a swing foot reaches catch_gain x "
                                           "this x the hip's sinking speed further down")
    touchdown_detection: bool = documented(True, "a swing foot in the air that is measured on "
                                                 "the ground early (on its way down) joins the "
                                                 "support (not for a path that declines it: "
                                                 "the pronk, whose feet land together)")
    stance_law: str = documented("virtual_model", "the stance feet's ground-force law, a "
                                                  "registered kind (robots/quadruped/"
                                                  "stance_laws.py)")

    def check(self, field: str) -> None:
        number = check_number
        for name in ("swing_bandwidth_hz", "body_bandwidth_hz"):
            number(f"{field}.{name}", getattr(self, name), MIN_BANDWIDTH_HZ)
        fastest = max(self.swing_bandwidth_hz, self.body_bandwidth_hz)
        number(f"{field}.control_period_s", self.control_period_s, MIN_TIME_STEP_S,
               1.0 / (CONTROL_SAMPLES_PER_BANDWIDTH * fastest),
               why=f"a digital loop samples at least {CONTROL_SAMPLES_PER_BANDWIDTH}x its "
                   f"bandwidth, here {fastest:g} Hz")
        number(f"{field}.control_delay_periods", self.control_delay_periods, 0,
               math.floor(MAX_DELAY_BANDWIDTH_PHASE
                          / (self.swing_bandwidth_hz * self.control_period_s) - 1e-9),
               integer=True, why=f"the delay must stay below {MAX_DELAY_BANDWIDTH_PHASE:g} of "
                                 "a period of swing_bandwidth_hz, or the swing loop has no "
                                 "phase margin left")
        number(f"{field}.damping_ratio", self.damping_ratio, 0.0, MAX_DAMPING_RATIO,
               low_open=True)
        number(f"{field}.catch_gain", self.catch_gain, 0.0, MAX_CATCH_GAIN)
        number(f"{field}.catch_rate_s", self.catch_rate_s, 0.0, MAX_CATCH_RATE_S)
        require(known(STANCE_LAWS, self.stance_law), f"{field}.stance_law", self.stance_law,
                f"allowed {list(STANCE_LAWS)}")

    def gains(self, params: Params, layout: RobotLayout) -> ControlGains:
        """Gains from the robot's numbers: the swing joint's inertia is the largest diagonal
        entry of the leg's mass matrix at home plus the reflected rotor inertia
        (derive_gains)."""
        leg = params.fivebar_leg
        home = leg.inverse(np.array([params.gait.x_center_m, params.gait.y_home_m]))
        leg_inertia = (np.max(np.diag(leg.mass_matrix(home)))
                       + params.motor.reflected_inertia_kg_m2)
        return derive_gains(layout.mass_kg, layout.inertia_kg_m2, leg_inertia,
                            self.swing_bandwidth_hz, self.body_bandwidth_hz, self.damping_ratio)

    def add_to(self, builder, params: Params, layout: RobotLayout,
               scenario) -> FootLegController:
        return builder.AddNamedSystem("leg_controller", FootLegController(
            params, layout, self.gains(params, layout), self, scenario.load_transfer_s,
            scenario.gait.early_touchdown))
