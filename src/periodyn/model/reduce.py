"""Modal reduction of a constant-speed model onto the undamped modes of its mean system.

Element models are stiff (rod modes with state eigenvalues down to -1e9 1/s) while the
dominant characteristic exponent lives in the lowest few modes. :func:`modal_reduction` projects
every sample and every omega-power of an :class:`~periodyn.system.OmegaSplitModel`
(mass, damping, stiffness, force, output maps) onto k M-orthonormal modes Phi (n, k) of
the time-averaged system at a reference speed,

    Mbar Phi = mean_theta M,   Kbar = sym(mean_theta sum_p w_ref^p K_p),   Kbar phi_i = w_i^2 Mbar phi_i,

giving again an OmegaSplitModel (:class:`ReducedModel`, with q = Phi q_r), so every solver
runs on it unchanged. :func:`mean_modes` gives all n modes with their frequencies (rad/s)
and modal damping ratios; :func:`guarded_modes` the mode count that keeps every
underdamped mode within the parametric reach of the modes asked for.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla

from ..errors import InputError
from ..system import OmegaSplitModel

__all__ = ["MeanModes", "ReducedModel", "mean_modes", "guarded_modes", "project", "modal_spectrum",
           "modal_reduction"]


@dataclass(frozen=True, eq=False)
class MeanModes:
    """Undamped modes of a model's mean system at ``reference_speed`` (rad/s), ascending.

    shapes (n, n) M-orthonormal columns (Phi^T Mbar Phi = I); frequencies (n,) rad/s
    (sqrt of the eigenvalue, negative for a mode the mean stiffness makes unstable);
    damping (n,) modal damping ratios c_ii / (2 |w_i|) of the mean damping at the
    reference speed (inf for a zero frequency)."""

    shapes: np.ndarray
    frequencies: np.ndarray
    damping: np.ndarray
    reference_speed: float


def _mean(powers: np.ndarray, w: float) -> np.ndarray:
    """sum_p w^p mean_theta X_p for samples X (P, p, n, n)."""
    return np.tensordot(w ** np.arange(powers.shape[0]), powers.mean(axis=1), 1)


def mean_modes(model: OmegaSplitModel, reference_speed: float = 0.0) -> MeanModes:
    """All modes of the symmetrized mean system of ``model`` at ``reference_speed`` rad/s."""
    if not isinstance(model, OmegaSplitModel):
        raise InputError(f"mean_modes takes an OmegaSplitModel, got {type(model).__name__}")
    w = float(reference_speed)
    if not np.isfinite(w) or w < 0:
        raise InputError(f"reference_speed must be a finite speed >= 0 rad/s, got {reference_speed!r}")
    M = model.mass.mean(axis=0)
    K = _mean(model.stiffness, w)
    lam, Phi = sla.eigh(0.5 * (K + K.T), 0.5 * (M + M.T))
    freq = np.sign(lam) * np.sqrt(np.abs(lam))
    C = Phi.T @ _mean(model.damping, w) @ Phi
    with np.errstate(divide="ignore"):
        zeta = np.abs(np.diag(C)) / (2 * np.abs(freq))
    return MeanModes(Phi, freq, zeta, w)


def guarded_modes(modes: MeanModes, k: int, harmonics: int, omega_max: float) -> int:
    """The mode count >= k that keeps every underdamped mode i (damping ratio < 1) within
    the parametric reach |w_i - w_j| <= m omega_max of an underdamped mode j among the first
    k (combination resonances of order up to m couple them; a sum resonance
    w_i + w_j <= m omega_max is inside this reach too)."""
    f, under = np.abs(modes.frequencies), modes.damping < 1.0
    low = f[:k][under[:k]]
    if low.size == 0:
        return k
    reach = low.max() + harmonics * float(omega_max)
    inside = np.nonzero(under & (f <= reach))[0]
    return int(max(k, inside.max() + 1 if inside.size else k))


@dataclass(frozen=True, eq=False)
class ReducedModel(OmegaSplitModel):
    """An OmegaSplitModel in mean-system modal coordinates q = Phi q_r.

    basis: Phi (n, k) of the full model's coordinates; frequencies (k,) rad/s of the kept
    modes; full: the model it was reduced from (None if not kept)."""

    basis: np.ndarray | None = None
    frequencies: np.ndarray | None = None
    full: OmegaSplitModel | None = None

    def physical(self, q: np.ndarray) -> np.ndarray:
        """Physical coordinates (..., n) of modal coordinates q (..., k) (real or complex)."""
        return np.asarray(q) @ self.basis.T


def project(model: OmegaSplitModel, basis: np.ndarray, frequencies: np.ndarray | None = None) -> ReducedModel:
    """Galerkin projection Phi^T X Phi of every sample and omega-power of ``model`` onto the
    columns of ``basis`` (n, k); forces Phi^T f, output maps G Phi. Resampling
    (``with_samples``) projects the resampled full model onto the same basis."""
    Phi = np.asarray(basis, float)
    if Phi.ndim != 2 or Phi.shape[0] != model.n or not 1 <= Phi.shape[1] <= model.n:
        raise InputError(f"basis must have shape (n={model.n}, k) with 1 <= k <= n, got {Phi.shape}")

    def sq(X):
        return np.einsum("ni,...nm,mj->...ij", Phi, X, Phi, optimize=True)

    k = Phi.shape[1]
    out = OmegaSplitModel.from_samples(
        sq(model.mass), list(sq(model.damping)), list(sq(model.stiffness)), list(model.force @ Phi),
        coordinate_names=tuple(f"mode{i}" for i in range(k)), output_maps=model.output_maps @ Phi,
        output_names=model.output_names, name=f"{model.name} ({k} modes)", metadata=dict(model.metadata))
    full = model

    def rebuild(p: int) -> ReducedModel:
        return project(full.with_samples(p), Phi, frequencies)

    return ReducedModel(out.mass, out.damping, out.stiffness, out.force, out.coordinate_names, out.output_maps,
                        out.output_names, out.name, rebuild if model.rebuild is not None else None, out.metadata,
                        Phi, None if frequencies is None else np.asarray(frequencies, float), model)


def modal_spectrum(X: np.ndarray, basis: np.ndarray, right: np.ndarray | None = None) -> np.ndarray:
    """Phi^T X_k Psi (2K+1, a, b[, P]) of a two-sided spectrum X (2K+1, n, n[, P]) of real
    samples (index k+K; P omega-powers) on the columns of basis Phi (n, a) and right Psi
    (n, b) (default Phi): the harmonics k >= 0 by real products of their real and imaginary
    parts (the narrower side first), k < 0 their conjugates (the spectrum of the projected
    samples, without transforming them again)."""
    K = (X.shape[0] - 1) // 2
    right = basis if right is None else right
    Y = np.moveaxis(X[K:], -1, 1) if X.ndim == 4 else X[K:, None]  # (K+1, P, n, n)
    half = np.empty(Y.shape[:2] + (basis.shape[1], right.shape[1]), complex)
    narrow_right = right.shape[1] < basis.shape[1]
    for out, Z in ((half.real, Y.real), (half.imag, Y.imag)):
        Z = np.ascontiguousarray(Z)
        out[...] = basis.T @ (Z @ right) if narrow_right else basis.T @ Z @ right
    half = np.moveaxis(half, 1, -1) if X.ndim == 4 else half[:, 0]
    return np.concatenate([np.conj(half[:0:-1]), half])


def modal_reduction(model: OmegaSplitModel, modes: int, reference_speed: float = 0.0, *, harmonics: int | None = None,
           omega_max: float | None = None) -> ReducedModel:
    """``model`` projected onto its ``modes`` lowest mean-system modes at
    ``reference_speed`` rad/s (:func:`mean_modes`). With ``harmonics`` m and ``omega_max``
    (rad/s, the highest speed of the use), more modes are kept where the parametric-reach
    guard asks for them (:func:`guarded_modes`)."""
    if isinstance(modes, bool) or not isinstance(modes, (int, np.integer)) or not 1 <= modes <= model.n:
        raise InputError(f"modes must be an integer from 1 to the model's {model.n} coordinates, got {modes!r}")
    if (harmonics is None) != (omega_max is None):
        raise InputError("the parametric-reach guard needs both harmonics and omega_max (or neither)")
    mm = mean_modes(model, reference_speed)
    k = int(modes) if harmonics is None else guarded_modes(mm, int(modes), int(harmonics), float(omega_max))
    return project(model, mm.shapes[:, :k], mm.frequencies[:k])
