"""The motor model block: the geared actuator's law (actuators/motor.py) between a controller's torque
command and the plant's actuation, at every plant step."""

from __future__ import annotations

import numpy as np
from pydrake.systems.framework import Diagram, DiagramBuilder, LeafSystem
from pydrake.systems.primitives import (Demultiplexer, DiscreteTimeDelay, MatrixGain,
                                        ZeroOrderHold)

from fivebar_drake.actuators.motor import MEMORY, Motor, motor_step
from fivebar_drake.core.compiled import bound


class MotorModel(Diagram):
    """Commanded torque and joint speed -> torque at the joints, one actuator per joint, values
    at the gearbox output, SI.

    Input ports: "torque_command" (n) N*m, "plant_state" (nx). Every period_s the command is
    sampled and held (zero-order hold, the drive's command rate). The torque of each plant step
    is evaluated from the joint speeds at the step's start (a direct feedthrough of the plant's
    state, which must not depend on its actuation: a discrete plant with unsampled output
    ports; a real drive's current loop sees the speed at once): the command clamped to the
    actuator's envelope (torque_limits: current and voltage limits through the gearbox, both
    quadrants, with the regenerative braking the back-EMF forces beyond the no-load speed), less
    friction (Coulomb, regularised over |w| < FRICTION_SMOOTHING_RAD_S, and viscous), both at
    the joint's mean speed over the step (held_torque), which follows from its response to its
    torque and its load, measured over the steps before (motor_step; the memory is sampled at
    every plant step of step_s). Why: a leg in the air (about 5e-4 kg m^2 at a hip here) gains 10 rad/s in a
    1 ms step at 5 N·m, while the voltage limit's time constant, J R / (N^2 eta k_t k_e), is
    0.6 ms: the limit taken at a speed from before the step let the joint overshoot the no-load
    speed while still driving (the jump's RL A: 20.8 rad/s at +5 N·m), and the braking the
    back-EMF forces beyond it, taken explicitly, oscillates; a loaded leg hardly responds within
    a step and gets the envelope at its speed. Measured on a single joint against the
    continuous law (tests/core/test_motor.py): the step's mean speed follows the continuous
    solution more closely than its end speed, whose lag a loaded joint feels.

    Output ports: "applied_torque" (n) N*m at the joints (delivered - friction, within
    +-Motor.max_applied_torque_Nm, the plant's effort limit); "motor_record" (3 n): the held
    command, the delivered torque and the applied torque (N*m) of the plant step that starts
    now (actuators.motor.clip_flags classifies the clipping). A recorder sampling it every period_s
    sees each motor period's first plant step. The rotor's reflected inertia N^2 J_rotor is in
    the plant (<drake:rotor_inertia>, <drake:gear_ratio>), not here.

    A Diagram of Drake's primitives around one Python block, so that a plant step makes one
    Python callback: the command's ZeroOrderHold (C++) -> MotorStep (the compiled law,
    motor_step, on the held command, the joint speeds and the memory of the steps before: one
    output of the step's values and what the next step needs) -> a Demultiplexer (C++): the
    record, the applied torque through a MatrixGain selecting it (C++), and the memory kept by a
    DiscreteTimeDelay sampling it at each plant step (C++), fed back to MotorStep."""

    def __init__(self, motor: Motor, v_index_in_state, nx: int, period_s: float,
                 step_s: float):
        super().__init__()
        n = len(v_index_in_state)
        size = MEMORY * n + 2                       # the memory and the flag "kept"
        builder = DiagramBuilder()
        hold = builder.AddNamedSystem("command_hold", ZeroOrderHold(period_s, n))
        law = builder.AddNamedSystem("motor_step", MotorStep(motor, v_index_in_state, nx))
        split = builder.AddNamedSystem("split", Demultiplexer([3 * n, size]))
        applied = builder.AddNamedSystem("applied", MatrixGain(
            np.hstack([np.zeros((n, 2 * n)), np.eye(n)])))
        memory = builder.AddNamedSystem("memory", DiscreteTimeDelay(step_s, 0, size))
        builder.Connect(hold.get_output_port(), law.GetInputPort("held_command"))
        builder.Connect(law.GetOutputPort("motor_step"), split.get_input_port())
        builder.Connect(split.get_output_port(0), applied.get_input_port())
        builder.Connect(split.get_output_port(1), memory.get_input_port())
        builder.Connect(memory.get_output_port(), law.GetInputPort("memory"))
        builder.ExportInput(hold.get_input_port(), "torque_command")
        builder.ExportInput(law.GetInputPort("plant_state"), "plant_state")
        builder.ExportOutput(applied.get_output_port(), "applied_torque")
        builder.ExportOutput(split.get_output_port(0), "motor_record")
        builder.BuildInto(self)


class MotorStep(LeafSystem):
    """The motor law over the plant step that starts now (actuators.motor.motor_step). Input ports:
    "held_command" (n) N*m, "plant_state" (nx), "memory" (MEMORY n + 2: what the step before
    left, then 1 once kept; all zero before the first step). Output port "motor_step" (3 n +
    MEMORY n + 2): the held command, the delivered and the applied torque (N*m), then what the
    next step needs and 1."""

    def __init__(self, motor: Motor, v_index_in_state, nx: int):
        super().__init__()
        self._law = motor.law
        self._cap = float(motor.max_applied_torque_Nm)
        self._v_index = np.asarray(v_index_in_state, dtype=np.int64)
        n = self._n = self._v_index.size
        self._held = self.DeclareVectorInputPort("held_command", n)
        self._state = self.DeclareVectorInputPort("plant_state", nx)
        self._memory = self.DeclareVectorInputPort("memory", MEMORY * n + 2)
        first = np.zeros(MEMORY * n + 1)            # no step before: nothing measured yet
        first[3::MEMORY] = np.nan
        first[6::MEMORY] = np.nan
        first[-1] = np.nan
        self._first = first
        self.DeclareVectorOutputPort("motor_step", 3 * n + MEMORY * n + 2, self._calc, {
            self.all_input_ports_ticket(), self.time_ticket()})
        out = np.zeros(3 * n + MEMORY * n + 2)         # the kernel for the types _calc passes
        self._step = bound(motor_step, self._law, np.zeros(n), np.zeros(n), first, 0.0,
                           self._cap, out[:3 * n], out[3 * n:-1])

    def _calc(self, context, output):
        memory = self._memory.Eval(context)
        out = output.get_mutable_value()
        n = self._n
        self._step(self._law, self._held.Eval(context), self._state.Eval(context)[self._v_index],
                   memory[:-1] if memory[-1] else self._first, context.get_time(), self._cap,
                   out[:3 * n], out[3 * n:-1])
        out[-1] = 1.0
