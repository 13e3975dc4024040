"""Every mechanism class by name (the names of `--mechanism`). Each names the parts of
mechanisms/base.py it implements in `parts`; tests/mechanisms/test_parts.py runs one generic
check per part over every class here, so a new mechanism is registered here and given an example
(an instance, tool points, a load and Drake's static torques) in that test."""

from fivebar_drake.mechanisms.ballscrew_leg import BallScrewLeg
from fivebar_drake.mechanisms.fivebar import FiveBarLeg
from fivebar_drake.mechanisms.parallel4.mechanism import Parallel4
from fivebar_drake.mechanisms.scara import ScaraArm

MECHANISMS = {"fivebar_leg": FiveBarLeg, "ballscrew_leg": BallScrewLeg, "scara": ScaraArm,
              "parallel4": Parallel4}
