"""`composer view`: MuJoCo's viewer on a task, in a real window on Xvfb (a virtual X
display whose screen is read back as a picture), and its one-line errors without one."""

from __future__ import annotations

import os
import select
import shutil
import struct
import subprocess
import sys
import time

import imageio.v3 as iio
import numpy as np
import pytest

from tests.cli.helpers import assert_one_line_error, composer, environment

XVFB = shutil.which("Xvfb")
needs_xvfb = pytest.mark.skipif(
    XVFB is None, reason="Xvfb is not installed (apt-get install xvfb; CI installs it)"
)


def read_xwd(path) -> np.ndarray:
    """The (height, width, 3) RGB picture in an XWD file of a 24-bit TrueColor screen, as
    Xvfb keeps its screen with -fbdir."""
    data = path.read_bytes()
    header = struct.unpack(">25I", data[:100])
    header_size, width, height = header[0], header[4], header[5]
    bytes_per_line, colormap_entries = header[12], header[19]
    offset = header_size + 12 * colormap_entries
    rows = np.frombuffer(data, np.uint8, height * bytes_per_line, offset)
    pixels = rows.reshape(height, bytes_per_line)[:, : 4 * width].reshape(height, width, 4)
    return pixels[..., 2::-1]  # BGRX in memory -> RGB


@pytest.fixture
def display(tmp_path):
    """A virtual display ':N' (Xvfb picks a free N) and the file its screen is kept in."""
    screen = tmp_path / "screen"
    screen.mkdir()
    read, write = os.pipe()
    process = subprocess.Popen(
        [XVFB, "-displayfd", str(write), "-screen", "0", "800x600x24", "-fbdir", str(screen),
         "-nolisten", "tcp", "-br"],
        pass_fds=(write,), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
    )  # fmt: skip
    os.close(write)
    try:
        ready, _, _ = select.select([read], [], [], 30)
        assert ready, "Xvfb did not start"
        number = os.read(read, 64).decode().strip()
        yield f":{number}", screen / "Xvfb_screen0"
    finally:
        os.close(read)
        process.terminate()
        process.wait(timeout=30)


@needs_xvfb
def test_view_shows_the_task_in_a_window_and_starts_the_next_episode(display, tmp_path):
    name, screen = display
    process = subprocess.Popen(
        [sys.executable, "-m", "composer", "view", "Reach", "--episodes", "2"],
        cwd=tmp_path, env=environment(DISPLAY=name), stdout=subprocess.PIPE,
        stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    shots = []
    deadline = time.monotonic() + 180  # two 3-second episodes at real-time pace, or slower
    try:
        while process.poll() is None and time.monotonic() < deadline:
            time.sleep(0.5)
            shots.append(read_xwd(screen))
        stdout, stderr = process.communicate(timeout=max(1.0, deadline - time.monotonic()))
    finally:
        if process.poll() is None:
            process.kill()
    assert process.returncode == 0, stderr
    ran = composer("run", "Reach", "--episodes", "2", cwd=tmp_path)  # the same seeds
    assert stdout.splitlines() == ran.stdout.splitlines()[:2]
    assert stdout.startswith("episode 1: return ") and "episode 2: return " in stdout
    colours = [len(np.unique(shot.reshape(-1, 3), axis=0)) for shot in shots]
    best = shots[int(np.argmax(colours))]
    iio.imwrite(tmp_path / "view.png", best)  # to look at when this fails
    assert max(colours) > 100, colours  # a rendered scene, not a blank (all black) screen
    window = best[np.any(best > 0, axis=2)]
    assert len(window) > 0.1 * 800 * 600  # a window of a tenth of the screen at least
    blue = (window[:, 2] > window[:, 0] + 40).mean()
    assert blue > 0.3  # Reach's floor and sky are blue


def test_view_without_a_display_says_so_in_one_line(tmp_path):
    env = {k: v for k, v in environment().items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    if not sys.platform.startswith("linux"):
        pytest.skip("the check for DISPLAY is Linux's")
    result = composer("view", "Reach", cwd=tmp_path, env=env)
    assert_one_line_error(result, "composer view needs a display and DISPLAY is not set")


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="X11 displays")
def test_view_on_a_display_that_cannot_be_reached_says_which(tmp_path):
    result = composer("view", "Reach", cwd=tmp_path, env=environment(DISPLAY=":4321"))
    assert_one_line_error(result, "cannot open a window on display :4321")


@needs_xvfb
def test_view_names_a_policy_that_does_not_exist(display, tmp_path):
    result = composer("view", "Reach", "--policy", "nothing", cwd=tmp_path,
                      env=environment(DISPLAY=display[0]))  # fmt: skip
    assert_one_line_error(result, "no policy at nothing")
