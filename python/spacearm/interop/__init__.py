"""Interoperability with Pinocchio, MuJoCo, SPART and SpaceDyn: model export and convention converters.

One module per engine — [`pinocchio`][spacearm.interop.pinocchio], [`mujoco`][spacearm.interop.mujoco],
[`spart`][spacearm.interop.spart], [`spacedyn`][spacearm.interop.spacedyn] — over the shared model tree
and joint order of ``_common.py``; every public name is also here, ``spacearm.interop.<name>``.

spacearm, Pinocchio and MuJoCo describe the same free-flying multibody system with different
coordinates. This package builds the equivalent model in each engine and maps states, forces,
accelerations and mass matrices between the three layouts, so that a user (or a test) can
compute a quantity in one and compare it with the other.

Conventions (``docs/conventions.md``; every formula below was verified numerically by
``tests/interop/test_pinocchio.py``, ``tests/interop/test_mujoco.py`` and ``tests/interop/test_interop_spart.py``):

    spacearm   x = [r0, quat0 (x, y, z, w), q]          u = [v0 (𝒥), ω0 (𝒥), q̇]
    Pinocchio  q = [r0, quat0 (x, y, z, w), P_eᵀ q]      v = [R0ᵀ v0, R0ᵀ ω0, P_eᵀ q̇]
    MuJoCo     qpos = [r0, quat0 (w, x, y, z), P_eᵀ q]   qvel = [v0, R0ᵀ ω0, P_eᵀ q̇]
    SPART      R0, r0, qm = q                          u0 = [R0ᵀ ω0, v0], um = q̇
    SpaceDyn   R0 = r0, A0 = R0, q                      v0, w0 = ω0, qd = q̇

SPART and SpaceDyn are MATLAB libraries: their "state" is a set of separate arrays, returned
here as the named tuples [`SpartState`][spacearm.interop.SpartState] and [`SpaceDynState`][spacearm.interop.SpaceDynState]. Both put the base
frame at the base centre of mass and use a rotation matrix mapping base-frame vectors to the
inertial frame (SPART's ``R0``, SpaceDyn's ``A0``). SPART's base velocity ``u0`` puts the
angular velocity first, in the base frame, then the linear velocity of the base CM in the
inertial frame (its ``Velocities`` builds the base twist as ``t0 = blkdiag(R0, E) u0``);
SpaceDyn's ``v0`` and ``w0`` are both in the inertial frame, like spacearm's. Both number the
joints in the order of their robot description: a serial chain has spacearm's order, which these
converters keep (no permutation).

All three put the base frame origin at the base centre of mass (the exported models are built
that way), so the base "origin velocity" of each engine is the base CM velocity ``v0``.

``P_e`` is the N×N permutation from the engines' joint order to spacearm's. spacearm numbers
its degrees of freedom in link order, which is only *topological* (each link after its
parent); Pinocchio's recursive algorithms (their ``nvSubtree`` blocks) and MuJoCo's nested
body tree both need a *depth-first* order, so the exported models number the joints by a
depth-first traversal of the tree (children in link order). [`engine_dof_order`][spacearm.interop.engine_dof_order] gives it:
``q_engine = q[order]``. For a serial chain ``order`` is the identity.

With the block-diagonal matrices

    T_pin = blkdiag(R0, R0, P_e)        (u = T_pin v)
    T_mj  = blkdiag(E,  R0, P_e)        (u = T_mj qvel)

power invariance (``fᵀ u = τ_engineᵀ v_engine``) and the kinetic energy ``½ uᵀ H u`` give

    H = T M Tᵀ,     f = T τ_engine,     τ_engine = Tᵀ f,

and differentiating ``u = T v`` gives the accelerations:

- Pinocchio's base linear velocity ``R0ᵀ v0`` is in the *moving* base frame, so
  ``d/dt(R0ᵀ v0) = R0ᵀ (v̇0 − ω0 × v0)``:  ``u̇ = T_pin a + [ω0 × v0; 0; 0]`` and
  ``c = T_pin nle − H[:, :3] (ω0 × v0)``.
- MuJoCo's base linear velocity is already in 𝒥 and ``d/dt(R0ᵀ ω0) = R0ᵀ ω̇0`` (``ω0 × ω0 =
  0``): ``u̇ = T_mj qacc`` and ``c = T_mj qfrc_bias`` with no extra term.

Quantities that do not depend on the base-velocity coordinates (the generalized inertia
``H*``, the Generalized Jacobian ``J*``, momentum, kinetic energy) compare directly once the
joint order is mapped.

Pinocchio (``pip install pin``) and MuJoCo (``pip install mujoco``) are optional: they are
imported only inside the functions that need them.
"""

from . import mujoco, pinocchio, spacedyn, spart
from ._common import ROOT_JOINT, ROTATION_TOLERANCE, engine_dof_order  # noqa: F401  (the constants too, as before the split)
from .mujoco import *  # noqa: F401,F403  (each engine's module lists its public names once, in its __all__)
from .pinocchio import *  # noqa: F401,F403
from .spacedyn import *  # noqa: F401,F403
from .spart import *  # noqa: F401,F403

__all__ = ["engine_dof_order", *pinocchio.__all__, *mujoco.__all__, *spart.__all__, *spacedyn.__all__]
