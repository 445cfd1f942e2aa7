"""MuJoCo as the robot: a scene of the object and a pusher, rendered by a camera.

``_scene`` builds the MJCF scene (needs ``pip install comcore[mujoco]``; mujoco is
imported only when a scene is built), ``_camera`` the camera and the table
homography, ``_robot`` the :class:`~simulators.MujocoRobot` that pushes and returns
frames. May import the rest of :mod:`simulators` and :mod:`comcore`'s public names.
"""
