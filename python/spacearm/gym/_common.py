"""What the three environments share: argument checks, the action scaling, the inertia
randomization (the campaign's perturbations, reused) and the RGB frame.

Nothing here computes dynamics or kinematics: the states come from the core's stepper, the
poses from the robot's core kinematics, the plant perturbation from the core's
``perturbed_model``."""

from __future__ import annotations

from typing import Optional

import numpy as np

from .._util.arrays import count, positive_number  # noqa: F401 - count: the one count rule, used by the envs
from ..campaign import scenario as _scenario
from ..campaign.perturbation import Perturbations
from ..errors import ArgumentError, NonFiniteError, SimulationError, SpacearmTypeError

#: The render modes every environment supports.
RENDER_MODES = ("rgb_array",)


def positive(value, name: str) -> float:
    """A finite number > 0, else ArgumentError."""
    return positive_number(value, name)


def non_negative(value, name: str) -> float:
    """A finite number >= 0, else ArgumentError."""
    return positive_number(value, name, zero_allowed=True)


def actions(value, shape: tuple, what: str = "action") -> np.ndarray:
    """An action (``shape`` ``(N,)``) or a batch of actions (``(B, N)``) as float64: real numbers
    (not text, complex or objects: a ``SpacearmTypeError``) of exactly ``shape`` (else an
    ``ArgumentError``, as every other wrong argument of an environment), finite (else a ``NonFiniteError`` naming the copy and the entry); each
    names what was given and what is expected."""
    expected = f"real numbers (float32 in [-1, 1]) of shape {shape}"
    try:
        arr = np.asarray(value)
    except (TypeError, ValueError):
        raise ArgumentError(f"{what} must be {expected}, got {type(value).__name__} {value!r:.80}") from None
    if arr.dtype.kind not in "biuf":
        got = f"{type(value).__name__} {value!r:.80}" if arr.ndim == 0 else f"an array of dtype {arr.dtype}"
        raise SpacearmTypeError(f"{what} must be {expected}, got {got}")
    if arr.shape != tuple(shape):
        raise ArgumentError(f"{what} must be {expected}, got shape {arr.shape}")
    arr = np.asarray(arr, dtype=np.float64)
    bad = ~np.isfinite(arr)
    if bad.any():
        where = np.argwhere(bad)[0]
        if arr.ndim == 2:
            raise NonFiniteError(f"{what} of copy {int(where[0])} must be finite, but entry {int(where[1])} is {arr[tuple(where)]}")
        raise NonFiniteError(f"{what} must be finite, but entry {int(where[0])} is {arr[tuple(where)]}")
    return arr


def check_finite(states: np.ndarray, what: str) -> np.ndarray:
    """``states`` ``(B, dim)`` if every value is finite, else a SimulationError naming the copy."""
    bad = ~np.all(np.isfinite(states), axis=1)
    if bad.any():
        raise SimulationError(f"{what}: copy {int(np.flatnonzero(bad)[0])} diverged (a non-finite state); "
                              "lower max_torque or dt, or max_joint_rate")
    return states


def check_render_mode(render_mode: Optional[str]) -> Optional[str]:
    if render_mode is not None and render_mode not in RENDER_MODES:
        raise ArgumentError(f"render_mode must be None or one of {list(RENDER_MODES)}, got {render_mode!r}")
    return render_mode


def boxes(observations: int, actions: int) -> tuple:
    """``(observation_space, action_space)`` of an environment: ``observations`` unbounded
    float64 entries, ``actions`` float32 entries in [-1, 1] (each scaled by the env)."""
    from .._util.optional import require

    spaces = require("gymnasium", "the Gymnasium environments (spacearm.gym)").spaces
    return (spaces.Box(-np.inf, np.inf, shape=(observations,), dtype=np.float64),
            spaces.Box(-1.0, 1.0, shape=(actions,), dtype=np.float32))


#: The time (s) in which a full action spins a joint alone from rest up to ``max_joint_rate``
#: with ``max_torque="auto"``.
AUTO_RAMP_TIME = 1.0


def torque_scale(robot, max_torque, dofs=None, *, max_joint_rate: float = 3.0) -> np.ndarray:
    """The torque (N·m, or N for a prismatic joint) that an action of 1 commands on each dof of
    ``dofs`` (default: all): ``max_torque`` (a number or one per dof); ``"auto"``:
    ``H_ii(x0) · max_joint_rate / AUTO_RAMP_TIME`` (``H_ii`` the joint's diagonal element of the
    core's mass matrix at the neutral configuration: a full action brings that joint alone to
    ``max_joint_rate`` in about a second, whatever its size); None: the joint's finite effort
    limit (an error where a joint has none)."""
    dofs = list(range(robot.n_dof)) if dofs is None else list(dofs)
    effort = {link.dof: link.limits.effort for link in robot.description.links if link.dof is not None}
    if isinstance(max_torque, str):
        if max_torque != "auto":
            raise ArgumentError(f"max_torque must be 'auto', None, a number or one per joint, got {max_torque!r}")
        h = np.diag(np.asarray(robot.mass_matrix(robot.neutral_configuration()), dtype=float))[6:]
        scale = h[dofs] * float(max_joint_rate) / AUTO_RAMP_TIME
    elif max_torque is None:
        scale = np.array([effort[d] for d in dofs], dtype=float)
        missing = [robot.joint_names[d] for d, s in zip(dofs, scale) if not np.isfinite(s)]
        if missing:
            raise ArgumentError(f"max_torque=None takes each joint's effort limit, but joints {missing} have none; give max_torque")
    else:
        scale = np.broadcast_to(np.asarray(max_torque, dtype=float), (len(dofs),)).copy() if np.ndim(max_torque) == 0 else np.asarray(max_torque, dtype=float)
        if scale.shape != (len(dofs),):
            raise ArgumentError(f"max_torque must be a number or {len(dofs)} numbers (one per actuated joint), got shape {scale.shape}")
    if not np.all(np.isfinite(scale) & (scale > 0)):
        raise ArgumentError(f"the torque scales must be finite and > 0, got {scale}")
    return scale


def check_randomization(randomize) -> Optional[Perturbations]:
    if randomize is None or randomize is False:
        return None
    if randomize is True:
        return Perturbations()
    if not isinstance(randomize, Perturbations):
        raise ArgumentError(f"randomize must be None, True (the default spacearm.campaign.Perturbations) or a Perturbations, got {type(randomize).__name__}")
    return randomize


def randomized_plant(nominal, perturbations: Optional[Perturbations], rng: np.random.Generator):
    """The plant of one episode: ``nominal`` itself, or (with ``perturbations``) the campaign's
    perturbed plant of one draw (``spacearm.campaign.scenario.plant``: the core's
    ``perturbed_model`` and the payload), drawn from a seed taken from ``rng``."""
    if perturbations is None:
        return nominal, None
    params = perturbations.draw(int(rng.integers(2**63 - 1)), 0)
    return _scenario.plant(nominal, params), params


class Frame:
    """An offscreen matplotlib (Agg) 3-D view that draws a robot state as an RGB array: the
    base as its equivalent box, the arm as segments (``spacearm.viz.animation``'s, from the
    core's kinematics), and marked points (goal, target)."""

    def __init__(self, robot, *, size: int = 320, half_width: float = 3.0):
        from .._util.optional import require

        self._Figure = require("matplotlib.figure", "render()").Figure
        self._Canvas = require("matplotlib.backends.backend_agg", "render()").FigureCanvasAgg
        self._Poly = require("mpl_toolkits.mplot3d.art3d", "render()").Poly3DCollection
        from ..viz.animation import equivalent_box

        self.robot = robot
        self.size = int(size)
        self.half = float(half_width)
        base = robot.description.base
        self.sides, self.axes = equivalent_box(base.mass, base.inertia)

    def rgb(self, x, points=(), title: str = "", boxes=()) -> np.ndarray:
        """``(size, size, 3)`` uint8 of configuration ``x``; ``points``: ``(xyz, color)``;
        ``boxes``: ``(centre, rotation, sides, axes, color)`` of other bodies (a target)."""
        from ..viz.animation import arm_segments, box_faces

        robot = self.robot
        kin = robot.forward_kinematics(x)
        dpi = 80
        fig = self._Figure(figsize=(self.size / dpi, self.size / dpi), dpi=dpi)
        canvas = self._Canvas(fig)
        ax = fig.add_subplot(projection="3d")
        c = np.asarray(x[:3], dtype=float)
        for set_lim, k in ((ax.set_xlim, 0), (ax.set_ylim, 1), (ax.set_zlim, 2)):
            set_lim(c[k] - self.half, c[k] + self.half)
        ax.set_box_aspect((1, 1, 1))
        ax.tick_params(labelsize=5)
        ax.add_collection3d(self._Poly(box_faces(c, kin.body_to_world[0], self.sides, self.axes), facecolor="silver",
                                       edgecolor="dimgray", alpha=0.4, linewidths=0.5))
        for centre, rot, sides, axes, color in boxes:
            ax.add_collection3d(self._Poly(box_faces(centre, rot, sides, axes), facecolor=color, edgecolor="dimgray", alpha=0.4, linewidths=0.5))
        for a, b in arm_segments(robot, x, robot.wheel_dofs):
            ax.plot([a[0], b[0]], [a[1], b[1]], [a[2], b[2]], "-o", color="C0", lw=2, ms=2)
        for p, color in points:
            ax.plot([p[0]], [p[1]], [p[2]], "o", color=color, ms=5)
        if title:
            ax.set_title(title, fontsize=7)
        canvas.draw()
        return np.asarray(canvas.buffer_rgba())[..., :3].copy()
