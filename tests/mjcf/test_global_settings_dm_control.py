"""Global settings of composed models read as dm_control's own `mjcf` reads them: the
same scenarios (attach, write after the attach, detach, copy) run on dm_control's
published wheel and on ours, each in a process of its own (the wheel is fetched at test
time; the tests skip with the reason where the package index cannot be reached)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
import zipfile

import pytest

import mjcf
from mjcf.compose.settings import OWN_COMPILER_SETTINGS
from tests import dm_control_wheel
from tests.conftest import GYM_ASSETS

# Run with dm_control's mjcf and with ours: each scenario returns what it reads.
_SCENARIOS = textwrap.dedent(
    """
    import mujoco
    import numpy as np

    OWN = set(OWN_COMPILER_SETTINGS)
    CHILDREN = {"option": ["flag"], "compiler": ["lengthrange"], "size": [], "statistic": [],
                "visual": ["global", "quality", "headlight", "map", "scale", "rgba"]}

    def text(value):
        if isinstance(value, str):
            return value
        return [float(x) for x in np.atleast_1d(np.asarray(value, dtype=float))]

    def values(model):
        found = {}
        for tag, children in CHILDREN.items():
            section = getattr(model, tag)
            for path, element in [(tag, section)] + [
                (tag + "." + child, getattr(section, child)) for child in children
            ]:
                got = {name: text(value) for name, value in element.get_attributes().items()
                       if value is not None and not (tag == "compiler" and name in OWN)}
                if got:
                    found[path] = got
        return found

    def compiled(model):
        # What MuJoCo compiles from the model's XML: its settings, and body masses.
        m = mujoco.MjModel.from_xml_string(model.to_xml_string(), model.get_assets())
        settings = {name: text(getattr(m.opt, name)) for name in (
            "timestep", "integrator", "iterations", "noslip_iterations", "cone", "solver",
            "gravity", "disableflags", "noslip_tolerance", "tolerance")}
        settings.update(ambient=text(m.vis.headlight.ambient), znear=text(m.vis.map.znear),
                        zfar=text(m.vis.map.zfar), nkey=m.nkey, nconmax=m.nconmax,
                        narena=m.narena)
        names = [mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, i) for i in range(m.nbody)]
        # dm_control's attachment frames are bodies ('ant/'), ours frames: left out
        settings["masses"] = {n: float(mass) for n, mass in zip(names, m.body_mass)
                              if n and not n.endswith("/")}
        return settings

    def robot(name):
        model = mjcf.from_path(GYM + name + ".xml")
        for setting in ("angle", "inertiafromgeom", "coordinate", "settotalmass"):
            setattr(model.compiler, setting, None)  # each model's own here: not compared
        return model

    def base_arena():
        arena = mjcf.RootElement(model="arena")
        arena.compiler.set_attributes(boundmass=1e-5, boundinertia=1e-11)
        arena.option.set_attributes(cone="elliptic", noslip_iterations=5,
                                    noslip_tolerance=0, timestep=0.002)
        arena.visual.map.znear = 0.01
        arena.visual.headlight.set_attributes(diffuse=[0.6] * 3, ambient=[0.3] * 3,
                                              specular=[0, 0, 0])
        return arena

    def attempt(call):
        try:
            call()
        except ValueError as error:
            return "ValueError: " + str(error).split("`")[1]
        return "attached"

    def robots_on_the_arena():
        arena, ant, humanoid = base_arena(), robot("ant"), robot("humanoid")
        arena.attach(ant)
        arena.attach(humanoid)
        return {"arena": values(arena), "ant": values(ant), "humanoid": values(humanoid)}

    def writes_after_the_attach():
        arena, hopper, walker = base_arena(), robot("hopper"), robot("walker2d")
        arena.attach(hopper)
        arena.attach(walker)
        hopper.compiler.boundmass = 0
        walker.visual.headlight.ambient = [0.1, 0.2, 0.3]
        arena.option.timestep = 0.01
        walker.option.flag.gravity = "disable"
        hopper.size.nconmax = 7
        return {"arena": values(arena), "hopper": values(hopper), "walker": values(walker),
                "compiled": compiled(arena)}

    def every_rule():
        parent, child = mjcf.RootElement(model="p"), mjcf.RootElement(model="c")
        parent.option.set_attributes(timestep=0.004, tolerance=1e-7, ls_tolerance=0.001,
                                     noslip_tolerance=1e-5, ccd_tolerance=1e-7, iterations=20,
                                     ls_iterations=80, noslip_iterations=2, ccd_iterations=10,
                                     sdf_iterations=30, sdf_initpoints=10)
        child.option.set_attributes(timestep=0.001, tolerance=1e-9, ls_tolerance=0.1,
                                    noslip_tolerance=1e-7, ccd_tolerance=1e-5, iterations=50,
                                    ls_iterations=20, noslip_iterations=4, ccd_iterations=50,
                                    sdf_iterations=5, sdf_initpoints=60)
        parent.size.set_attributes(memory="10000", nconmax=123)
        child.size.set_attributes(memory="1M", nconmax=345)
        parent.visual.map.set_attributes(znear=0.02, zfar=40)
        child.visual.map.set_attributes(znear=0.01, zfar=80)
        other = mjcf.RootElement(model="o")
        other.size.set_attributes(memory="2M")
        parent.attach(child)
        parent.attach(other)
        return {"parent": values(parent), "child": values(child), "compiled": compiled(parent)}

    def conflicts():
        arena, pusher, reacher = base_arena(), robot("pusher"), robot("reacher")
        arena.attach(pusher)
        outcome = attempt(lambda: arena.attach(reacher))
        return {"outcome": outcome, "arena": values(arena), "reacher": values(reacher)}

    def detach():
        arena, ant = base_arena(), robot("ant")
        arena.attach(ant)
        ant.detach()
        ant.option.timestep = 0.03
        return {"arena": values(arena), "ant": values(ant), "compiled": compiled(arena)}

    def nested_top_down():
        arena, base, arm = base_arena(), mjcf.RootElement(model="base"), robot("reacher")
        mount = base.worldbody.add("site", name="mount")
        arena.attach(base)
        mount.attach(arm)
        arm.option.timestep = 0.0005
        return {"arena": values(arena), "base": values(base), "arm": values(arm),
                "compiled": compiled(arena)}

    RESULTS = {name: scenario() for name, scenario in [
        ("robots_on_the_arena", robots_on_the_arena),
        ("writes_after_the_attach", writes_after_the_attach),
        ("every_rule", every_rule), ("conflicts", conflicts), ("detach", detach),
        ("nested_top_down", nested_top_down)]}
    """
)


def _run_scenarios(mjcf_module: object) -> dict:
    namespace = {
        "mjcf": mjcf_module,
        "GYM": f"{GYM_ASSETS}/",
        "OWN_COMPILER_SETTINGS": sorted(OWN_COMPILER_SETTINGS),
    }
    exec(_SCENARIOS, namespace)
    return json.loads(json.dumps(namespace["RESULTS"]))


@pytest.fixture(scope="module")
def dm_control_results(tmp_path_factory: pytest.TempPathFactory) -> dict:
    """The scenarios run by dm_control's own mjcf (unchanged, from its wheel), in a
    process of its own: it shares the name `dm_control` with the rewritten tree."""
    pytest.importorskip("absl")
    pytest.importorskip("dm_env")  # dm_control.mjcf imports dm_control.rl
    root = tmp_path_factory.mktemp("dm_control_mjcf")
    needed = ("dm_control/__init__.py", "dm_control/_render/", "dm_control/mjcf/",
              "dm_control/mujoco/", "dm_control/rl/", "dm_control/utils/")  # fmt: skip
    with zipfile.ZipFile(dm_control_wheel.wheel()) as archive:
        for name in archive.namelist():
            keep = name.endswith(".py") or name == "dm_control/mjcf/schema.xml"
            if keep and name.startswith(needed) and "/testing/" not in name:
                archive.extract(name, root)
    script = (
        "import json\nfrom dm_control import mjcf\n"
        f"GYM = {f'{GYM_ASSETS}/'!r}\nOWN_COMPILER_SETTINGS = {sorted(OWN_COMPILER_SETTINGS)!r}\n"
        + _SCENARIOS
        + "\nprint(json.dumps(RESULTS))\n"
    )
    environment = {**os.environ, "PYTHONPATH": str(root), "MUJOCO_GL": "disable"}
    done = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, env=environment, timeout=300
    )
    assert done.returncode == 0, done.stderr[-3000:]
    return json.loads(done.stdout.strip().splitlines()[-1])


@pytest.mark.parametrize(
    "scenario",
    ["robots_on_the_arena", "writes_after_the_attach", "every_rule", "conflicts", "detach",
     "nested_top_down"],
)  # fmt: skip
def test_settings_read_as_dm_control_s_own_mjcf_reads_them(dm_control_results, scenario) -> None:
    ours = _run_scenarios(mjcf)[scenario]
    assert ours == dm_control_results[scenario]
