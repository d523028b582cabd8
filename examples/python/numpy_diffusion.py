"""Diffusion as a batched Python controller: controllers/diffusion/diffusion.cpp's rule, written
once over numpy arrays for all the robots of a controller configuration.

An experiment file runs it with
    <python_batch_controller id="pdc">
      <actuators><differential_steering/></actuators>
      <sensors><proximity/></sensors>
      <params module="numpy_diffusion" class="Diffusion" alpha="7.5" delta="0.1" velocity="0.05"/>
    </python_batch_controller>
(docs/python.md, "Batched controllers"): each robot drives straight while the mean of its
proximity readings, as vectors, points within +-alpha of its heading and is shorter than delta, or
points behind it; otherwise it turns on the spot away from the side the obstacle is on."""

import numpy as np


class Diffusion:
    def __init__(self, params):
        # <params>, typed from their text; the same defaults as the C++ controller.
        self.alpha = np.radians(params.get("alpha", 7.5))
        self.delta = float(params.get("delta", 0.1))
        self.velocity = float(params.get("velocity", 0.05))
        self._angles = None

    def step(self, readings):
        values = readings["proximity"]             # N x 24, one row per robot
        angles = readings["proximity_angles"]      # N x 24 (rad), the same array while the robots are
        if angles is not self._angles:
            self._angles = angles
            if (angles == angles[0]).all():        # one ring for all: a matrix-vector product
                self._cos, self._sin = np.cos(angles[0]), np.sin(angles[0])
            else:
                self._cos, self._sin = np.cos(angles), np.sin(angles)
        k = values.shape[1]
        if self._cos.ndim == 1:
            x, y = values @ self._cos / k, values @ self._sin / k
        else:
            x, y = (values * self._cos).sum(1) / k, (values * self._sin).sum(1) / k
        angle = np.arctan2(y, x)
        clear_ahead = (np.abs(angle) <= self.alpha) & (np.hypot(x, y) < self.delta)
        straight = clear_ahead | (np.abs(angle) > np.pi / 2)
        v = self.velocity
        # Obstacle on the left (angle > 0): turn right (v, -v); on the right: turn left.
        left = np.where(straight | (angle > 0), v, -v)
        right = np.where(straight | (angle <= 0), v, -v)
        return {"differential_steering": (left, right)}
