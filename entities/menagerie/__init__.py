"""The robot files shipped with the package, laid out as in a MuJoCo Menagerie clone.

    from entities import menagerie, robots
    menagerie.ROOT / 'universal_robots_ur5e' / 'ur5e.xml'    # a real file, for any loader
    robots.from_menagerie('robotiq_2f85')                    # found here (see robots)

The UR5e arm and the Robotiq 2F-85 gripper are MuJoCo Menagerie's files under their own
LICENSE files, so `composer/ArmPushBox-v0` works with no download. The UR5e's meshes are
MSH files that compile to the identical MjModel (`entities.menagerie.convert`); README.md
here gives the licenses, what changed and the originals' SHA-256 sums.
"""

from pathlib import Path

ROOT = Path(__file__).resolve().parent
ROBOTS = ("robotiq_2f85", "universal_robots_ur5e")

__all__ = ["ROBOTS", "ROOT"]
