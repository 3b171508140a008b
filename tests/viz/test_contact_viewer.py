"""The viewer draws a contact run's contacts (docs/viewer.md, "Contact"; spacearm.viz.viewer):
read back from the saved HTML the way the browser reads it (the base64 msgpack commands decoded
by u-msgpack-python, quaternions turned into matrices by scipy) and checked against the run's
record ``contact_forces`` row by row: each key frame's contact points, the normal-force and
friction arrows' directions and lengths (one scale for both), the empty slots hidden, and the
free target's body at its recorded state."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

import spacearm
from spacearm.contact import ContactModel, Pair

pytest.importorskip("meshcat")
pytest.importorskip("umsgpack")
Rotation = pytest.importorskip("scipy.spatial.transform").Rotation

sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_viewer import _commands, _matrix, _objects, _tracks  # noqa: E402  (the CMG drawing test's readers)

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "contact"))
from test_contact_records import MU, bus_and_rock  # noqa: E402


@pytest.fixture(scope="module")
def contact_run(tmp_path_factory):
    bus, rock = bus_and_rock()
    q = Rotation.from_euler("z", 0.02).as_quat()
    s0 = np.concatenate([[0.67, 0.0, 0.0], q, [-0.4, 0.15, 0.0], [0.0, 0.3, -0.5]])
    contact = ContactModel(stiffness=2e4, damping=0.5, law="hunt_crossley", friction=MU, slip_velocity=1e-2,
                           pairs=[Pair("base", "target")])
    traj = spacearm.simulate(bus, 0.25, dt=5e-5, record_every=4, target=rock, target_state=s0, contact=contact)
    path = tmp_path_factory.mktemp("contact_viewer") / "contact.html"
    traj.view(path, fps=1000, target=rock)  # a key frame every 1 ms: ~40 in contact
    return traj, rock, _commands(path.read_text())


def _arrow(tracks, objects, root):
    """Origin, unit direction, total length (shaft + head) and visibility of an arrow, per key frame."""
    _, origin = tracks[f"{root}/shaft"]["position"]
    _, quat = tracks[f"{root}/shaft"]["quaternion"]
    _, shaft = tracks[f"{root}/shaft"]["scale"]
    _, head = tracks[f"{root}/head"]["scale"]
    height = objects[f"{root}/head/body"]["geometries"][0]["height"]
    direction = np.einsum("kij,j->ki", _matrix(quat), [0.0, 1.0, 0.0])
    shown = head[:, 1] > 1e-5
    length = np.where(shown, shaft[:, 1] * (shaft[:, 1] > 1e-5) + height * head[:, 1], 0.0)
    return origin, direction, length, shown


def test_contact_points_and_force_arrows_are_the_recorded_ones(contact_run):
    traj, _, cmds = contact_run
    objects, tracks = _objects(cmds), _tracks(cmds)
    rows = traj.contact_forces
    slots = sorted({int(p.split("/")[3]) for p in objects if p.startswith("/spacearm/contacts/")})
    assert slots == [0, 1]  # the slab meets both balls at once
    times, _ = tracks["/spacearm/contacts/0/point"]["position"]
    rel = traj.t - traj.t[0]
    samples = np.array([int(np.argmin(np.abs(rel - t))) for t in times])
    np.testing.assert_allclose(rel[samples], times, atol=1e-9)
    ratios, checked = [], 0
    for j in slots:
        root = f"/spacearm/contacts/{j}"
        _, point = tracks[f"{root}/point"]["position"]
        _, scale = tracks[f"{root}/point"]["scale"]
        n_origin, n_dir, n_len, n_shown = _arrow(tracks, objects, f"{root}/normal")
        f_origin, f_dir, f_len, f_shown = _arrow(tracks, objects, f"{root}/friction")
        for i, k in enumerate(samples):
            mine = rows[rows[:, 0] == k]
            if j >= len(mine):  # an empty slot is hidden, its arrows too
                assert scale[i].max() < 1e-5 and not n_shown[i] and not f_shown[i]
                continue
            row = mine[j]
            p, n, fn, f = row[3:6], row[6:9], row[9], row[10:13]
            ft = f - fn * n
            assert scale[i].min() == 1.0
            np.testing.assert_allclose(point[i], p, atol=1e-12)
            np.testing.assert_allclose(n_origin[i], p, atol=1e-12)
            np.testing.assert_allclose(f_origin[i], p, atol=1e-12)
            if fn > 1e-9:
                np.testing.assert_allclose(n_dir[i], n, atol=1e-9)
                ratios.append(n_len[i] / fn)
            if np.linalg.norm(ft) > 1e-3 * fn:
                np.testing.assert_allclose(f_dir[i], ft / np.linalg.norm(ft), atol=1e-9)
                ratios.append(f_len[i] / np.linalg.norm(ft))
            checked += 1
    assert checked > 20
    ratios = np.array(ratios)
    np.testing.assert_allclose(ratios, ratios[0], rtol=1e-9)  # one scale: metres of arrow per newton


def test_the_free_target_is_drawn_at_its_recorded_states(contact_run):
    traj, rock, cmds = contact_run
    tracks = _tracks(cmds)
    (node,) = [p for p in tracks if p.startswith("/spacearm/target/bodies/")]
    times, pos = tracks[node]["position"]
    _, quat = tracks[node]["quaternion"]
    rel = traj.t - traj.t[0]
    samples = np.array([int(np.argmin(np.abs(rel - t))) for t in times])
    s = traj["target"][samples]
    np.testing.assert_allclose(pos, s[:, :3], atol=1e-12)
    np.testing.assert_allclose(_matrix(quat), _matrix(s[:, 3:7]), atol=1e-12)


def test_without_the_target_model_a_note_says_it_is_not_drawn(contact_run):
    traj, _, _ = contact_run
    from spacearm.viz.viewer import trajectory_scene

    with pytest.warns(UserWarning, match="free target is not drawn"):
        scene = trajectory_scene(traj, fps=20)
    assert any("contact normal force" in text for _, text in scene.legend)
    bare = trajectory_scene(traj, fps=20, contacts=False, target=bus_and_rock()[1])
    assert not any(c.path.lower().startswith("/spacearm/contacts") for c in bare.commands() if type(c).__name__ == "SetObject")


def test_a_target_for_a_run_without_one_is_refused():
    from spacearm.errors import ArgumentError
    from spacearm.viz.viewer import trajectory_scene

    traj = spacearm.simulate(spacearm.presets.spatial6(), 0.02, dt=0.01)
    with pytest.raises(ArgumentError, match="has none"):
        trajectory_scene(traj, target=bus_and_rock()[1])
