"""Forced response of a rotor in the stationary frame: unbalance, gravity, synchronous
response over spin speed (Bode), damped critical speeds.

Conventions (those of ROSS's ``run_unbalance_response``): a response or load at
frequency w is a complex amplitude X per coordinate with ``x(t) = Re(X e^{i w t})``,
amplitude |X| and phase arg X (rad). An unbalance of mass m (kg) at eccentricity e (m)
and angle phi (rad) at a station turns with the shaft (forward, from y towards z):
``F_y = m e Omega^2 cos(Omega t + phi)``, ``F_z = m e Omega^2 sin(Omega t + phi)``, i.e.
``F = m e Omega^2 e^{i phi} [1, -i]`` on (y, z). The synchronous response at spin speed
Omega solves the stationary-frame equations of :meth:`RotorModel.equations` directly in
the frequency domain,

    (K0 + Omega K1 + Omega^2 K2 + i w (C0 + Omega C1) - w^2 M) X = F,   w = Omega.

Orbit of a station: ``y + i z = R_f e^{i(w t + a)} + R_b e^{-i(w t - b)}`` with forward and
backward radii ``R_f = |Y + i Z| / 2``, ``R_b = |Y - i Z| / 2``: an ellipse of semi-major
axis R_f + R_b and semi-minor axis |R_f - R_b|, whirling forward when R_f > R_b.
"""

from __future__ import annotations

import json
from dataclasses import dataclass

import numpy as np
import xarray as xr

from ..errors import InputError
from .diagram import FORWARD, BACKWARD, _speeds, campbell
from .model import RotorModel

__all__ = ["Unbalance", "unbalance_load", "unbalance_response", "synchronous_response", "static_deflection",
           "critical_speeds"]

STANDARD_GRAVITY = 9.80665   # m/s^2
_CHUNK_ENTRIES = 4_000_000   # complex matrix entries per batched solve


@dataclass(frozen=True)
class Unbalance:
    """Unbalance mass (kg) at eccentricity (m) from the axis of station index ``station``,
    at angle ``phase`` (rad, from y towards z at t = 0); magnitude m e (kg m)."""

    station: int
    mass: float
    eccentricity: float
    phase: float = 0.0

    def __post_init__(self):
        if isinstance(self.station, bool) or not isinstance(self.station, (int, np.integer)) or self.station < 0:
            raise InputError(f"unbalance station must be a station index (an integer >= 0), got {self.station!r}")
        for name in ("mass", "eccentricity", "phase"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)) \
                    or not np.isfinite(value):
                raise InputError(f"unbalance {name} must be a finite number, got {value!r}")
        if self.mass < 0 or self.eccentricity < 0:
            raise InputError(f"unbalance mass ({self.mass!r} kg) and eccentricity ({self.eccentricity!r} m) must be "
                             "non-negative; turn a negative unbalance into a positive one with phase + pi")

    @property
    def magnitude(self) -> float:
        """m e (kg m)."""
        return float(self.mass) * float(self.eccentricity)


def _rotor(model) -> RotorModel:
    if not isinstance(model, RotorModel):
        raise InputError(f"forced rotor response takes a compiled rotor in the stationary frame (Rotor(...).compile() "
                         f"or periodyn.examples.rotor()), got {type(model).__name__}; an element rotor's coordinates "
                         "turn with the shaft")
    return model


def _unbalances(model: RotorModel, unbalance) -> tuple[Unbalance, ...]:
    items = (unbalance,) if isinstance(unbalance, Unbalance) else tuple(unbalance)
    if not items or not all(isinstance(u, Unbalance) for u in items):
        raise InputError(f"unbalance must be an Unbalance(station, mass, eccentricity, phase) or a non-empty list of "
                         f"them, got {unbalance!r}")
    for u in items:
        if u.station >= model.stations.size:
            raise InputError(f"unbalance station {u.station} is out of range: rotor '{model.name}' has stations 0 to "
                             f"{model.stations.size - 1} (at {np.round(model.stations, 6).tolist()} m)")
    return items


def unbalance_load(model: RotorModel, unbalance, speeds) -> np.ndarray:
    """Complex load amplitudes (S, n) of ``unbalance`` (one or a list of
    :class:`Unbalance`) at spin speeds (S,) rad/s: ``m e Omega^2 e^{i phi} [1, -i]``
    on (y, z) of each unbalanced station (N)."""
    model, speeds = _rotor(model), _speeds(speeds)
    load = np.zeros((speeds.size, model.n), dtype=complex)
    for u in _unbalances(model, unbalance):
        rotating = u.magnitude * np.exp(1j * u.phase) * speeds**2
        load[:, 4 * u.station] += rotating
        load[:, 4 * u.station + 1] += -1j * rotating
    return load


def _solve(model: RotorModel, speeds: np.ndarray, load: np.ndarray) -> np.ndarray:
    """X (S, n) of the synchronous dynamic stiffness at every speed times X = load."""
    eq = model.equations("stationary")
    M, (C0, C1), (K0, K1, K2) = eq.mass, eq.damping, eq.stiffness
    n = model.n
    out = np.empty((speeds.size, n), dtype=complex)
    chunk = max(1, _CHUNK_ENTRIES // (n * n))
    for lo in range(0, speeds.size, chunk):
        w = speeds[lo:lo + chunk, None, None]
        A = K0 + w * K1 + w**2 * K2 + 1j * w * (C0 + w * C1) - w**2 * M
        try:
            out[lo:lo + chunk] = np.linalg.solve(A, load[lo:lo + chunk, :, None])[..., 0]
        except np.linalg.LinAlgError:
            bad = [float(s) for s, a in zip(speeds[lo:lo + chunk], A) if np.linalg.matrix_rank(a) < n]
            raise InputError(f"rotor '{model.name}': the dynamic stiffness is singular at speeds {bad} rad/s (an "
                             "undamped resonance, or a rigid-body mode at speed 0: add bearings); leave those speeds "
                             "out") from None
    return out


def synchronous_response(model: RotorModel, load, speeds, *, description: str = "") -> xr.Dataset:
    """Steady response to loads turning at the spin speed: ``load`` (n,) or (S, n) complex
    amplitudes (N, N m) at spin speeds (S,) rad/s, each load at frequency w = Omega.

    Returns a dataset with dims (speed, coordinate, station, direction): ``response``
    (speed, coordinate) complex X (m, rad), ``amplitude`` |X| and ``phase`` arg X (rad)
    of the (speed, station, direction) lateral displacements (direction y, z),
    ``major_axis`` / ``minor_axis`` (speed, station) the orbit's semi-axes (m), ``whirl``
    (speed, station) "forward"/"backward"; coordinates ``speed_rpm`` and
    ``station_position`` (m)."""
    model, speeds = _rotor(model), _speeds(speeds)
    load = np.asarray(load, dtype=complex)
    if load.ndim == 1:
        load = np.broadcast_to(load, (speeds.size, load.size))
    if load.shape != (speeds.size, model.n) or not np.all(np.isfinite(load)):
        raise InputError(f"load must be finite complex amplitudes of shape ({model.n},) or ({speeds.size}, "
                         f"{model.n}) (coordinates {model.coordinate_names[:4]}... per station), got shape "
                         f"{load.shape}")
    X = _solve(model, speeds, load)
    lateral = X.reshape(speeds.size, -1, 4)[..., :2]                       # (S, n_s, 2): Y, Z
    forward = np.abs(lateral[..., 0] + 1j * lateral[..., 1]) / 2.0
    backward = np.abs(lateral[..., 0] - 1j * lateral[..., 1]) / 2.0
    dims = ("speed", "station", "direction")
    return xr.Dataset(
        {"response": (("speed", "coordinate"), X, {"units": "m or rad", "long_name": "complex amplitude, "
                                                                                     "x = Re(X exp(i w t))"}),
         "amplitude": (dims, np.abs(lateral), {"units": "m"}),
         "phase": (dims, np.angle(lateral), {"units": "rad"}),
         "major_axis": (dims[:2], forward + backward, {"units": "m", "long_name": "orbit semi-major axis"}),
         "minor_axis": (dims[:2], np.abs(forward - backward), {"units": "m", "long_name": "orbit semi-minor axis"}),
         "whirl": (dims[:2], np.where(forward >= backward, FORWARD, BACKWARD).astype(object))},
        coords={"speed": ("speed", speeds, {"units": "rad/s"}),
                "speed_rpm": ("speed", speeds * 30.0 / np.pi, {"units": "rpm"}),
                "coordinate": list(model.coordinate_names), "station": np.arange(model.stations.size),
                "station_position": ("station", model.stations, {"units": "m"}), "direction": ["y", "z"]},
        attrs={"rotor": model.name, "load": description or "synchronous load"})


def unbalance_response(model: RotorModel, unbalance, speeds) -> xr.Dataset:
    """Synchronous response to ``unbalance`` (an :class:`Unbalance` or a list of them,
    superposed) at spin speeds (S,) rad/s: the dataset of :func:`synchronous_response`,
    attrs ``load`` (in words) and ``unbalance`` (JSON: station, mass, eccentricity, phase)."""
    model = _rotor(model)
    items = _unbalances(model, unbalance)
    text = "unbalance " + "; ".join(f"{u.magnitude:.4g} kg m at station {u.station}, {u.phase:.4g} rad" for u in items)
    ds = synchronous_response(model, unbalance_load(model, items, speeds), speeds, description=text)
    ds.attrs["unbalance"] = json.dumps([{"station": int(u.station), "mass": float(u.mass),
                                         "eccentricity": float(u.eccentricity), "phase": float(u.phase)} for u in items])
    return ds


def static_deflection(model: RotorModel, gravity=(0.0, -STANDARD_GRAVITY), *, speed: float = 0.0) -> xr.Dataset:
    """Static deflection under a uniform lateral acceleration ``gravity`` (g_y, g_z) m/s^2
    (default standard gravity along -z) at spin speed ``speed`` (rad/s; the stiffness
    K0 + Omega K1 + Omega^2 K2): K u = M a with a the rigid translation by ``gravity``,
    the consistent weight of shaft, disks and masses. Returns a dataset with
    ``displacement`` (coordinate) (m, rad), ``deflection`` (station, direction) (m) and
    ``load`` (coordinate) (N, N m)."""
    model = _rotor(model)
    g = np.asarray(gravity, dtype=float)
    if g.shape != (2,) or not np.all(np.isfinite(g)):
        raise InputError(f"gravity must be the lateral acceleration (g_y, g_z) in m/s^2, got {gravity!r}")
    if np.ndim(speed) != 0:
        raise InputError(f"speed must be one spin speed >= 0 in rad/s, got {speed!r}")
    w = float(_speeds(speed)[0])
    M, _, K = model.equations("stationary").at(w)
    rigid = np.zeros(model.n)
    rigid[0::4], rigid[1::4] = g
    load = M @ rigid
    if np.linalg.matrix_rank(K) < model.n:
        raise InputError(f"rotor '{model.name}': its stiffness is singular (a rigid-body motion, the rotor is not "
                         "held by bearings against it); add bearings for a static deflection")
    u = np.linalg.solve(K, load)
    return xr.Dataset(
        {"displacement": ("coordinate", u, {"units": "m or rad"}),
         "deflection": (("station", "direction"), u.reshape(-1, 4)[:, :2], {"units": "m"}),
         "load": ("coordinate", load, {"units": "N or N m"})},
        coords={"coordinate": list(model.coordinate_names), "station": np.arange(model.stations.size),
                "station_position": ("station", model.stations, {"units": "m"}), "direction": ["y", "z"]},
        attrs={"rotor": model.name, "gravity": g.tolist(), "speed": w})


def critical_speeds(model: RotorModel, speed_range, *, num: int = 200, xtol: float = 1e-10) -> np.ndarray:
    """Damped critical speeds (rad/s) in ``speed_range`` (lo, hi): the spin speeds where a
    forward whirl frequency of the Campbell diagram equals the spin speed, bracketed on
    ``num`` grid speeds (forward modes counted in order of frequency) and refined by
    Brent's method to ``xtol`` relative. Sorted."""
    from scipy.optimize import brentq

    model = _rotor(model)
    try:
        lo, hi = (float(v) for v in speed_range)
    except (TypeError, ValueError):
        raise InputError(f"speed_range must be (lo, hi) in rad/s, got {speed_range!r}") from None
    if not (0.0 <= lo < hi and np.isfinite(hi)) or int(num) < 2:
        raise InputError(f"speed_range must satisfy 0 <= lo < hi (rad/s) and num >= 2, got {speed_range!r}, {num!r}")

    def forward(speeds):
        ds = campbell(model, speeds, frame="stationary")
        f, fwd = ds["frequency"].values, ds["whirl"].values == FORWARD
        return [np.sort(f[i][fwd[i]]) for i in range(len(speeds))]

    grid = np.linspace(lo, hi, int(num))
    freqs = forward(grid)
    count = min(len(f) for f in freqs)
    found = []
    for k in range(count):
        gap = np.array([f[k] for f in freqs]) - grid
        for i in np.nonzero(np.sign(gap[:-1]) * np.sign(gap[1:]) < 0)[0]:
            found.append(brentq(lambda s, k=k: forward([s])[0][k] - s, grid[i], grid[i + 1],
                                xtol=xtol * grid[i + 1], rtol=xtol))
    return np.sort(np.array(found))
