"""Bad scenario files: one clear message naming the file, the field path, what
was expected and what was found; `acs run BAD.yaml` exits 2 with that message
on stderr (prefixed "error:"), no Python traceback, and no output written.

Every case starts from the valid scenarios/sdo_inertial_slew.yaml and breaks
exactly one thing, so exactly one problem (one line) must be reported. The
expected fragments come from the requirements, not from the code: the field
path the user wrote, the bad value they wrote, and what would have been right
(the allowed names where there is a closed list).
"""
import os
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from sim.scenario import ScenarioError, load_scenario

REPO = Path(__file__).resolve().parent.parent
BASE_FILE = REPO / "scenarios" / "sdo_inertial_slew.yaml"
ACS = Path(sys.executable).parent / "acs"

# Closed lists the messages must offer (from the spacecraft files, the command
# schema in the issue, and the always-present telemetry columns).
COMMAND_TYPES = ("set_target_quaternion", "reset_integrator")
SOME_TELEMETRY_FIELDS = ("t_s", "mode", "q_BN_w", "omega_BN_B_x_rad_s", "h_wheel_4_Nms",
                         "h_total_N_z_Nms", "att_err_arcsec")


def base() -> dict:
    data = yaml.safe_load(BASE_FILE.read_text())
    # Pin the parts the cases below refer to (the shipped file may be retuned).
    data.update(spacecraft="sdo", duration_s=1500, output={"period_s": 1.0},
                expect=[{"field": "att_err_arcsec", "from_s": 1200, "below": 60}])
    data["commands"] = [{"t_s": 60, "type": "set_target_quaternion", "q_RN": data["commands"][0]["q_RN"]}]
    return data


def _set(path: str, value):
    """A mutation that sets a dotted path (list indices as numbers)."""
    def mutate(d):
        *head, last = path.split(".")
        node = d
        for k in head:
            node = node[int(k)] if isinstance(node, list) else node.setdefault(k, {})
        if isinstance(node, list):
            node[int(last)] = value
        else:
            node[last] = value
        return d
    return mutate


# id -> (mutation of the valid dict, field path that must lead the message,
#        fragments that must all appear in the message)
CASES = {
    "unknown_top_level_field": (_set("colour", "blue"), "colour",
                                ["unknown field 'colour'", "allowed: name, description, spacecraft"]),
    "unknown_command_field": (_set("commands.0.speed_deg_s", 3), "commands.0.speed_deg_s",
                              ["unknown field 'speed_deg_s'", "allowed: t_s, type, q_RN"]),
    "wrong_type_duration": (_set("duration_s", "long"), "duration_s", ["number", "'long'"]),
    "unknown_spacecraft": (_set("spacecraft", "hubble2"), "spacecraft", ["hubble2", "sdo"]),
    "command_after_end": (_set("commands.0.t_s", 2000), "commands.0.t_s", ["2000", "1500", "duration_s"]),
    "negative_duration": (_set("duration_s", -5), "duration_s", ["greater than 0", "-5"]),
    "zero_duration": (_set("duration_s", 0), "duration_s", ["greater than 0", "found 0"]),
    "non_unit_initial_q_BN": (_set("initial.q_BN", [1, 1, 0, 0]), "initial.q_BN",
                              ["unit quaternion", "1.414213"]),
    "non_unit_command_q_RN": (_set("commands.0.q_RN", [0.5, 0, 0, 0]), "commands.0.q_RN",
                              ["unit quaternion", "0.5"]),
    "unknown_command_type": (_set("commands.0.type", "self_destruct"), "commands.0",
                             ["self_destruct", *COMMAND_TYPES]),
    "unknown_output_field": (_set("output.fields", ["att_err_arcsec", "warp_factor"]), "output.fields.1",
                             ["warp_factor", *SOME_TELEMETRY_FIELDS]),
    "unknown_expectation_field": (_set("expect.0.field", "warp_factor"), "expect.0.field",
                                  ["warp_factor", *SOME_TELEMETRY_FIELDS]),
    "wrong_wheel_count": (_set("initial.h_wheels_Nms", [1.0, 2.0, 3.0]), "initial.h_wheels_Nms",
                          ["4", "found 3"]),
    "period_not_multiple_of_cycle": (_set("output.period_s", 0.3), "output.period_s", ["0.2", "0.3"]),
    "bad_override": (_set("overrides", {"wheels": {"h_max_Nms": -1}}), "overrides.wheels.h_max_Nms",
                     ["greater than 0", "-1"]),
    "expectation_both_below_and_above": (_set("expect.0", {"field": "att_err_arcsec", "below": 60, "above": 1}),
                                         "expect.0", ["below", "above"]),
    "expectation_unknown_key": (_set("expect.0.beneath", 5), "expect.0.beneath",
                                ["unknown field 'beneath'", "below, above"]),
}


def write(tmp_path: Path, data, name: str = "bad.yaml") -> Path:
    p = tmp_path / name
    p.write_text(data if isinstance(data, str) else yaml.safe_dump(data, sort_keys=False))
    return p


def load_error(path: Path) -> str:
    with pytest.raises(ScenarioError) as info:
        load_scenario(path)
    return str(info.value)


def test_base_scenario_is_valid(tmp_path):
    """The starting point loads, also after a YAML round trip through tmp_path."""
    s, sc = load_scenario(write(tmp_path, base()))
    assert s.duration_s == 1500 and sc.n_wheels == 4


@pytest.mark.parametrize("case", sorted(CASES), ids=sorted(CASES))
def test_one_clear_message(tmp_path, case):
    mutate, where, fragments = CASES[case]
    path = write(tmp_path, mutate(base()), f"{case}.yaml")
    msg = load_error(path)
    lines = msg.splitlines()
    assert len(lines) == 1, f"one thing broken, one message expected; got:\n{msg}"
    # file name first, then the field path the user wrote
    assert msg.startswith(f"{path}: "), msg
    after_file = msg[len(f"{path}: "):]
    assert after_file.startswith(f"{where}"), f"field path {where!r} expected first: {msg}"
    for frag in fragments:
        assert frag in msg, f"{frag!r} missing from: {msg}"


def test_override_path_is_prefixed(tmp_path):
    """An override is reported where the user wrote it, under overrides., not as
    a path inside the spacecraft file."""
    path = write(tmp_path, _set("overrides", {"wheels": {"h_max_Nms": -1}})(base()))
    after_file = load_error(path).removeprefix(f"{path}: ")
    assert after_file.startswith("overrides.wheels.h_max_Nms:"), after_file


def test_invalid_yaml_gives_line_and_column(tmp_path):
    text = yaml.safe_dump(base(), sort_keys=False)
    lines = text.splitlines()
    i = next(n for n, line in enumerate(lines) if line.startswith("duration_s:"))
    lines[i] = "duration_s: 300: 5"          # a second ':' in a plain scalar
    path = write(tmp_path, "\n".join(lines) + "\n")
    msg = load_error(path)
    line_no, col_no = i + 1, lines[i].index(":", lines[i].index(":") + 1) + 1
    assert len(msg.splitlines()) == 1, msg
    assert msg.startswith(f"{path}:{line_no}:{col_no}"), f"expected {path}:{line_no}:{col_no} in: {msg}"
    assert "YAML" in msg


def test_missing_file(tmp_path):
    path = tmp_path / "does_not_exist.yaml"
    msg = load_error(path)
    assert len(msg.splitlines()) == 1, msg
    assert msg.startswith(str(path)), msg
    assert "No such file" in msg or "not found" in msg.lower() or "cannot read" in msg, msg


@pytest.mark.parametrize("text, found", [("- a\n- b\n", "list"), ("just a string\n", "str"), ("", "empty")],
                         ids=["list", "scalar", "empty"])
def test_top_level_not_a_mapping(tmp_path, text, found):
    path = write(tmp_path, text)
    msg = load_error(path)
    assert len(msg.splitlines()) == 1, msg
    assert msg.startswith(f"{path}: "), msg
    assert "mapping" in msg and found in msg, msg


# -- through the console command ----------------------------------------------

def _acs_run(scenario: Path, out: Path) -> subprocess.CompletedProcess:
    env = dict(os.environ, CI="1")
    return subprocess.run([str(ACS), "run", str(scenario), "--out", str(out)], capture_output=True, text=True,
                          timeout=60, env=env)


CLI_CASES = ["unknown_spacecraft", "unknown_command_type", "bad_override", "period_not_multiple_of_cycle"]


def _assert_bad_input(proc, path: Path, out: Path, *fragments: str):
    assert proc.returncode == 2, (proc.returncode, proc.stdout, proc.stderr)
    assert proc.stderr.startswith("error:"), proc.stderr
    assert "Traceback" not in proc.stderr and "Traceback" not in proc.stdout, proc.stderr
    assert str(path) in proc.stderr, proc.stderr
    for frag in fragments:
        assert frag in proc.stderr, (frag, proc.stderr)
    assert not out.exists() or not any(out.iterdir()), f"output written: {list(out.iterdir())}"


@pytest.mark.parametrize("case", CLI_CASES)
def test_cli_bad_scenario_exits_2(tmp_path, case):
    mutate, where, fragments = CASES[case]
    path = write(tmp_path, mutate(base()), f"{case}.yaml")
    out = tmp_path / "out"
    _assert_bad_input(_acs_run(path, out), path, out, where, *fragments)


def test_cli_invalid_yaml_exits_2(tmp_path):
    path = write(tmp_path, "name: x\nspacecraft: sdo\nduration_s: 300: 5\n")
    out = tmp_path / "out"
    _assert_bad_input(_acs_run(path, out), path, out, f"{path}:3:16")


def test_cli_missing_file_exits_2(tmp_path):
    path = tmp_path / "nowhere.yaml"
    out = tmp_path / "out"
    _assert_bad_input(_acs_run(path, out), path, out)
