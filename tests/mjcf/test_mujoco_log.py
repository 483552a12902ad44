"""MuJoCo's warnings go to the 'mujoco' logger, from MuJoCo's threads too, and never into
MUJOCO_LOG.TXT in the current folder; a handler of the user's own is left alone."""

from __future__ import annotations

import logging
import os
import subprocess
import sys
from pathlib import Path

import mujoco
import numpy as np
from mujoco import batch

from mjcf.physics import Physics

REPO = Path(__file__).resolve().parents[2]
MOTOR = """
<mujoco>
  <worldbody><body><joint name="hinge"/><geom size="0.1"/></body></worldbody>
  <actuator><motor joint="hinge"/></actuator>
</mujoco>
"""
UNSTABLE = (
    "MuJoCo warning: Nan, Inf or huge value in CTRL at ACTUATOR 0. The simulation is unstable."
)


def test_a_warning_is_logged_and_no_log_file_is_written(tmp_path, monkeypatch, caplog):
    monkeypatch.chdir(tmp_path)
    physics = Physics.from_xml_string(MOTOR)
    physics.data.ctrl[0] = np.nan
    with caplog.at_level(logging.WARNING, logger="mujoco"):
        physics.step()
    (record,) = caplog.records
    assert record.name == "mujoco" and record.levelno == logging.WARNING
    assert record.getMessage().startswith(UNSTABLE)
    assert list(tmp_path.iterdir()) == []


def test_warnings_from_mujoco_s_threads_are_logged_too(tmp_path, monkeypatch, caplog):
    monkeypatch.chdir(tmp_path)
    simulations = batch.Batch(mujoco.MjModel.from_xml_string(MOTOR), nsim=6, nthread=2)
    simulations.bind("ctrl")[:] = np.nan
    with caplog.at_level(logging.WARNING, logger="mujoco"):
        simulations.step()
    assert len(caplog.records) == 6  # one per simulation, whichever thread ran it
    assert all(r.getMessage().startswith(UNSTABLE) for r in caplog.records)
    assert list(tmp_path.iterdir()) == []


def test_a_handler_of_the_user_s_own_is_kept(tmp_path):
    code = (
        "import mujoco\n"
        "heard = []\n"
        "mujoco.set_mju_user_warning(heard.append)\n"
        "import mjcf\n"
        f"physics = mjcf.Physics.from_xml_string({MOTOR!r})\n"
        "physics.data.ctrl[0] = float('nan')\n"
        "physics.step()\n"
        "print(len(heard), mujoco.get_mju_user_warning() == heard.append)\n"
    )
    env = {
        **os.environ,
        "PYTHONPATH": os.pathsep.join([str(REPO), os.environ.get("PYTHONPATH", "")]),
    }
    done = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=120, check=True)  # fmt: skip
    assert done.stdout.split() == ["1", "True"]
    assert done.stderr == "" and list(tmp_path.iterdir()) == []
