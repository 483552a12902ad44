"""The robot files shipped with the package, laid out as in a MuJoCo Menagerie clone.

    from entities import menagerie, robots
    menagerie.ROOT / 'universal_robots_ur5e' / 'ur5e.xml'    # a real file, for any loader
    robots.from_menagerie('robotiq_2f85')                    # found here (see robots)

`universal_robots_ur5e` (UR5e arm, BSD-3-Clause, ROS Industrial Consortium) and
`robotiq_2f85` (Robotiq 2F-85 gripper, BSD-2-Clause, ROS-Industrial) are MuJoCo Menagerie's
files with their LICENSE files; `composer/ArmPushBox-v0` uses them, so it works on any
install with no download. The 2F-85 is unchanged; the UR5e's OBJ meshes were converted to
MuJoCo's binary MSH format by `entities.menagerie.convert`, which compiles to the identical
MjModel (31 MB of text -> 10 MB). README.md here lists the originals' SHA-256 sums.
"""

from pathlib import Path

ROOT = Path(__file__).resolve().parent
ROBOTS = ("robotiq_2f85", "universal_robots_ur5e")

__all__ = ["ROBOTS", "ROOT"]
