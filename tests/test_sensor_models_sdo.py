"""The sensor sections of the spacecraft file (sim/spacecraft/sensor_models.py)
and their SDO values (the sensors section of sim/spacecraft/sdo.yaml): they validate, build every
kernel's parameters, cite their sources, and bad values fail with a message
that names the field and says what is allowed."""
import re

import numpy as np
import pytest
import yaml
from pydantic import ValidationError
from sdo_sensor_setup import DT, SUITE, YAML_PATH

from sim.spacecraft.sensor_models import (
    Css,
    Dss,
    GuideTelescopes,
    IruUnits,
    SensorSuite,
    covering_radius_deg,
)
from sim.truth.sensors import (
    css,
    dss,
    guide_telescope,
    iru_units,
    star_tracker_exclusion,
    tachometer,
)
from sim.truth.sensors.star_tracker import StarTrackerParams

RAW = yaml.safe_load(YAML_PATH.read_text())["sensors"]


def test_every_section_builds_its_kernel_parameters():
    st = StarTrackerParams(np.array([[1.0, 0, 0, 0]]), np.zeros((1, 3)))
    built = [
        iru_units.make_iru_units_params(**SUITE.iru_units.model_dump(exclude={"bias_deg_h"}), dt=DT),
        star_tracker_exclusion.make_star_tracker_exclusion_params(st, **SUITE.star_tracker_exclusion.model_dump()),
        css.make_css_params(**SUITE.css.model_dump()),
        dss.make_dss_params(**SUITE.dss.model_dump()),
        guide_telescope.make_guide_telescope_params(**SUITE.guide_telescopes.model_dump()),
        tachometer.make_tachometer_params(**SUITE.tachometers.model_dump(), dt=DT),
    ]
    assert [type(b).__name__ for b in built] == ["IruUnitsParams", "StarTrackerExclusionParams", "CssParams",
                                                 "DssParams", "GuideTelescopeParams", "TachometerParams"]
    # seed 001 "Hardware complement" figures reach the kernels in SI
    assert built[0].counter.lsb_rad == pytest.approx(0.5 * np.pi / 180 / 3600)
    assert built[1].sun_half_angle_rad == pytest.approx(np.radians(55.0))
    assert built[2].cos_fov == pytest.approx(np.cos(np.radians(85.0)))
    assert built[3].fov_half_width_rad == pytest.approx(np.radians(16.0))


def test_every_number_in_the_sdo_spacecraft_file_cites_a_source():
    # DESIGN.md: every number traceable to a seed section or marked as an assumption.
    # A number is covered by its own line's comment, or by a comment block above it
    # that holds until the next commented line or the next section.
    cites = re.compile(r"seed 00\d|assumption")
    uncited, block_cited = [], False
    for line in YAML_PATH.read_text().splitlines():
        code, _, comment = line.partition("#")
        if not code.strip():
            block_cited = block_cited or bool(cites.search(comment))
            continue
        if re.search(r"\d", code) and not (cites.search(comment) or block_cited):
            uncited.append(line)
        if comment or not code.startswith(" "):
            block_cited = False
    assert not uncited


def test_cube_diagonals_leave_no_direction_farther_than_54_7_deg():
    # the farthest direction from the eight cube diagonals is a face normal: acos(1/sqrt(3))
    diagonals = np.array([[a, b, c] for a in (1, -1) for b in (1, -1) for c in (1, -1)]) / np.sqrt(3)
    assert covering_radius_deg(diagonals) == pytest.approx(np.degrees(np.arccos(1 / np.sqrt(3))), abs=1e-9)
    assert covering_radius_deg(diagonals[:4]) == 180.0       # all on the +X side: the -X hemisphere unseen


def rejected(model, section: dict, **changes) -> str:
    with pytest.raises(ValidationError) as info:
        model.model_validate({**section, **changes})
    return str(info.value)


def test_iru_axes_must_survive_the_loss_of_any_unit():
    same_plane = [[1, 0, 0], [0, 1, 0]] * 3      # every unit senses X, Y: Z is never seen
    msg = rejected(IruUnits, RAW["iru_units"], channel_axes_B=same_plane)
    assert "channel_axes_B" in msg and "any two units sense all three body axes" in msg
    assert "channel_axes_B" in rejected(IruUnits, RAW["iru_units"], channel_axes_B=[[1, 0, 0]] * 5)


def test_css_sets_must_each_cover_the_sphere():
    one_side = [[0.6, 0.8, 0.0], [0.6, -0.8, 0.0], [0.6, 0.0, 0.8], [0.6, 0.0, -0.8]] * 2
    msg = rejected(Css, RAW["css"], boresights_backup_B=one_side)
    assert "boresights_backup_B" in msg and "4-pi" in msg
    assert "fov_half_angle_deg" in rejected(Css, RAW["css"], fov_half_angle_deg=120.0)
    msg = rejected(Css, RAW["css"], boresights_primary_B=[[1.0, 1.0, 1.0]] * 8)
    assert "boresights_primary_B" in msg and "unit vector" in msg


def test_dss_and_guide_telescope_limits():
    msg = rejected(Dss, RAW["dss"], inner_half_angle_deg=20.0)
    assert "inner_half_angle_deg" in msg and "fov_half_width_deg" in msg
    assert "lit_fraction_min" in rejected(Dss, RAW["dss"], lit_fraction_min=1.5)
    msg = rejected(GuideTelescopes, RAW["guide_telescopes"], fine_range_arcsec=1000.0)
    assert "fine_range_arcsec" in msg and "field of view" in msg
    assert "units" in rejected(GuideTelescopes, RAW["guide_telescopes"], units=RAW["guide_telescopes"]["units"][:3])


def test_unknown_fields_are_refused():
    msg = rejected(SensorSuite, RAW, dss={**RAW["dss"], "accuracy_arcmin": 1.0})
    assert "accuracy_arcmin" in msg and "Extra inputs are not permitted" in msg
