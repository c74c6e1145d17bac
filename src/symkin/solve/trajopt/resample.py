"""The trajectory at a controller's rate: states, accelerations and feedforward torques on a
uniform time grid, read off the re-simulation (forward transcriptions: each interval integrated
from its node under its torque, so the samples are dynamically consistent to the reported
defect) or off the exact quadratics of the inverse-dynamics transcription."""

from __future__ import annotations

from typing import Any

import numpy as np

from symkin.solve.trajopt.accuracy import control_function, integrate_interval
from symkin.solve.trajopt.functions import RobotFunctions


def resampled(trajectory: Any, functions: RobotFunctions, rate: float) -> dict[str, np.ndarray]:
    """``{"t", "q", "dq", "ddq", "tau"}`` at ``rate`` samples per second from 0 to T (T
    included): ``t`` (m,), the others m x n.  ``tau`` is the feedforward torque and ``ddq`` the
    forward dynamics under it."""
    t = np.arange(0.0, trajectory.final_time, 1.0 / rate)
    t = np.append(t[t < trajectory.final_time - 1e-12], trajectory.final_time)
    n = functions.dof
    k = np.clip(np.searchsorted(trajectory.t, t, side="right") - 1, 0, len(trajectory.t) - 2)
    control = control_function(trajectory, functions)
    states = np.zeros((len(t), 2 * n))
    torques = np.zeros((len(t), n))
    for interval in np.unique(k):
        rows = np.flatnonzero(k == interval)
        s = t[rows] - trajectory.t[interval]
        start = np.concatenate([trajectory.q[interval], trajectory.dq[interval]])
        h = trajectory.t[interval + 1] - trajectory.t[interval]
        solution = integrate_interval(functions, control, interval, start, h)
        states[rows] = solution.sol(s).T
        torques[rows] = [control(interval, value) for value in s]
    q, dq = states[:, :n], states[:, n:]
    ddq = np.reshape(functions.numpy_forward_dynamics(q, dq, torques), q.shape)
    return {"t": t, "q": q, "dq": dq, "ddq": ddq, "tau": torques}
