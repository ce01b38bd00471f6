"""Archive behaviour that a user meets: an archive from another schema version
is refused with a clear message, and asking for a field a run did not record
names what it did record."""
import sqlite3
import subprocess
import sys
from pathlib import Path

import pytest

from server.archive import SCHEMA_VERSION, Archive, ArchiveError

REPO = Path(__file__).parent.parent


def test_foreign_schema_is_refused_and_left_untouched(tmp_path):
    path = tmp_path / "archive.sqlite"
    db = sqlite3.connect(path)
    db.execute("CREATE TABLE telemetry (run_id, t_s, frame_json)")
    db.commit()
    db.close()
    before = path.read_bytes()
    with pytest.raises(ArchiveError) as err:
        Archive(path)
    assert f"schema version 0, this program writes version {SCHEMA_VERSION}" in str(err.value)
    assert path.read_bytes() == before


def test_cli_refuses_foreign_archive_with_exit_2(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    db = sqlite3.connect(out / "archive.sqlite")
    db.execute("CREATE TABLE x (a)")
    db.commit()
    db.close()
    proc = subprocess.run([sys.executable, "-m", "server.cli", "run", str(REPO / "scenarios/sdo_inertial_hold.yaml"),
                           "--out", str(out)], capture_output=True, text=True, cwd=REPO, env={"CI": "1", "PATH": ""})
    assert proc.returncode == 2
    assert proc.stderr.startswith("error:") and "schema version" in proc.stderr and "Traceback" not in proc.stderr
    assert not (out / "telemetry.csv").exists()


def test_unknown_field_names_the_recorded_ones(tmp_path):
    archive = Archive(tmp_path / "a.sqlite")

    class S:
        name, spacecraft, duration_s = "x", "sdo", 1.0
        from datetime import datetime, timezone
        epoch_utc = datetime(2026, 1, 1, tzinfo=timezone.utc)

        def model_dump_json(self):
            return "{}"

    rec = archive.start_run(S(), 0, ["t_s", "mode", "att_err_arcsec"])
    with pytest.raises(KeyError) as err:
        archive.telemetry(rec.run_id, ["wheel_speed_1_rpm"])
    assert "did not record wheel_speed_1_rpm" in str(err.value) and "att_err_arcsec" in str(err.value)
