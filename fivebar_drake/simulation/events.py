"""A run's key events, found in its recorded foot forces and body height (any gait or maneuver):
each foot's lift-off and touchdown, and for a flight (every foot off the ground) its takeoff,
the apex of the body height and the touchdown that ends it.

A foot is on the ground while the ground force on it exceeds CONTACT_N; a contact or an air
phase shorter than MIN_PHASE_S is chatter and joins the phase around it (so is a flight)."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

CONTACT_N = 2.0        # a foot pressing harder than this is on the ground (~3 % of a foot's share)
MIN_PHASE_S = 0.01     # shorter contact, air or flight phases are chatter
FOOT_KINDS = ("lift-off", "touchdown")
FLIGHT_KINDS = ("takeoff", "apex", "touchdown")


class Event(NamedTuple):
    """t_s: the time of the row the event is seen in (s); kind: FOOT_KINDS for a foot,
    FLIGHT_KINDS for the whole robot (leg ""); height_m: the body height then (m)."""

    t_s: float
    kind: str
    leg: str
    height_m: float

    @property
    def text(self) -> str:
        where = f"{self.leg} " if self.leg else "flight "
        return f"{where}{self.kind} (body height {self.height_m * 1e3:.1f} mm)"


def phases(t: np.ndarray, on: np.ndarray, min_phase_s: float = MIN_PHASE_S) -> np.ndarray:
    """The flags on (rows,) over the times t (s) with every phase (a run of equal flags) shorter
    than min_phase_s turned into the phase before it (the first into the one after it); a
    phase's length is the time from its first row to the next phase's first row."""
    on = np.asarray(on, dtype=bool).copy()
    while len(on) > 1:
        starts = np.flatnonzero(np.r_[True, on[1:] != on[:-1]])
        ends = np.r_[t[starts[1:]], np.inf]            # the last phase lasts: it is not chatter
        short = np.flatnonzero(ends - t[starts] < min_phase_s)
        if not len(short) or len(starts) == 1:
            break
        k = short[np.argmin((ends - t[starts])[short])]  # the shortest first, one at a time
        stop = starts[k + 1] if k + 1 < len(starts) else len(on)
        on[starts[k]:stop] = on[starts[k] - 1] if k > 0 else on[stop]
    return on


def detect_events(t, foot_force_N, height_m, legs, contact_N: float = CONTACT_N,
                  min_phase_s: float = MIN_PHASE_S) -> list[Event]:
    """The events (sorted by time) of rows at times t (s) from the ground force magnitude on
    each foot foot_force_N (rows, legs) N and the body height height_m (rows,) m. The apex of a
    flight is the row of its greatest height (the last row if the data ends in flight)."""
    t, height = np.asarray(t, dtype=float), np.asarray(height_m, dtype=float)
    contact = np.stack([phases(t, f > contact_N, min_phase_s)
                        for f in np.asarray(foot_force_N, dtype=float).T], 1)
    events = []
    for i, leg in enumerate(legs):
        change = np.flatnonzero(contact[1:, i] != contact[:-1, i]) + 1
        events += [Event(t[k], FOOT_KINDS[int(contact[k, i])], leg, height[k]) for k in change]
    flying = phases(t, ~contact.any(1), min_phase_s)
    change = np.flatnonzero(flying[1:] != flying[:-1]) + 1
    for k in change:
        if flying[k]:
            events.append(Event(t[k], "takeoff", "", height[k]))
            end = next((j for j in change if j > k), len(t))
            top = k + int(np.argmax(height[k:end]))
            events.append(Event(t[top], "apex", "", height[top]))
        else:
            events.append(Event(t[k], "touchdown", "", height[k]))
    return sorted(events, key=lambda e: (e.t_s, e.leg == ""))
