"""The compiled Kalman steps (``_ckalman.c``; see :mod:`laserpeople.tracking.kalman`)."""

import numpy as np
from numpy.typing import NDArray

SOURCE_HASH: str

def predict(
    means: list[NDArray[np.float64]] | NDArray[np.float64],
    covs: list[NDArray[np.float64]] | NDArray[np.float64],
    dts: list[float],
    cubes: list[float],
    decays: list[float] | None,
    accel_psd: float,
    tau: float,
    pm: NDArray[np.float64],
    pc: NDArray[np.float64],
    cm: NDArray[np.float64] | None,
    cc: NDArray[np.float64] | None,
) -> None: ...
def score(
    pm: NDArray[np.float64],
    pc: NDArray[np.float64],
    z: NDArray[np.float64],
    r: NDArray[np.float64],
    gate: float,
    max_gate_sq: float,
    log_2pi: float,
    gated: NDArray[np.bool_] | None,
    partial: NDArray[np.float64],
    det: NDArray[np.float64],
    d2: NDArray[np.float64] | None,
) -> None: ...
def update(
    pm: NDArray[np.float64],
    pc: NDArray[np.float64],
    rows: list[int],
    z: NDArray[np.float64],
    r: NDArray[np.float64],
    js: list[int],
    means: NDArray[np.float64],
    covs: NDArray[np.float64],
) -> None: ...
