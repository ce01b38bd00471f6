"""Every shipped scenario is a test: it runs and all its expectations hold."""
from pathlib import Path

import pytest

from sim.runner import Runner
from sim.scenario import load_scenario

SCENARIOS = sorted((Path(__file__).parent.parent / "scenarios").glob("*.yaml"))


def test_scenarios_exist():
    names = {p.stem for p in SCENARIOS}
    assert {"sdo_inertial_hold", "sdo_inertial_slew"} <= names


@pytest.mark.parametrize("path", SCENARIOS, ids=lambda p: p.stem)
def test_scenario_expectations_hold(path):
    scenario, sc = load_scenario(path)
    assert scenario.expect, f"{path.name} has no expectations, so it tests nothing"
    result = Runner(scenario, sc).run()
    failed = [f"{e.description}: {e.measured}" for e in result.expectations if not e.ok]
    assert not failed, "\n".join(failed)
