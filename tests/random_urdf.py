"""Random URDF documents: trees with every supported joint type, rotated inertial frames,
off-origin base inertials, fixed joints anywhere (including fixed leaves without inertials),
and random joint origins. Used by the Pinocchio comparison and by the fuzz test."""

from __future__ import annotations

import numpy as np

JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed")


def _vec(v) -> str:
    return " ".join(repr(float(x)) for x in v)


def _inertia(rng) -> dict:
    """A physical inertia (principal moments obeying the triangle inequality) in random axes."""
    a, b, c = rng.uniform(0.005, 0.25, size=3)  # second moments along principal axes
    moments = np.array([b + c, a + c, a + b])
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    i = q @ np.diag(moments) @ q.T
    return {"ixx": i[0, 0], "iyy": i[1, 1], "izz": i[2, 2], "ixy": i[0, 1], "ixz": i[0, 2], "iyz": i[1, 2]}


def _inertial(rng) -> str:
    i = _inertia(rng)
    attrs = " ".join(f'{k}="{float(v)!r}"' for k, v in i.items())
    return (f'    <inertial>\n      <origin xyz="{_vec(rng.uniform(-0.3, 0.3, 3))}" rpy="{_vec(rng.uniform(-3, 3, 3))}"/>\n'
            f'      <mass value="{float(rng.uniform(0.5, 10.0))!r}"/>\n      <inertia {attrs}/>\n    </inertial>\n')


def random_urdf(seed: int, n_links: int = 7) -> str:
    """A valid URDF tree of ``n_links + 1`` links (root ``root``) from a seed."""
    rng = np.random.default_rng([11, seed])
    parts = ['<?xml version="1.0"?>', f'<robot name="random{seed}">']
    parts.append(f'  <link name="root">\n{_inertial(rng)}  </link>')
    names = ["root"]
    for k in range(1, n_links + 1):
        kind = JOINT_TYPES[rng.integers(len(JOINT_TYPES))]
        parent = names[rng.integers(len(names))]
        name = f"l{k}"
        # fixed leaves may be massless frames (tool flanges); every moving link has mass
        inertial = "" if (kind == "fixed" and rng.random() < 0.4) else _inertial(rng)
        parts.append(f'  <link name="{name}">\n{inertial}  </link>')
        limit = ""
        if kind in ("revolute", "prismatic"):
            limit = f'\n    <limit lower="-1.5" upper="1.5" effort="{float(rng.uniform(1, 100))!r}" velocity="{float(rng.uniform(0.5, 3))!r}"/>'
        elif kind == "continuous":
            limit = '\n    <limit effort="10" velocity="2"/>'
        axis = rng.normal(size=3)
        parts.append(
            f'  <joint name="j{k}" type="{kind}">\n    <parent link="{parent}"/>\n    <child link="{name}"/>\n'
            f'    <origin xyz="{_vec(rng.uniform(-0.5, 0.5, 3))}" rpy="{_vec(rng.uniform(-3, 3, 3))}"/>\n'
            f'    <axis xyz="{_vec(axis / np.linalg.norm(axis))}"/>{limit}\n  </joint>'
        )
        names.append(name)
    parts.append("</robot>")
    return "\n".join(parts) + "\n"
