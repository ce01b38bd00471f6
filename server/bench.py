"""`acs bench`: built-in benchmark scenarios, reported as real-time ratios.

The machine is shared and noisy, so a figure means something only beside the
reference measured in the same minute: `--reference PYTHON` runs
../shared/bench/basilisk_reference.py in Basilisk's own virtual environment,
interleaved with ours, and prints the ratio of medians.
"""
from __future__ import annotations

import math
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import yaml

REPO = Path(__file__).resolve().parent.parent
HOLD_SCENARIO = REPO / "scenarios" / "sdo_inertial_hold.yaml"
SLEW_SCENARIO = REPO / "scenarios" / "sdo_inertial_slew.yaml"
SCIENCE_SCENARIO = REPO / "scenarios" / "sdo_science_day.yaml"
DELTAV_SCENARIO = REPO / "scenarios" / "sdo_deltav_main_engine.yaml"


def basilisk_mirror() -> dict:
    """The scenario of ../shared/bench/basilisk_reference.py: SDO's full-tank
    inertia, the four-wheel pyramid in Basilisk's order with its HR16 wheels
    (75 N m s at 6000 rpm, 0.2 N m, no friction, spun up to 100 rpm), the same
    initial MRP attitude and rates, an inertial hold of the identity attitude,
    truth and flight software both at 0.1 s, 3600 s, recorded every 10 s."""
    from sim.attitude import quat_from_mrp

    s, c = math.sin(math.radians(30)), math.cos(math.radians(30))
    axes = [[s, c, 0.0], [s, 0.0, c], [s, -c, 0.0], [s, 0.0, -c]]
    spin_inertia = 75.0 / (6000.0 * 2 * math.pi / 60.0)
    omega0 = [0.001, -0.01, 0.003]
    speed0 = 100.0 * 2 * math.pi / 60.0
    h0 = [spin_inertia * (speed0 + float(np.dot(a, omega0))) for a in axes]
    return {
        "name": "basilisk-mirror", "spacecraft": "sdo", "duration_s": 3600.0, "seed": 1,
        "overrides": {
            "timing": {"truth_dt_s": 0.1, "control_dt_s": 0.1},
            "thrusters": {"pulse_s": 0.05, "max_pulses_per_cycle": 2},   # two 50 ms pulses fit the 0.1 s cycle
            "wheels": {"axes_B": axes, "spin_inertia_kgm2": spin_inertia, "h_max_Nms": 75.0,
                       "torque_max_Nm": 0.2, "torque_limit_sw_Nm": 0.2, "viscous_Nm_per_rad_s": 0.0,
                       "coulomb_Nm": 0.0},
            # the reference's spacecraft carries no Sun sensors or tachometers: attitude
            # and rates only (its simpleNav; here the IRU and the star trackers)
            "sensors": {"css": None, "dss": None, "guide_telescopes": None, "tachometers": None},
            # its flight software takes the navigation attitude as it is (fly a tracker, no
            # Kalman filter) and has no ephemeris, no torque filter and no zero-speed logic
            # its flight software has one mode (no Sun acquisition, ACE Safehold, thruster
            # modes or failure detection)
            "fsw": {"attitude_option": "star_tracker", "wheel_bias": None, "ephemeris": None,
                    "sun_acquisition": None, "safehold": None, "thruster_control": None, "fdc": None,
                    "torque_filters": {bank: {"x": None, "y": None, "z": None} for bank in ("inertial", "science")}}},
        "initial": {"mode": "INERTIAL", "q_BN": quat_from_mrp(np.array([0.1, 0.2, -0.3])).tolist(),
                    "omega_BN_B_rad_s": omega0, "h_wheels_Nms": h0, "target_q_RN": [1.0, 0.0, 0.0, 0.0]},
        # the reference has no environment: no disturbance torque, point-mass gravity
        "environment": {"srp": False, "gravity_gradient": False, "engine_torque": False, "zonal": False,
                        "tesseral": False, "third_body": False},
        "output": {"period_s": 10.0},
    }


def sdo_inertial() -> dict:
    """SDO at its flight rates (0.05 s truth, 0.2 s control): the 10 deg slew
    scenario, run for an hour, recorded at 1 Hz."""
    data = yaml.safe_load(SLEW_SCENARIO.read_text())
    data.update(name="sdo-inertial", duration_s=3600.0, expect=[])
    return data


def sdo_truth() -> dict:
    """The full SDO truth model (orbit with J2-J4, C22/S22, Sun and Moon; SRP,
    gravity gradient; propellant; every sensor) at flight rates under the
    Inertial hold, one hour, recorded at 1 Hz."""
    data = yaml.safe_load(HOLD_SCENARIO.read_text())
    data.update(name="sdo-truth", duration_s=3600.0, expect=[])
    return data


def sdo_science() -> dict:
    """Science mode with the whole flight software (EKF on the IRU, both star
    trackers and the DSS; the on-board ephemeris task at 1 Hz; the guide
    telescope; torque filters; zero-speed logic) on the full truth model at
    flight rates, one hour, recorded at 1 Hz."""
    data = yaml.safe_load(SCIENCE_SCENARIO.read_text())
    data.update(name="sdo-science", duration_s=3600.0, expect=[], output={"period_s": 1.0})
    return data


def sdo_deltav() -> dict:
    """The 50-min main-engine burn of seed 001 Fig. 6 (sdo_deltav_main_engine):
    thrusters on-pulsing at 50 ms resolution (four RK4 steps per 0.2 s cycle),
    propellant draining, IRU-propagated attitude, recorded at 1 Hz."""
    data = yaml.safe_load(DELTAV_SCENARIO.read_text())
    data.update(name="sdo-deltav", expect=[])
    return data


BENCHMARKS = {"basilisk-mirror": basilisk_mirror, "sdo-inertial": sdo_inertial, "sdo-truth": sdo_truth,
              "sdo-science": sdo_science, "sdo-deltav": sdo_deltav}


def time_ours(data: dict) -> tuple[float, float, float]:
    """(sim s, wall s of the run loop alone, final attitude error deg)."""
    from sim.runner import Runner
    from sim.scenario import parse_scenario

    scenario, sc = parse_scenario(data, data["name"])
    runner = Runner(scenario, sc)
    start = time.perf_counter()
    result = runner.run()
    wall = time.perf_counter() - start
    return scenario.duration_s, wall, result.telemetry["att_err_arcsec"][-1] / 3600.0


def time_reference(python: str, script: Path, sim_s: float = 3600.0, dt: float = 0.1) -> dict:
    out = subprocess.run([python, str(script), f"{sim_s:g}", f"{dt:g}"], capture_output=True, text=True,
                         check=True).stdout.strip().splitlines()[-1]
    return dict(kv.split("=") for kv in out.split()[1:])


def _line(name: str, sim_s: float, wall: float, extra: str = "") -> str:
    return f"{name} sim_s={sim_s:g} wall_s={wall:.3f} realtime_ratio={sim_s / wall:.0f}{extra}"


def _startup(scenario: Path) -> None:
    """Cold start (empty numba cache) and warm start of `acs run`, as wall time of the whole process."""
    with tempfile.TemporaryDirectory() as cache, tempfile.TemporaryDirectory() as out:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        for label in ("cold", "warm"):
            start = time.perf_counter()
            subprocess.run([sys.executable, "-m", "server.cli", "run", str(scenario), "--out", out], env=env,
                           cwd=REPO, capture_output=True, check=False)
            print(f"startup-{label} scenario={scenario.name} wall_s={time.perf_counter() - start:.2f}")


def main(args) -> int:
    names = args.names or list(BENCHMARKS)
    unknown = [n for n in names if n not in BENCHMARKS]
    if unknown:
        print(f"error: unknown benchmark {', '.join(unknown)}; allowed: {', '.join(BENCHMARKS)}", file=sys.stderr)
        return 2
    if args.reference and not Path(args.reference_script).is_file():
        print(f"error: --reference-script {args.reference_script} not found", file=sys.stderr)
        return 2
    for name in names:
        data = BENCHMARKS[name]()
        time_ours(data)  # compile and warm up; cold start is measured by --startup
        ours, theirs = [], []
        for _ in range(max(1, args.repeat)):
            ours.append(time_ours(data))
            if args.reference and name == "basilisk-mirror":
                theirs.append(time_reference(args.reference, args.reference_script))
        sim_s, _, err_deg = ours[0]
        wall = statistics.median(o[1] for o in ours)
        print(_line(name, sim_s, wall, f" final_att_err_deg={err_deg:.2e}"), flush=True)
        if theirs:
            ref_wall = statistics.median(float(t["wall_s"]) for t in theirs)
            ref_sim = float(theirs[0]["sim_s"])
            print(_line("basilisk", ref_sim, ref_wall, f" final_att_err_deg={theirs[0]['final_att_err_deg']}"))
            ratio = (sim_s / wall) / (ref_sim / ref_wall)
            print(f"ratio {name}/basilisk realtime_ratio={ratio:.2f} (medians of {len(ours)} interleaved runs)")
    if args.startup:
        _startup(HOLD_SCENARIO)
    return 0
