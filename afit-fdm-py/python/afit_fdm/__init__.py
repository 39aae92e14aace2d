"""afit_fdm: the flight models of the 2021 AFIT thesis from Python.

* :class:`Flight`: one aircraft of either model (Palmer's Cessna 172, point
  mass, RK4, float64; Bourg's 6-DoF aircraft, Euler, float32), flown frame by
  frame exactly as ``sim-cli`` flies it (the same bits).
* :meth:`Flight.record_to`, :func:`replay`: recordings in ``sim-cli``'s
  format (``--record``, ``sim-cli replay``), flown again to the same bits.
* :meth:`Flight.acmi_to`, :meth:`Flight.csv_to`, :meth:`Flight.dis_to`:
  ``sim-cli``'s ``--acmi``, ``--csv`` and ``--dis`` outputs, the same bytes.
* :class:`Fleet`: many aircraft of one model stepped by the SIMD fleet
  kernels, with the state as read-only NumPy columns.
* :class:`Study`, :func:`study`: Monte Carlo studies (the study files of
  ``sim-cli study``), their per-run table as NumPy columns and their summary;
  :func:`ray_study` spreads one over a Ray cluster (Ray imported only then).
* :mod:`afit_fdm.gym`: Gymnasium environments (single and vector), registered
  as ``afit_fdm/...`` ids when Gymnasium is installed.

The API reference is the type stub ``_afit_fdm.pyi`` next to this file (your
editor shows it) and the README's Python section.
"""

from __future__ import annotations

import enum

from ._afit_fdm import (
    MAX_FPS,
    MODELS,
    Fleet,
    Flight,
    RecordingCutError,
    RecordingError,
    Replay,
    ReplayDivergedError,
    __version__,
    replay,
)
from .distributed import ShardDone, ray_study
from .study import STATUS_CODES, RunTable, Study, study

__all__ = [
    "MAX_FPS",
    "MODELS",
    "STATUS_CODES",
    "Fleet",
    "Flight",
    "RecordingCutError",
    "RecordingError",
    "Replay",
    "ReplayDivergedError",
    "RunTable",
    "ShardDone",
    "Status",
    "Study",
    "__version__",
    "ray_study",
    "replay",
    "study",
]


class Status(enum.IntEnum):
    """Flight status codes, as :attr:`Fleet.status` holds them and
    :attr:`Flight.status_code` returns them (``sim-cli``'s CSV ``status``
    column uses the same numbers)."""

    ON_GROUND = 0
    """On the ground, not flown since the start."""
    AIRBORNE = 1
    """Above the ground plane."""
    LANDED_SAFE = 2
    """Touched down slower than 2 m/s vertically."""
    LANDED_ROUGH = 3
    """Touched down at 2 to 5 m/s vertically."""
    CRASHED = 4
    """Touched down at 5 m/s or faster (final: the aircraft stays at rest)."""
    DIVERGED = 5
    """The model's step gave a non-finite state (final: the last finite state is kept)."""


def _register() -> None:
    try:
        from . import gym as _gym
    except ImportError:  # Gymnasium not installed: the environments are optional.
        return
    _gym.register_envs()


_register()
