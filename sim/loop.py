"""The compiled cycle loop: sensors -> flight software -> actuators -> truth.

The runner calls `advance` once per segment, a run of control cycles with
nothing for Python to do: no command due, no telemetry sample, no
flight-software event. The loop returns early on an event so the Python side
(mode machine, command lifecycle) acts at the exact cycle. Crossing the wall
is here, in the runner's code: sim.truth and sim.fsw never meet otherwise.
"""
from numba import njit

from sim.fsw.cycle import fsw_cycle
from sim.fsw.safehold import ace_cycle
from sim.records import copy_command
from sim.telemetry_fields import _numbers
from sim.truth.plant import propagate, sense, set_environment


@njit(cache=True)
def advance(n_cycles, cycle0, cycle_s, ts, tp, noise, noise_row, rec, s, fp, ace, ap, act_applied, act_new, delay,
            cycle_ns, tlm_every, tlm_rows, tlm_mode):
    """Run up to n_cycles from control cycle number cycle0; return (cycles run,
    last event code, telemetry rows written).

    Telemetry samples that fall inside the segment (every tlm_every cycles,
    not its first cycle) are computed here, into tlm_rows / tlm_mode, with the
    same function the runner uses: a segment no longer ends at each sample,
    which saves the records' unboxing twice per sample (~0.1 ms each).

    With a one-cycle actuator delay the command computed from the samples at
    t_k drives the plant over [t_k+1, t_k+2]; with none, over [t_k, t_k+1].
    """
    n_rows = 0
    for k in range(n_cycles):
        c = cycle0 + k
        if k > 0 and c % tlm_every == 0:   # the segment's first sample is the runner's (after its commands)
            tlm_rows[n_rows, :] = _numbers(c * cycle_ns / 1e9, ts, tp, s, rec, act_applied)
            tlm_mode[n_rows] = s.mode[0]
            n_rows += 1
        set_environment(ts, tp, (cycle0 + k) * cycle_s)
        sense(ts, tp, noise[noise_row + k], rec)
        event = fsw_cycle(rec, s, fp, act_new)
        # the ACE runs beside the main processor and overrides it in Safehold
        if ap.present:
            ace_event = ace_cycle(s.proc_up[0], rec.css_current_A, rec.iru_rate_ch_rad_s, rec.iru_ch_valid,
                                  rec.tach_speed_rad_s, ace, ap, act_new.wheel_torque_Nm, act_new.thruster_pulses,
                                  act_new.engine_on)
            if event == 0:
                event = ace_event
        elif not s.proc_up[0]:   # no ACE: nothing commands the actuators
            act_new.wheel_torque_Nm[:] = 0.0
            act_new.thruster_pulses[:] = 0.0
            act_new.engine_on[0] = 0.0
        if delay == 0:
            copy_command(act_new, act_applied)
        propagate(ts, tp, act_applied)
        if delay != 0:
            copy_command(act_new, act_applied)
        if event != 0:
            return k + 1, event, n_rows
    return n_cycles, 0, n_rows
