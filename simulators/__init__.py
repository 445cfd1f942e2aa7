"""Pusher-slider simulators for comcore (needs ``pip install comcore[sim]``).

A quasi-static simulation of a flat object pushed by a round pusher on a flat,
uniform floor with distributed Coulomb friction, seen by a top-down camera. The
default engine solves the quasi-static pusher-slider problem exactly on the limit
surface of the support; a pymunk rigid-body engine is an option
(``EngineSettings(engine="pymunk")``), less accurate at affordable solver
settings. :class:`MujocoRobot` plays the robot and its camera in MuJoCo
(``pip install comcore[mujoco]``; mujoco is imported only when one is built).
Objects come from vertex arrays, from SVG/DXF outlines or from meshes
(trimesh), or from the 20-object benchmark set (``load_object("Obj7")``).
The physics model and its measured parameters are in ``docs/results/simulators.md``.

Examples
--------
>>> import comcore, simulators
>>> sim = simulators.random_simulator("Obj7", friction="low", rng=0)
>>> actions = comcore.sample_pushes(sim.mask, 3, cone=0.3, rng=0)
>>> sim.push_motions(actions).shape
(3, 3)
"""

from ._mass import MassDistribution, tilt_to_com
from ._objects import BENCHMARK_AREAS_CM2, BENCHMARK_OBJECTS, load_object
from ._pushes import action_from_world, normal_pushes_through_com
from ._random import FRICTION_CLASSES, MASS_STYLES, random_com, random_simulator
from ._robot import DEFAULT_CAMERA_MARGIN, DEFAULT_PUSHER_SPEED, RobotPush, SimulatedRobot
from ._settings import ENGINES, EngineSettings
from ._shapes import ObjectShape, check_polygon, load_shape
from ._simulator import DEFAULT_PUSHER_RADIUS, PushResult, PushSimulator
from .mujoco._camera import CameraSettings, homography_table_to_image, warp_to_grid
from .mujoco._robot import CellFrame, MujocoPush, MujocoRobot
from .mujoco._scene import MujocoSettings

# isort: split
# Draws the simulator accepts, and a robot's errors (noisy masks, pusher paths, the camera).
from ._pushes import AcceptedPushes, sample_accepted_pushes
from ._random import accepted_random_simulator
from ._robot import camera_frame_margin, noisy_mask, perturb_actions, retreat_starts

__all__ = [
    "BENCHMARK_AREAS_CM2",
    "BENCHMARK_OBJECTS",
    "DEFAULT_CAMERA_MARGIN",
    "DEFAULT_PUSHER_RADIUS",
    "DEFAULT_PUSHER_SPEED",
    "ENGINES",
    "FRICTION_CLASSES",
    "MASS_STYLES",
    "CameraSettings",
    "CellFrame",
    "EngineSettings",
    "MassDistribution",
    "MujocoPush",
    "MujocoRobot",
    "MujocoSettings",
    "ObjectShape",
    "PushResult",
    "PushSimulator",
    "RobotPush",
    "SimulatedRobot",
    "action_from_world",
    "check_polygon",
    "homography_table_to_image",
    "load_object",
    "load_shape",
    "normal_pushes_through_com",
    "random_com",
    "random_simulator",
    "tilt_to_com",
    "warp_to_grid",
]
__all__ += [
    "AcceptedPushes",
    "accepted_random_simulator",
    "camera_frame_margin",
    "noisy_mask",
    "perturb_actions",
    "retreat_starts",
    "sample_accepted_pushes",
]
