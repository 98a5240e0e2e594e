"""Rheo-linear systems ``M(t) q'' + C(t) q' + K(t) q = f(t)`` with period ``T = 2*pi/omega``.

Two containers, grouped by lifetime:

* :class:`RheoLinear` -- one system at one speed: coefficient samples at the ``p``
  angles ``theta_j = 2*pi*j/p`` (times ``t_j = theta_j/omega``) and their spectra.
* :class:`OmegaSplitModel` -- a constant-speed model built once: samples over the crank
  angle of the coefficients of each power of omega (``C = C0 + w C1``,
  ``K = K0 + w K1 + w^2 K2``, ``f = f0 + w f1 + w^2 f2``); ``.at(omega)`` combines the
  precomputed spectra, so a speed sweep does no kinematics and no FFT per speed.

Outputs are linear maps ``y(t) = G(t) q(t)`` with ``G`` sampled as (p, n_out, n).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import Callable, NamedTuple, Sequence

import numpy as np

from .errors import InputError
from .numerics.spectra import fourier_coefficients, sample_angles

__all__ = ["RheoLinear", "OmegaSplitModel", "Spectra"]


class Spectra(NamedTuple):
    """Two-sided coefficient spectra, index k+K for k=-K..K: mass, damping, stiffness
    (2K+1, n, n), force (2K+1, n) and output maps (2K+1, n_out, n)."""

    mass: np.ndarray
    damping: np.ndarray
    stiffness: np.ndarray
    force: np.ndarray
    outputs: np.ndarray


def _check_omega(omega) -> float:
    try:
        w = float(omega)
    except (TypeError, ValueError):
        raise InputError(f"omega must be a number in rad/s, got {omega!r}") from None
    if not np.isfinite(w) or w <= 0.0:
        raise InputError(f"omega must be a positive finite driving speed in rad/s, got {omega!r}")
    return w


def _real(name: str, value) -> np.ndarray:
    """``value`` as a float array; InputError for a complex or non-numeric one (a complex
    coefficient would lose its imaginary part silently)."""
    try:
        a = np.asarray(value)
        real = None if np.iscomplexobj(a) else np.asarray(a, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a real numeric array, got {type(value).__name__}") from None
    if real is None:
        raise InputError(f"{name} must be real, got complex values (their imaginary part would be dropped); "
                         "give the real coefficients of the equations of motion")
    return real


def _as_samples(name: str, value, p: int | None, n: int | None, vector: bool) -> np.ndarray:
    """Validate one coefficient series: (p,n,n) or (p,n); constants (n,n)/(n,) are broadcast."""
    a = _real(name, value)
    ndim = 2 if vector else 3
    if p is not None and a.ndim == ndim - 1:
        a = np.broadcast_to(a, (p,) + a.shape)
    if a.ndim != ndim:
        want = "(p, n)" if vector else "(p, n, n)"
        raise InputError(f"{name} must have shape {want} (samples first), got shape {a.shape}")
    if 0 in a.shape:
        raise InputError(f"{name} has shape {a.shape}: it needs at least one sample and one coordinate "
                         "(samples first, e.g. (p, n, n) with p >= 1, n >= 1)")
    if p is not None and a.shape[0] != p:
        raise InputError(f"{name} has {a.shape[0]} samples but the mass matrix has {p}; give every series the same sample count")
    if not vector and a.shape[1] != a.shape[2]:
        raise InputError(f"{name} samples must be square n x n matrices, got {a.shape[1]} x {a.shape[2]}")
    if n is not None and a.shape[1] != n:
        raise InputError(f"{name} is for {a.shape[1]} coordinates but the mass matrix for {n}; sizes must match")
    bad = ~np.isfinite(a)
    if bad.any():
        j = int(np.argwhere(bad)[0][0])
        raise InputError(f"{name} has NaN or inf at sample {j} (angle {2 * np.pi * j / a.shape[0]:.4g} rad); check the model or its input")
    return a


def _check_mass(mass: np.ndarray, rcond: float = 1e-12) -> None:
    s = np.linalg.svd(mass, compute_uv=False)  # (p, n)
    ratio = s[:, -1] / np.maximum(s[:, 0], np.finfo(float).tiny)
    bad = np.nonzero(ratio < rcond)[0]
    if bad.size:
        j = int(bad[0])
        raise InputError(
            f"mass matrix is singular at sample {j} (angle {2 * np.pi * j / mass.shape[0]:.4g} rad, "
            f"condition {1 / max(ratio[j], 1e-300):.3g}); every dynamic coordinate needs inertia, "
            "so add mass/inertia or make that coordinate rigid/prescribed"
        )


def _check_samples(p: int) -> int:
    if not isinstance(p, (int, np.integer)) or isinstance(p, bool) or p < 1:
        raise InputError(f"samples must be a positive integer number of time samples per period, got {p!r}")
    return int(p)


def _names_and_outputs(coordinate_names, output_maps, output_names, p: int, n: int) -> tuple[tuple, np.ndarray, tuple]:
    """Validated coordinate names (n,) (default q0, q1, ...), output maps (p, n_out, n) and
    output names (default: the coordinates, or y0, y1, ... for given maps)."""
    names = tuple(coordinate_names) if coordinate_names is not None else tuple(f"q{i}" for i in range(n))
    if len(names) != n:
        raise InputError(f"{len(names)} coordinate names for {n} coordinates")
    return (names,) + _outputs(output_maps, output_names, p, n, names)


def _outputs(output_maps, output_names, p: int, n: int, coordinate_names) -> tuple[np.ndarray, tuple]:
    if output_maps is None:
        return np.broadcast_to(np.eye(n), (p, n, n)), tuple(coordinate_names)
    G = np.asarray(output_maps, dtype=float)
    if G.ndim == 2:
        G = np.broadcast_to(G, (p,) + G.shape)
    if G.ndim != 3 or G.shape[0] != p or G.shape[2] != n:
        raise InputError(f"output_maps must have shape (p={p}, n_out, n={n}) or (n_out, n), got {np.shape(output_maps)}")
    names = tuple(output_names) if output_names is not None else tuple(f"y{i}" for i in range(G.shape[1]))
    if len(names) != G.shape[1]:
        raise InputError(f"{len(names)} output names for {G.shape[1]} outputs; give one name per output row")
    return G, names


class _Sampled:
    """Sizes of coefficients sampled over one period, from the mass samples (p, n, n)."""

    mass: np.ndarray

    @property
    def n(self) -> int:
        """Number of coordinates."""
        return self.mass.shape[1]

    @property
    def samples(self) -> int:
        """Samples per period p."""
        return self.mass.shape[0]


@dataclass(frozen=True, eq=False)
class RheoLinear(_Sampled):
    """``M(t) q'' + C(t) q' + K(t) q = f(t)`` sampled over one period ``T = 2*pi/omega``.

    Build with :meth:`from_functions` or :meth:`from_samples` (which validate); fields:
    omega (rad/s), mass/damping/stiffness (p, n, n), force (p, n), output_maps
    (p, n_out, n), names, and optional exact callables of t for time-domain checks.
    """

    omega: float
    mass: np.ndarray
    damping: np.ndarray
    stiffness: np.ndarray
    force: np.ndarray
    coordinate_names: tuple[str, ...]
    output_maps: np.ndarray
    output_names: tuple[str, ...]
    functions: tuple[Callable, Callable, Callable, Callable] | None = None
    precomputed_spectra: Spectra | None = field(default=None, repr=False)

    @property
    def period(self) -> float:
        """T = 2*pi/omega, s."""
        return 2.0 * np.pi / self.omega

    @property
    def times(self) -> np.ndarray:
        """Sample times t_j = j T / p, shape (p,), s."""
        return sample_angles(self.samples) / self.omega

    @cached_property
    def spectra(self) -> Spectra:
        """Spectra of M, C, K, f and the output maps (all (p-1)//2 harmonics)."""
        if self.precomputed_spectra is not None:
            return self.precomputed_spectra
        return Spectra(*(fourier_coefficients(a) for a in
                         (self.mass, self.damping, self.stiffness, self.force, self.output_maps)))

    @cached_property
    def inverse_mass_spectra(self) -> Spectra:
        """Spectra of the paper's form (16): identity, P = M^-1 C, Q = M^-1 K, r = M^-1 f."""
        P = np.linalg.solve(self.mass, self.damping)
        Q = np.linalg.solve(self.mass, self.stiffness)
        r = np.linalg.solve(self.mass, self.force[..., None])[..., 0]
        eye = np.zeros((2 * ((self.samples - 1) // 2) + 1, self.n, self.n))
        eye[(self.samples - 1) // 2] = np.eye(self.n)
        return Spectra(eye, fourier_coefficients(P), fourier_coefficients(Q), fourier_coefficients(r),
                       self.spectra.outputs)

    # ------------------------------------------------------------------ constructors
    @classmethod
    def from_samples(cls, M, C, K, f, omega, *, coordinate_names: Sequence[str] | None = None,
                     output_maps=None, output_names: Sequence[str] | None = None) -> "RheoLinear":
        """From samples at ``t_j = 2*pi*j/(p*omega)``: M, C, K (p,n,n), f (p,n).

        Constant coefficients may be given as (n,n)/(n,) once M fixes p.
        """
        w = _check_omega(omega)
        Ma = _as_samples("M", M, None, None, vector=False)
        p, n = Ma.shape[0], Ma.shape[1]
        Ca = _as_samples("C", C, p, n, vector=False)
        Ka = _as_samples("K", K, p, n, vector=False)
        fa = _as_samples("f", f, p, n, vector=True)
        _check_mass(Ma)
        names, G, out_names = _names_and_outputs(coordinate_names, output_maps, output_names, p, n)
        return cls(w, Ma, Ca, Ka, fa, names, G, out_names)

    @classmethod
    def from_functions(cls, M: Callable, C: Callable, K: Callable, f: Callable, omega, samples: int, *,
                       coordinate_names: Sequence[str] | None = None, output_maps=None,
                       output_names: Sequence[str] | None = None) -> "RheoLinear":
        """From callables of time t (s): M(t), C(t), K(t) -> (n,n), f(t) -> (n,); scalars
        are accepted for n = 1. They are sampled at ``samples`` times over one period and
        kept for time-domain checks (monodromy, direct integration)."""
        w = _check_omega(omega)
        p = _check_samples(samples)
        t = sample_angles(p) / w

        def sample(name, fun, vector):
            if not callable(fun):
                raise InputError(f"{name} must be a callable of time t returning an array, got {type(fun).__name__}")
            vals = []
            for tj in t:
                v = _real(f"{name}(t)", fun(float(tj)))
                vals.append(v.reshape(1) if (vector and v.ndim == 0) else v.reshape(1, 1) if v.ndim == 0 else v)
            return np.stack(vals)

        sys = cls.from_samples(sample("M", M, False), sample("C", C, False), sample("K", K, False),
                               sample("f", f, True), w, coordinate_names=coordinate_names,
                               output_maps=output_maps, output_names=output_names)
        object.__setattr__(sys, "functions", (M, C, K, f))
        return sys


@dataclass(frozen=True, eq=False)
class OmegaSplitModel(_Sampled):
    """Constant-speed model with coefficients polynomial in omega, sampled over the crank
    angle theta = omega t at ``p`` angles.

    mass (p,n,n); damping (nc,p,n,n), stiffness (nk,p,n,n), force (nf,p,n): entry k
    multiplies omega**k. output_maps (p,n_out,n). ``rebuild(p)`` (optional) returns the
    same model sampled at p angles, used when a sweep asks for another sample count.
    ``metadata``: builder parameters and reference frequencies (e.g. ``omega0``), rad/s.
    """

    mass: np.ndarray
    damping: np.ndarray
    stiffness: np.ndarray
    force: np.ndarray
    coordinate_names: tuple[str, ...]
    output_maps: np.ndarray
    output_names: tuple[str, ...]
    name: str = "model"
    rebuild: Callable[[int], "OmegaSplitModel"] | None = field(default=None, repr=False)
    metadata: dict = field(default_factory=dict)

    @classmethod
    def from_samples(cls, mass, damping: Sequence, stiffness: Sequence, force: Sequence, *,
                     coordinate_names=None, output_maps=None, output_names=None, name="model",
                     rebuild=None, metadata=None) -> "OmegaSplitModel":
        """Validate and build; damping/stiffness/force are sequences over powers of omega."""
        Ma = _as_samples("mass", mass, None, None, vector=False)
        p, n = Ma.shape[:2]
        _check_mass(Ma)

        def powers(label, seq, vector):
            if len(seq) == 0:
                shape = (p, n) if vector else (p, n, n)
                return np.zeros((1,) + shape)
            return np.stack([_as_samples(f"{label}[omega^{k}]", s, p, n, vector) for k, s in enumerate(seq)])

        names, G, out_names = _names_and_outputs(coordinate_names, output_maps, output_names, p, n)
        return cls(Ma, powers("damping", damping, False), powers("stiffness", stiffness, False),
                   powers("force", force, True), names, np.ascontiguousarray(G), out_names, name, rebuild,
                   dict(metadata or {}))

    @classmethod
    def from_functions(cls, mass: Callable, damping: Sequence[Callable], stiffness: Sequence[Callable],
                       force: Sequence[Callable], samples: int, **kwargs) -> "OmegaSplitModel":
        """From callables of the crank angle theta (rad); the model can be resampled."""
        p = _check_samples(samples)
        theta = sample_angles(p)

        def sample(fun, vector):
            vals = [_real("a coefficient function's value", fun(float(th))) for th in theta]
            v = np.stack(vals)
            if v.ndim == 1:
                v = v.reshape((p, 1) if vector else (p, 1, 1))
            return v

        def rebuild(q):
            return cls.from_functions(mass, damping, stiffness, force, q, **kwargs)

        kwargs_out = dict(kwargs)
        output_maps = kwargs_out.pop("output_maps", None)
        if callable(output_maps):
            output_maps = np.stack([np.atleast_2d(output_maps(float(th))) for th in theta])
        return cls.from_samples(sample(mass, False), [sample(c, False) for c in damping],
                                [sample(k, False) for k in stiffness], [sample(f, True) for f in force],
                                output_maps=output_maps, rebuild=rebuild, **kwargs_out)

    @cached_property
    def _power_spectra(self) -> tuple[np.ndarray, ...]:
        return (fourier_coefficients(self.mass), fourier_coefficients(np.moveaxis(self.damping, 0, -1)),
                fourier_coefficients(np.moveaxis(self.stiffness, 0, -1)), fourier_coefficients(np.moveaxis(self.force, 0, -1)),
                fourier_coefficients(self.output_maps))

    def derived(self, kind: str, key, build: Callable[[], object]):
        """What ``build()`` makes of this model for ``key``: per-model data of the solvers
        above (mean modes, projections, resampled coefficients), kept with the model like its
        spectra, so that later sweeps of it and the workers forked from its process reuse it.
        One key per kind (another key replaces the kind's entry: memory stays bounded); a
        build must depend on the model and the key only. Not pickled."""
        store = self.__dict__.setdefault("_derived", {})
        if kind not in store or store[kind][0] != key:
            store[kind] = (key, build())
        return store[kind][1]

    def __getstate__(self):
        state = dict(self.__dict__)
        state.pop("_derived", None)  # rebuilt where needed, never shipped
        return state

    def with_samples(self, p: int) -> "OmegaSplitModel":
        """This model sampled at p angles (needs ``rebuild``)."""
        if p == self.samples:
            return self
        if self.rebuild is None:
            raise InputError(f"model '{self.name}' was built from {self.samples} samples and cannot be resampled; "
                             f"build it with samples={p} instead")
        return self.rebuild(p)

    def at(self, omega: float) -> RheoLinear:
        """The rheo-linear system at driving speed omega (rad/s)."""
        w = _check_omega(omega)
        Ms, Cs, Ks, fs, Gs = self._power_spectra
        wc = w ** np.arange(self.damping.shape[0])
        wk = w ** np.arange(self.stiffness.shape[0])
        wf = w ** np.arange(self.force.shape[0])
        spectra = Spectra(Ms, Cs @ wc, Ks @ wk, fs @ wf, Gs)
        return RheoLinear(w, self.mass, np.tensordot(wc, self.damping, 1), np.tensordot(wk, self.stiffness, 1),
                          np.tensordot(wf, self.force, 1), self.coordinate_names, self.output_maps,
                          self.output_names, None, spectra)
