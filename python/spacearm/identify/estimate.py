r"""Least-squares estimate of a payload's inertial parameters from momentum conservation.

The combined system (robot + payload fixed to the grasp body) moves with no external wrench, so
its momentum $h = [P; L_\text{origin}]$ is constant:

$$
h_\text{robot}(x_k, u_k) + Y(x_k, u_k)\, \pi = h_0 \quad \text{for every sample } k \tag{1}
$$

([`spacearm.identify.regressor`][spacearm.identify.regressor]; Yoshida & Abiko 2002). With $h_0$ known, (1) is linear in $\pi$.
With ``h0`` unknown (the usual case: nothing measures it), it is eliminated by subtracting the
sample mean of each of the six rows (the least-squares estimate of $h_0$ for any $\pi$), leaving
$(Y_k - \bar Y)\, \pi = -(h_{\text{robot},k} - \bar h_\text{robot})$; $h_0$ is recovered afterwards as the mean of
$h_\text{robot} + Y \pi$.

Noise model (what the covariance means): the errors of the six momentum equations are
independent between samples, zero-mean, with one standard deviation $\sigma_P$ for the three linear
rows and one $\sigma_L$ for the three angular rows. Both are estimated from the residuals of an
ordinary least-squares pass; a second pass weights the rows by $1/\sigma$ and gives
$\operatorname{Cov}(\pi) = (A^T W A)^{-1}$ restricted to the identifiable subspace. Measurement noise on the joint
and base velocities enters (1) this way to first order (on both sides: the regressor holds
measured velocities too, which biases the estimate by a term of order $\sigma^2$, not corrected here).

Identifiability: the parameters are made commensurable with a characteristic length $\ell$ (the
RMS distance of the grasp body's CM from the base CM over the samples): $[m, h/\ell, \bar I/\ell^2]$ all
have units of mass, and their columns of the weighted regressor units of momentum per kg. The
SVD of that matrix gives the rank: singular values below ``rcond`` times the largest singular
value of the same matrix before the mean is removed (the size of the parameters' contribution
to the momentum) span the null space, the parameter combinations the motion does not determine
(a contribution that is tiny, or constant along the motion and so indistinguishable from
``h0``, gives a small singular value). The condition number reported is that of this nondimensional matrix; it measures how
well the motion excites the parameters, not an artefact of the units.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._util.arrays import number, real_array
from .._util.summary import summary_repr
from .._util.pickling import reduce_through_constructor as _reduce_through_constructor
from ..errors import ArgumentError, NonFiniteError, ShapeError, SingularError, SpacearmTypeError
from ..model.robot import Robot
from .parameters import PARAMETER_NAMES, from_parameters, physical_jacobian
from .regressor import momentum_regressor, robot_momentum

__all__ = ["PayloadEstimate", "identify_payload", "DEFAULT_RCOND"]

#: Relative threshold on the singular values of the column-scaled regressor below which a
#: direction of π counts as not identified.
DEFAULT_RCOND = 1e-9


@dataclass(frozen=True, repr=False)
class PayloadEstimate:
    """The result of [`identify_payload`][spacearm.identify.identify_payload]. Frames: ``com`` from the grasp body's CM in its
    axes, ``inertia`` about the payload's CM in the grasp body's axes, ``momentum`` in 𝒥."""

    body: str  #: the grasp body
    parameters: np.ndarray  #: $\pi$ (10): $m$, $m c$, $\bar I$ about the grasp body's CM (PARAMETER_NAMES)
    covariance: np.ndarray  #: $\operatorname{Cov}(\pi)$ (10×10) under the noise model; zero along the null space
    momentum: np.ndarray  #: [P; L_origin] of robot + payload (6): estimated, or as given
    momentum_estimated: bool  #: whether ``momentum`` was estimated (True) or given
    singular_values: np.ndarray  #: of the column-scaled, weighted regressor (10, descending)
    rank: int  #: number of identified directions of π (10: all)
    null_space: np.ndarray  #: (10, 10 − rank): orthonormal directions of $\pi$ not identified
    condition_number: float  #: largest / smallest singular value (inf when rank < 10)
    noise_std: np.ndarray  #: estimated $\sigma_P$ (N·s) and $\sigma_L$ (N·m·s) of the momentum equations
    n_samples: int  #: samples used

    __repr__ = summary_repr
    __reduce__ = _reduce_through_constructor  # unpickled through __post_init__'s checks

    def __post_init__(self):
        """Check every value (what [`identify_payload`][spacearm.identify.identify_payload] produces; a
        tampered or bit-flipped pickle is refused the same way)."""
        if not isinstance(self.body, str):
            raise SpacearmTypeError(f"PayloadEstimate.body must be a body name (str), got {type(self.body).__name__}")
        for key in ("momentum_estimated",):
            if not isinstance(getattr(self, key), (bool, np.bool_)):
                raise SpacearmTypeError(f"PayloadEstimate.{key} must be a bool, got {getattr(self, key)!r}")
        for key in ("rank", "n_samples"):
            v = getattr(self, key)
            if isinstance(v, (bool, np.bool_)) or not isinstance(v, (int, np.integer)):
                raise SpacearmTypeError(f"PayloadEstimate.{key} must be an integer, got {v!r}")
        rank, n = int(self.rank), int(self.n_samples)
        if not 0 <= rank <= 10:
            raise ArgumentError(f"PayloadEstimate.rank must be in 0..10, got {rank}")
        if n < 2:
            raise ArgumentError(f"PayloadEstimate.n_samples must be >= 2 (an estimate needs at least 2 samples), got {n}")
        shapes = {"parameters": (10,), "covariance": (10, 10), "momentum": (6,), "singular_values": (10,),
                  "null_space": (10, 10 - rank), "noise_std": (2,)}
        arrays = {}
        for key, shape in shapes.items():
            arr = np.array(real_array(getattr(self, key), f"PayloadEstimate.{key}"), dtype=float)
            if arr.shape != shape:
                raise ShapeError(f"PayloadEstimate.{key} must have shape {shape} (rank {rank}), got {arr.shape}")
            if not np.all(np.isfinite(arr)):
                raise NonFiniteError(f"PayloadEstimate.{key} must be finite, got {arr}")
            arrays[key] = arr
        cov, sv, null = arrays["covariance"], arrays["singular_values"], arrays["null_space"]
        tol = 1e-9 * max(float(np.abs(cov).max()), np.finfo(float).tiny)
        if not (np.abs(cov - cov.T).max() <= tol and np.all(np.diag(cov) >= -tol)):
            raise ArgumentError("PayloadEstimate.covariance must be symmetric with a non-negative diagonal")
        if np.any(sv < 0) or np.any(np.diff(sv) > 0):
            raise ArgumentError(f"PayloadEstimate.singular_values must be >= 0 and descending, got {sv}")
        if null.size and not np.abs(null.T @ null - np.eye(10 - rank)).max() <= 1e-9:
            raise ArgumentError("PayloadEstimate.null_space must have orthonormal columns")
        if np.any(arrays["noise_std"] < 0):
            raise ArgumentError(f"PayloadEstimate.noise_std must be >= 0, got {arrays['noise_std']}")
        cond = number(self.condition_number, "PayloadEstimate.condition_number")
        expected = float(sv[0] / sv[-1]) if rank == 10 and sv[-1] > 0 else float("inf")
        if not (cond == expected or (np.isfinite(expected) and abs(cond - expected) <= 1e-12 * expected)):
            raise ArgumentError(f"PayloadEstimate.condition_number must be the ratio of the extreme singular values "
                                f"({expected:.6g}; inf below rank 10), got {cond!r}")
        for key, arr in arrays.items():
            object.__setattr__(self, key, arr)
        object.__setattr__(self, "condition_number", cond)
        object.__setattr__(self, "rank", rank)
        object.__setattr__(self, "n_samples", n)
        object.__setattr__(self, "momentum_estimated", bool(self.momentum_estimated))

    @property
    def identifiable(self) -> bool:
        """Whether the motion determined all ten parameters."""
        return self.rank == 10

    @property
    def identifiable_combinations(self) -> np.ndarray:
        """(rank, 10): orthonormal rows ``c`` such that ``c · π`` is determined by the motion
        (the orthogonal complement of [`null_space`][spacearm.identify.estimate.PayloadEstimate.null_space])."""
        _, _, vt = np.linalg.svd(np.eye(10) - self.null_space @ self.null_space.T)
        return vt[: self.rank]

    def _physical(self):
        if not self.identifiable:
            raise SingularError(f"the motion determined only {self.rank} of the 10 inertial parameters of the payload on "
                                f"'{self.body}'; undetermined combinations of {list(PARAMETER_NAMES)}: "
                                f"{np.round(self.null_space.T, 3).tolist()}; record a motion that rotates the grasp body "
                                "about more axes, or use the identified combinations (identifiable_combinations)")
        return from_parameters(self.parameters)

    @property
    def mass(self) -> float:
        """Payload mass, kg."""
        return self._physical()[0]

    @property
    def com(self) -> np.ndarray:
        """Payload CM from the grasp body's CM, in the grasp body's axes, m."""
        return self._physical()[1]

    @property
    def inertia(self) -> np.ndarray:
        """Payload inertia about its own CM, in the grasp body's axes (3×3), kg·m²."""
        return self._physical()[2]

    @property
    def physical_std(self) -> np.ndarray:
        """Standard deviations (10) of ``[m, cx, cy, cz, Ixx, Iyy, Izz, Ixy, Ixz, Iyz]`` (the
        physical parameters, inertia about the payload's CM), propagated to first order."""
        self._physical()
        g = physical_jacobian(self.parameters)
        return np.sqrt(np.maximum(np.diag(g @ self.covariance @ g.T), 0.0))

    def summary(self) -> str:
        """A few lines: rank, condition number, and the estimate with its standard deviations."""
        lines = [f"payload on '{self.body}': {self.n_samples} samples, rank {self.rank}/10, "
                 f"condition number {self.condition_number:.3g} (nondimensional regressor)",
                 f"noise of the momentum equations: sigma_P {self.noise_std[0]:.3g} N*s, sigma_L {self.noise_std[1]:.3g} N*m*s"]
        if not self.identifiable:
            lines.append(f"not identified: {self.null_space.shape[1]} direction(s) of {list(PARAMETER_NAMES)}")
            return "\n".join(lines)
        s = self.physical_std
        lines.append(f"mass {self.mass:.6g} kg (std {s[0]:.2g})")
        lines.append("com  " + ", ".join(f"{v:.6g}" for v in self.com) + " m (std " + ", ".join(f"{v:.2g}" for v in s[1:4]) + ")")
        i = self.inertia
        entries = (i[0, 0], i[1, 1], i[2, 2], i[0, 1], i[0, 2], i[1, 2])
        lines.append("inertia (xx, yy, zz, xy, xz, yz) " + ", ".join(f"{v:.6g}" for v in entries) + " kg*m^2 (std "
                     + ", ".join(f"{v:.2g}" for v in s[4:]) + ")")
        return "\n".join(lines)


def _samples(robot: Robot, trajectory, x, u):
    """``(xs, us)`` from a Trajectory or arrays, with their shapes checked against ``robot``."""
    if trajectory is not None:
        if x is not None or u is not None:
            raise ArgumentError("give a trajectory or the arrays x and u, not both")
        if not all(hasattr(trajectory, a) for a in ("x", "u", "meta")):
            raise SpacearmTypeError(f"trajectory must be a spacearm Trajectory, got {type(trajectory).__name__}")
        conserved = set(trajectory.meta.get("conserved", ()))
        if not {"P", "L_origin"} <= conserved:
            why = (" (in orbit the gravity gradient's tidal wrenches change it; run with gravity_gradient=False or "
                   "off orbit)" if trajectory.meta.get("balanced") else "")
            raise ArgumentError(f"identification needs a motion that conserves the momentum (P and L_origin: mode "
                                f"'floating'), but this trajectory ({trajectory.meta.get('mode')!r} mode) conserves "
                                f"only {sorted(conserved)}{why}")
        x, u = trajectory.x, trajectory.u
    if x is None or u is None:
        raise ArgumentError("identify_payload needs a trajectory, or the arrays x (K, 7+N) and u (K, 6+N)")
    xs, us = real_array(x, "x"), real_array(u, "u")  # the one array check: complex, object and text refused
    if xs.ndim != 2 or xs.shape[1] != robot.nx or us.ndim != 2 or us.shape[1] != robot.nu or len(xs) != len(us):
        raise ShapeError(f"x and u must have shapes (K, {robot.nx}) and (K, {robot.nu}) for the robot '{robot.name}' "
                         f"(N = {robot.n_dof}), got {xs.shape} and {us.shape}; the combined system must have the robot's "
                         "joints (a payload attached by a fixed joint adds none)")
    if not (np.all(np.isfinite(xs)) and np.all(np.isfinite(us))):
        from ..errors import NonFiniteError

        raise NonFiniteError("x and u must be finite")
    return xs, us


def _solve(a: np.ndarray, b: np.ndarray, scale: np.ndarray, threshold: float):
    """Least squares on the columns of ``a`` divided by ``scale``, by SVD, keeping the singular
    values above ``threshold``: ``(π, Cov(π) for unit row noise, singular values, rank, null space)``."""
    try:
        u, s, vt = np.linalg.svd(a / scale, full_matrices=False)
    except np.linalg.LinAlgError:
        raise SingularError("the least-squares problem of the identification has no solution (the SVD of the weighted regressor "
                            "did not converge): the recording holds too little motion of the grasp body") from None
    rank = int(np.sum(s > threshold))
    z = vt[:rank].T @ ((u[:, :rank].T @ b) / s[:rank])
    pi = z / scale
    # Cov(π) = D V_r S_r⁻² V_rᵀ D with D = diag(1/scale).
    half = (vt[:rank].T / s[:rank]) / scale[:, None]
    null = vt[rank:].T / scale[:, None]
    if null.size:
        null, _ = np.linalg.qr(null)
    return pi, half @ half.T, s, rank, null


def _lever_arm(robot: Robot, body: int, xs: np.ndarray) -> float:
    """RMS distance (m) of ``body``'s CM from the base CM over the samples; 1 m if zero (the
    payload on the base itself)."""
    d2 = [np.sum((robot.forward_kinematics(x).com_in_world[body] - x[:3]) ** 2) for x in xs]
    ell = float(np.sqrt(np.mean(d2)))
    return ell if ell > 0.0 else 1.0


def identify_payload(robot: Robot, trajectory=None, *, body, x=None, u=None, momentum=None,
                     rcond: float = DEFAULT_RCOND) -> PayloadEstimate:
    """Estimate the mass, CM and inertia of a rigid payload carried by ``body`` of ``robot``
    from a motion of the combined system (robot + payload) with no external wrench.

    Parameters
    ----------
    robot : Robot
        The known robot, without the payload.
    trajectory : Trajectory, optional
        A recorded motion of the combined system in a mode that conserves momentum
        (``"floating"``); or give ``x`` (K, 7+N) and ``u`` (K, 6+N) instead. The combined
        system has the robot's joints, so its states are the robot's.
    body : str or int
        The grasp body the payload is fixed to (e.g. the gripper link).
    momentum : array of 6, optional
        ``[P; L_origin]`` of robot + payload, if known; by default it is estimated too.
    rcond : float
        Relative singular-value threshold for identifiability ([`DEFAULT_RCOND`][spacearm.identify.estimate.DEFAULT_RCOND]).

    Returns
    -------
    PayloadEstimate
        π with its covariance, rank, null space and condition number, and the physical
        parameters (``mass``, ``com`` from the grasp body's CM in its axes, ``inertia`` about
        the payload's CM in the grasp body's axes) when all ten are identified.

    The method and the noise model are in the module docstring and ``docs/identification.md``.
    """
    if not isinstance(robot, Robot):
        raise SpacearmTypeError(f"robot must be a spacearm.Robot (the known robot, without the payload), got {type(robot).__name__}")
    g = robot.body_index(body)
    rcond = number(rcond, "rcond")
    if not 0.0 < rcond < 1.0:
        raise ArgumentError(f"rcond must be in (0, 1), got {rcond}")
    xs, us = _samples(robot, trajectory, x, u)
    k = len(xs)
    given = momentum is not None
    need = 2 if given else 3  # 6K rows against 10 unknowns (plus 6 for an unknown momentum)
    if k < need:
        raise ArgumentError(f"identification needs at least {need} samples{'' if given else ' (the momentum is estimated too)'}, got {k}")
    y = momentum_regressor(robot, g, xs, us)
    h_robot = robot_momentum(robot, xs, us)
    if given:
        from .._util.arrays import vector

        from .._util.arrays import finite

        h0 = finite(vector(momentum, "momentum", 6), "momentum")
        a, b = y, h0[None, :] - h_robot
    else:
        a, b = y - y.mean(axis=0), -(h_robot - h_robot.mean(axis=0))
    a, b = a.reshape(6 * k, 10), b.reshape(6 * k)
    if not np.any(a):
        raise SingularError(f"nothing to identify: the grasp body '{robot.body_names[g]}' does not move relative to the system over the "
                            f"{k} samples (the regressor{'' if given else ' less its mean'} is zero); record a motion of the arm")
    linear = np.tile(np.r_[np.ones(3, bool), np.zeros(3, bool)], k)

    # [m, h, Ī] = [m, ℓ h̃, ℓ² Ĩ]: the regressor's columns times 1, ℓ, ℓ² act on parameters in kg.
    ell = _lever_arm(robot, g, xs)
    scale = 1.0 / np.r_[1.0, ell, ell, ell, np.full(6, ell**2)]

    # Pass 1 (ordinary) gives the residual's scale on the linear and angular rows; pass 2 weights them.
    def threshold(weight):
        return rcond * np.linalg.norm(y.reshape(6 * k, 10) * weight[:, None] / scale, 2)

    pi, _, _, rank, _ = _solve(a, b, scale, threshold(np.ones(6 * k)))
    residual = a @ pi - b
    dof = max(6 * k - rank - (0 if given else 6), 1)
    inflation = 6 * k / dof
    floor = np.finfo(float).eps * (np.sqrt(np.mean(b**2)) + np.finfo(float).tiny)
    sigma = np.array([max(np.sqrt(np.mean(residual[rows] ** 2) * inflation), floor) for rows in (linear, ~linear)])
    weight = np.where(linear, 1.0 / sigma[0], 1.0 / sigma[1])
    pi, cov, s, rank, null = _solve(a * weight[:, None], b * weight, scale, threshold(weight))
    h_est = h0 if given else (h_robot + y @ pi).mean(axis=0)
    return PayloadEstimate(
        body=robot.body_names[g],
        parameters=pi,
        covariance=cov,
        momentum=np.array(h_est, dtype=float),
        momentum_estimated=not given,
        singular_values=s,
        rank=rank,
        null_space=null,
        condition_number=float(s[0] / s[-1]) if rank == 10 else float("inf"),
        noise_std=sigma,
        n_samples=k,
    )
