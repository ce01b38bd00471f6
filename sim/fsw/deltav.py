"""DeltaV burn sequencing, seed 001 "DeltaV".

* "In main engine burns, the ACS thrusters on-pulse as needed for control,
  and in burns without the main engine, the ACS thrusters provide the
  velocity change and off-pulse for disturbance rejection."
* A settling burn on the ACS thrusters (off-pulsing) precedes a main-engine
  burn (the issue: 20 s; the burn duration includes it: seed 001 entry item
  (2) "burn duration, including any settling burn length").
* "The exit criterion for the DeltaV mode is based on spending a prescribed
  amount of time in the mode".
Attitude control is the thruster PD of thruster_modes.py toward the DeltaV
target, which set_deltav_target may change mid-burn.
"""
from numba import njit

PHASE_SETTLE, PHASE_ENGINE, PHASE_ACS, PHASE_DONE = 0, 1, 2, 3


@njit(cache=True)
def burn_phase(k, burn_cycles, settle_cycles, main_engine):
    """The phase of burn cycle k (0-based)."""
    if k >= burn_cycles:
        return PHASE_DONE
    if not main_engine:
        return PHASE_ACS
    return PHASE_SETTLE if k < settle_cycles else PHASE_ENGINE
