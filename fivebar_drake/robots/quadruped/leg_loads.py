"""The seed's torque model readings for one leg of this robot: as written, physically consistent,
and under trot loading."""

from __future__ import annotations

import numpy as np

from fivebar_drake.gaits import FootPath, stance_loads
from fivebar_drake.mechanisms.fivebar import DynamicsModel, LINK_NAMES, physical_izz
from fivebar_drake.robots.quadruped.params import Params
from fivebar_drake.robots.quadruped.legs import TROT_PHASES_RAD


def seed_model(params: Params) -> DynamicsModel:
    """Seed 000 eqs. 6-8 as written: no Coriolis, [0, -1] for link weights, Izz_AC = 0."""
    return DynamicsModel(
        name="seed",
        description="seed 000 as written: tau = M q'' + G, G with [0, -1] for the link weights "
                    "and the foot load, Coriolis dropped, Izz of AC = 0",
        izz=tuple(params.links[n].izz_kg_m2 for n in LINK_NAMES),
        link_weight_sign=-1.0, coriolis=False,
        foot_load_N=params.robot.weight_share_kg * params.robot.gravity_m_s2,
        gravity_m_s2=params.robot.gravity_m_s2)


def full_model(params: Params) -> DynamicsModel:
    """Physically consistent: link weights held up (+[0, 1]), Coriolis kept, Izz_AC thin rod,
    the rotors' inertia reflected through the gearbox (N^2 J_rotor on each motor)."""
    return DynamicsModel(
        name="full",
        description="physically consistent: tau = (M + N^2 J_rotor) q'' + c(q, q') + G, link "
                    "weights held up (+[0, 1]), foot load m_leg g J_F^T [0, -1], Izz of AC = "
                    "thin rod m L^2/12, the rotors reflected through the gearbox",
        izz=physical_izz(params.leg, params.links),
        link_weight_sign=1.0, coriolis=True,
        foot_load_N=params.robot.weight_share_kg * params.robot.gravity_m_s2,
        gravity_m_s2=params.robot.gravity_m_s2,
        rotor_inertia_kg_m2=params.motor.reflected_inertia_kg_m2)


def trot_model(params: Params, path: FootPath | str, t, phases_rad=TROT_PHASES_RAD,
               leg: int = 0) -> DynamicsModel:
    """The full model under trot loading at times t (s) of the foot path: the robot's weight
    shared by the feet the schedule (legs' gait phases phases_rad) has in stance, none in swing
    (gaits.stance_loads), on leg number `leg`."""
    weight = params.robot.total_mass_kg * params.robot.gravity_m_s2
    foot_load_N = stance_loads(params.gait, path, t, phases_rad, weight)[leg]
    return DynamicsModel(
        name="full_trot",
        description="full model, trot loading: the robot's weight shared by the feet the trot "
                    "schedule has in stance (half on each foot of a diagonal pair alone, a quarter "
                    "while all four are down), none in swing",
        izz=physical_izz(params.leg, params.links), link_weight_sign=1.0, coriolis=True,
        foot_load_N=np.asarray(foot_load_N, dtype=float), gravity_m_s2=params.robot.gravity_m_s2,
        rotor_inertia_kg_m2=params.motor.reflected_inertia_kg_m2)
