"""Apply an injected fault to the truth model's fault inputs (the runner's
job: it is the one that sees both the commands and the truth state)."""
from __future__ import annotations

import math

from sim.faults import (
    CssFailed,
    FaultBase,
    IruBias,
    IruStuck,
    StarTrackerDropout,
    ThrusterFailedOff,
    ThrusterStuckOn,
    WheelDrag,
    WheelSeized,
)
from sim.truth.rigid_body import W_EXTRA_VISCOUS, W_MOTOR_OFF
from sim.truth.sensors import css, iru_units, star_tracker_exclusion
from sim.truth.thrusters import FAIL_OFF, STUCK_ON

# A seized rotor: the motor is dead and a stiff friction locks the rotor to the
# body within Js / c = 0.11 s (stable for RK4 steps up to ~0.3 s with Js 0.11).
SEIZED_VISCOUS_Nm_per_rad_s = 1.0


def _target(f: FaultBase, ts) -> tuple[object, int, str]:
    """(fault array, row, unit name) the fault acts on."""
    for attr, array in (("wheel", ts.inputs.wheel_faults), ("channel", ts.sensor_faults.iru),
                        ("tracker", ts.sensor_faults.st), ("thruster", ts.thruster_faults),
                        ("eye", ts.sensor_faults.css)):
        if hasattr(f, attr):
            return array, getattr(f, attr) - 1, attr
    raise TypeError(f"no target for fault {f.kind}")


def apply(f: FaultBase, ts, active: bool = True) -> str:
    """Set (or clear) the fault in the truth state ts; return why it cannot
    be applied, or "" when it was."""
    array, row, unit = _target(f, ts)
    if not 0 <= row < array.shape[0]:
        return f"{unit} {row + 1} does not exist; this spacecraft has {unit}s 1-{array.shape[0]}"
    on = 1.0 if active else 0.0
    if isinstance(f, WheelSeized):
        array[row, W_MOTOR_OFF] = on
        array[row, W_EXTRA_VISCOUS] = SEIZED_VISCOUS_Nm_per_rad_s * on
    elif isinstance(f, WheelDrag):
        array[row, W_EXTRA_VISCOUS] = f.viscous_Nm_per_rad_s * on
    elif isinstance(f, IruStuck):
        array[row, iru_units.FAULT_STUCK] = on
    elif isinstance(f, IruBias):
        array[row, iru_units.FAULT_EXCESS_BIAS] = math.radians(f.bias_deg_h) / 3600.0 * on
    elif isinstance(f, StarTrackerDropout):
        array[row, star_tracker_exclusion.FAULT_DROPOUT] = on
    elif isinstance(f, ThrusterFailedOff):
        array[row, FAIL_OFF] = on
    elif isinstance(f, ThrusterStuckOn):
        array[row, STUCK_ON] = on
    elif isinstance(f, CssFailed):
        array[row, css.FAULT_FAILED] = on
    return ""
