"""The gait source block: time -> the foot references of every leg (a foot path of
gaits/, any registered kind), the first block of the quadruped's Diagram."""

from __future__ import annotations

import numpy as np
from pydrake.systems.framework import BasicVector, LeafSystem

from fivebar_drake.core.compiled import bound
from fivebar_drake.gaits import REFERENCES_PER_LEG, FootPath, Gait, references_kernel


class GaitSource(LeafSystem):
    """Time (s) -> foot targets of all legs in their leg planes and the stance schedule.

    Output port "foot_references" (REFERENCES_PER_LEG x legs, footpath.reference_parts): foot
    targets (legs x (x, y), m), velocities (m/s), accelerations (m/s^2), then the stance
    weights (legs, in [0, 1]). The foot path (FootPath.point) with gait time tau = t - start_s,
    each leg at its phase (rad), about the home point (x_c, y_home) scaled by s ramping 0 -> 1
    over ramp_s (none for a maneuver); the stance weights blend from all-stance to the schedule
    with the same s. While standing (t < start_s) the feet rest at home (FootPath.home), all in
    stance.

    The output is a function of time alone, computed when it is asked for and cached by Drake
    until time moves (the controller samples it once a tick): no state, no update event."""

    def __init__(self, gait: Gait, path: FootPath, phases, start_s: float, ramp_s: float,
                 transfer_s: float):
        super().__init__()
        self._args = (path.constants(gait), *path.clock(gait), path.stance_start(gait),
                      float(transfer_s), np.ascontiguousarray(path.home(gait), dtype=float),
                      np.ascontiguousarray(phases, dtype=float), float(path.start_s(start_s)),
                      float(ramp_s) if path.periodic else 0.0, path.periodic)
        self._kernel = bound(references_kernel(path.point), *self._args, 0.0)
        self.DeclareVectorOutputPort("foot_references",
                                     BasicVector(REFERENCES_PER_LEG * len(phases)),
                                     self._calc, {self.time_ticket()})
        self.references(0.0)     # compiled now (references_kernel), not in the first tick

    @classmethod
    def add_to(cls, builder, gait: Gait, path: FootPath, phases, start_s: float, ramp_s: float,
               transfer_s: float) -> "GaitSource":
        """Add the source of the path (named "gait_source") to the DiagramBuilder; start_s: the
        scenario's standing time (FootPath.start_s), ramp_s its ramp."""
        return builder.AddNamedSystem("gait_source", cls(gait, path, phases, start_s, ramp_s,
                                                         transfer_s))

    def references(self, t: float) -> np.ndarray:
        """The output port's value at time t (s)."""
        return self._kernel(*self._args, float(t))

    def _calc(self, context, output):
        output.SetFromVector(self.references(context.get_time()))
