"""Gymnasium environments of spacearm (extra ``rl``): reach, capture and detumble with a
free-floating space manipulator, and a vectorized reach stepped in one native batch call.

Importing ``spacearm.gym`` registers ``spacearm/Reach-v0`` ([`ReachEnv`][spacearm.gym.ReachEnv]),
``spacearm/Capture-v0`` ([`CaptureEnv`][spacearm.gym.CaptureEnv]), ``spacearm/Detumble-v0``
([`DetumbleEnv`][spacearm.gym.DetumbleEnv]) and ``spacearm/ContactCapture-v0``
([`ContactCaptureEnv`][spacearm.gym.ContactCaptureEnv]: a gripper closing on a tumbling handle by
contact, rewarded by the core's grasp outcome) with ``gymnasium.register``; ``gymnasium.make_vec("spacearm/Reach-v0",
num_envs=8, vectorization_mode="vector_entry_point")`` gives [`ReachVectorEnv`][spacearm.gym.ReachVectorEnv].
Every step's dynamics run in the core (``Simulator``'s RK4 stepper, the ``BatchSimulator`` of
the vector env, the target's free-body propagation, the grasp impulse); this package holds the
tasks: observations, actions, rewards, resets and the frames of ``render()`` (docs/rl.md).
"""

from __future__ import annotations

import inspect

from .._util.optional import require

_gymnasium = require("gymnasium", "the Gymnasium environments (spacearm.gym)")

from .capture import CaptureEnv  # noqa: E402
from .contact_capture import ContactCaptureEnv  # noqa: E402
from .detumble import DetumbleEnv  # noqa: E402
from .reach import ReachEnv, ReachTask  # noqa: E402
from .vector import ReachVectorEnv  # noqa: E402

__all__ = ["ReachEnv", "ReachTask", "CaptureEnv", "ContactCaptureEnv", "DetumbleEnv", "ReachVectorEnv", "make_vec", "ENV_IDS"]

#: The registered environment ids.
ENV_IDS = ("spacearm/Reach-v0", "spacearm/Capture-v0", "spacearm/Detumble-v0", "spacearm/ContactCapture-v0")


def make_vec(num_envs: int = 8, *, threads=None, **task) -> ReachVectorEnv:
    """``num_envs`` Reach copies stepped in one native batch call per step
    ([`ReachVectorEnv`][spacearm.gym.ReachVectorEnv])."""
    return ReachVectorEnv(num_envs, threads=threads, **task)


def _register() -> None:
    # The episode limits are the envs' own defaults (their max_episode_steps), registered so that
    # `spec.max_episode_steps` says them and gymnasium's TimeLimit wrapper agrees.
    def limit(cls):
        return inspect.signature(cls).parameters["max_episode_steps"].default

    entries = {
        "spacearm/Reach-v0": ("spacearm.gym.reach:ReachEnv", "spacearm.gym.vector:ReachVectorEnv", limit(ReachTask)),
        "spacearm/Capture-v0": ("spacearm.gym.capture:CaptureEnv", None, limit(CaptureEnv)),
        "spacearm/Detumble-v0": ("spacearm.gym.detumble:DetumbleEnv", None, limit(DetumbleEnv)),
        "spacearm/ContactCapture-v0": ("spacearm.gym.contact_capture:ContactCaptureEnv", None, limit(ContactCaptureEnv)),
    }
    for env_id, (entry, vector_entry, steps) in entries.items():
        if env_id not in _gymnasium.registry:
            _gymnasium.register(id=env_id, entry_point=entry, vector_entry_point=vector_entry, max_episode_steps=steps)


_register()
