"""Planar rigid-body builder: bodies, joints, springs, loads -> :class:`~periodyn.dae.DAE`.

Bodies have centre-of-mass coordinates (x, y, phi) in m, m, rad, or (x, y) for a point
mass (a slider block). Gravity acts along -y. Everything the solvers need (M, f, f_q,
f_q', Phi, Phi_q, sum lam Phi_qq, Phi_t, gamma) is filled by the jitted kernels of
``periodyn.kernels.solvers.rigid2d`` for a whole batch of samples at once.

Named parameters scale loads and base motions: ``add_load(..., parameter="f")`` makes
the load amplitude proportional to ``params["f"]`` (amplitude given per unit parameter).
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..kernels.solvers import rigid2d as K
from ..dae import DAE

__all__ = ["PlanarSystem"]


class PlanarSystem:
    """Mutable builder; :meth:`build` returns an immutable-by-convention DAE."""

    def __init__(self, gravity: float = 9.81, name: str = "planar"):
        self.gravity = float(gravity)
        self.name = name
        self._bodies: list[tuple[float, float | None, str]] = []
        self._joints: list[tuple] = []
        self._sliders: list[tuple] = []
        self._springs: list[tuple] = []
        self._loads: list[tuple] = []
        self._order: list[tuple[str, int]] = []  # constraint rows in the order added
        self._params: dict[str, float] = {}

    # ------------------------------------------------------------------ bodies
    def add_body(self, mass: float, inertia: float | None = None, name: str | None = None) -> int:
        """Add a body of ``mass`` (kg) and centroidal ``inertia`` (kg m^2); None makes a
        point mass with coordinates (x, y) only. Returns the body index."""
        if mass <= 0 or (inertia is not None and inertia <= 0):
            raise InputError(f"body mass and inertia must be positive, got mass={mass}, inertia={inertia}")
        self._bodies.append((float(mass), None if inertia is None else float(inertia),
                             name or f"b{len(self._bodies)}"))
        return len(self._bodies) - 1

    def coordinate(self, body: int, which: str) -> int:
        """Global index of coordinate ``which`` in {"x", "y", "phi"} of ``body``."""
        start, rot = self._layout()
        k = {"x": 0, "y": 1, "phi": 2}[which]
        if k == 2 and not rot[body]:
            raise InputError(f"body {body} is a point mass without a rotation coordinate")
        return int(start[body] + k)

    def _layout(self):
        rot = np.array([b[1] is not None for b in self._bodies], dtype=np.int64)
        start = np.concatenate([[0], np.cumsum(2 + rot)[:-1]]).astype(np.int64)
        return start, rot

    def _check_body(self, b):
        if b is not None and not (0 <= b < len(self._bodies)):
            raise InputError(f"body index {b} does not exist; add the body first")

    # ------------------------------------------------------------------ joints
    def add_revolute(self, body_b: int, point_b, body_a: int | None = None, point_a=(0.0, 0.0),
                     base_cos=(0.0, 0.0), base_sin=(0.0, 0.0), parameter: str | None = None) -> None:
        """Pin local point ``point_b`` of body b to local point ``point_a`` of body a
        (``body_a=None``: the ground point ``point_a + base_cos cos(w t) + base_sin sin(w t)``,
        a prescribed base motion, its amplitude times ``params[parameter]`` if given).
        Constraint: ``r_b + R(phi_b) s_b - r_a - R(phi_a) s_a = 0`` (2 rows)."""
        self._check_body(body_b)
        self._check_body(body_a)
        self._order.append(("j", len(self._joints)))
        self._joints.append((-1 if body_a is None else body_a, body_b, tuple(point_a), tuple(point_b),
                             tuple(base_cos), tuple(base_sin), parameter))

    def add_slider(self, body: int, point=(0.0, 0.0), normal=(0.0, 1.0), origin=(0.0, 0.0)) -> None:
        """Keep a body point on the line through ``origin`` with unit ``normal``: one row
        ``n . (r + R(phi) s - origin) = 0``."""
        self._check_body(body)
        nrm = np.asarray(normal, float)
        self._order.append(("s", len(self._sliders)))
        self._sliders.append((body, tuple(point), tuple(nrm / np.linalg.norm(nrm)), tuple(origin)))

    # ------------------------------------------------------------------ forces
    def add_spring(self, i: int, j: int | None = None, k: float = 0.0, k3: float = 0.0, c: float = 0.0,
                   offset: float = 0.0) -> None:
        """Coordinate spring/damper between global coordinates i and j (None: ground):
        with ``d = q_i - q_j - offset`` the force ``-k d - k3 d^3 - c d'`` acts on q_i and
        the opposite on q_j. Torsional springs act between phi coordinates (N m/rad,
        N m/rad^3, N m s/rad); linear ones between x or y coordinates (N/m, N/m^3, N s/m)."""
        self._springs.append((int(i), -1 if j is None else int(j), float(k), float(k3), float(c), float(offset)))

    def add_load(self, i: int, cos: float = 0.0, sin: float = 0.0, harmonic: int = 1,
                 parameter: str | None = None) -> None:
        """Time forcing ``cos * cos(h w t) + sin * sin(h w t)`` on coordinate i (N or N m),
        times ``params[parameter]`` when given."""
        self._loads.append((int(i), float(cos), float(sin), float(harmonic), parameter))

    def add_parameter(self, name: str, value: float) -> None:
        """Declare a named scalar parameter (used by loads/base motions, continuation)."""
        self._params[name] = float(value)

    # ------------------------------------------------------------------ build
    def build(self, q0=None, coordinate_names=None) -> DAE:
        """Assemble the DAE. q0: (n,) reference configuration (default zeros)."""
        start, rot = self._layout()
        n = int(np.sum(2 + rot))
        masses = np.zeros(n)
        weight = np.zeros(n)
        for b, (mb, Ib, _) in enumerate(self._bodies):
            masses[start[b]:start[b] + 2] = mb
            weight[start[b] + 1] = -mb * self.gravity
            if Ib is not None:
                masses[start[b] + 2] = Ib
        Mconst = np.diag(masses)
        for par in [j[6] for j in self._joints] + [ld[4] for ld in self._loads]:
            if par is not None and par not in self._params:
                raise InputError(f"parameter {par!r} is used but not declared; call add_parameter({par!r}, value)")

        nj, ns = len(self._joints), len(self._sliders)
        m = 2 * nj + ns
        row_of, cnames, row = {}, [], 0
        for kind, e in self._order:  # rows in the order the constraints were added
            row_of[(kind, e)] = row
            cnames += [f"lambda_j{e}_x", f"lambda_j{e}_y"] if kind == "j" else [f"lambda_s{e}"]
            row += 2 if kind == "j" else 1
        jint = np.zeros((nj, 3), np.int64)
        jraw = np.zeros((nj, 10))
        for e, (a, b, sa, sb, gc, gs, _) in enumerate(self._joints):
            jint[e] = (a, b, row_of[('j', e)])
            jraw[e] = (*sa, *sb, *(sa if a < 0 else (0.0, 0.0)), *gc, *gs)
        sint = np.zeros((ns, 2), np.int64)
        sflt = np.zeros((ns, 6))
        for e, (b, s, nrm, org) in enumerate(self._sliders):
            sint[e] = (b, row_of[('s', e)])
            sflt[e] = (*s, *nrm, *org)
        kint = np.array([[s[0], s[1]] for s in self._springs], np.int64).reshape(-1, 2)
        kflt = np.array([s[2:] for s in self._springs], float).reshape(-1, 4)
        lint = np.array([ld[0] for ld in self._loads], np.int64)
        lraw = np.array([ld[1:4] for ld in self._loads], float).reshape(-1, 3)
        jpar = [j[6] for j in self._joints]
        lpar = [ld[4] for ld in self._loads]

        def jflt_of(P):
            out = jraw.copy()
            for e, par in enumerate(jpar):
                if par is not None:
                    out[e, 6:] *= P[par]
            return out

        def lflt_of(P):
            out = lraw.copy()
            for e, par in enumerate(lpar):
                if par is not None:
                    out[e, :2] *= P[par]
            return out

        def mass(q):
            return np.broadcast_to(Mconst, (q.shape[0], n, n))

        def force(q, qd, t, w, P):
            out = np.empty((q.shape[0], n))
            K.forces(np.ascontiguousarray(q, float), np.ascontiguousarray(qd, float), np.ascontiguousarray(t, float),
                     float(w), weight, kint, kflt, lint, lflt_of(P), out)
            return out

        def force_jacobians(q, qd, t, w, P):
            Kq = np.empty((q.shape[0], n, n))
            Kv = np.empty((q.shape[0], n, n))
            K.force_jacobians(np.ascontiguousarray(q, float), np.ascontiguousarray(qd, float), kint, kflt, Kq, Kv)
            return Kq, Kv

        def constraint(q, t, w, P):
            out = np.empty((q.shape[0], m))
            K.constraint_values(np.ascontiguousarray(q, float), np.ascontiguousarray(t, float), float(w), start, rot,
                                jint, jflt_of(P), sint, sflt, out)
            return out

        def constraint_jacobian(q, t, w, P):
            out = np.empty((q.shape[0], m, n))
            K.constraint_jacobian(np.ascontiguousarray(q, float), start, rot, jint, jraw, sint, sflt, out)
            return out

        def constraint_hessian(q, lam, t, w, P):
            out = np.empty((q.shape[0], n, n))
            K.constraint_hessian(np.ascontiguousarray(q, float), np.ascontiguousarray(lam, float), start, rot, jint,
                                 jraw, sint, sflt, out)
            return out

        def constraint_rates(q, qd, t, w, P):
            pt = np.empty((q.shape[0], m))
            g = np.empty((q.shape[0], m))
            K.constraint_rates(np.ascontiguousarray(q, float), np.ascontiguousarray(qd, float),
                               np.ascontiguousarray(t, float), float(w), start, rot, jint, jflt_of(P), sint, sflt, pt, g)
            return pt, g

        if coordinate_names is None:
            coordinate_names = []
            for b, (_, Ib, nm) in enumerate(self._bodies):
                coordinate_names += [f"x_{nm}", f"y_{nm}"] + ([f"phi_{nm}"] if Ib is not None else [])
        dae = DAE.from_batch(n=n, m=m, mass=mass, force=force, force_jacobians=force_jacobians,
                             constraint=constraint, constraint_jacobian=constraint_jacobian,
                             constraint_hessian=constraint_hessian, constraint_rates=constraint_rates,
                             mass_jacobian=None, q0=q0, parameters=dict(self._params),
                             coordinate_names=coordinate_names, constraint_names=cnames, name=self.name)
        # the packed arrays for fused kernels (periodyn.kernels.solvers.rigid2d_flow): model tuple, and the
        # joint and load data at parameters P
        model = (np.ascontiguousarray(Mconst[None]), weight, kint, kflt, lint, np.asarray(start, np.int64),
                 np.asarray(rot, np.int64), jint, jraw, sint, sflt)
        dae.planar_arrays = (model, lambda P: (jflt_of(P), lflt_of(P)))
        return dae
