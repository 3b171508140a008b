"""Fuzz the array boundary of the per-state methods: random memory layouts, dtypes and batch
sizes of valid arguments, and random invalid arguments; count the outcomes.

    python scripts/fuzz_array_layouts.py [--calls 20000] [--seed 0]

A valid call is "right" when it equals, bit for bit, the call on the canonical C-ordered
float64 copy of the same values, "WRONG" when it returns something else, "refused" when it
raises (a valid input must not be refused). An invalid call is "refused" (a SpacearmError) or
"OTHER ERROR" (any other exception) or "ACCEPTED". The property tests
(tests/model/test_array_properties.py) check the same in CI on a bounded, seeded sample; this
script is for the larger rounds quoted in closing notes.
"""

import argparse
import collections
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "model"))

import spacearm  # noqa: E402
from test_array_layouts import METHODS  # noqa: E402

ROBOT = spacearm.presets.spatial6()
WIDTH = {"x": ROBOT.nx, "u": ROBOT.nu, "du": ROBOT.nu, "f": ROBOT.nu, "tau": ROBOT.n_dof, "base_wrench": 6,
         "qd": ROBOT.n_dof, "P": 3, "L": 3}
DTYPES = ["<f8", ">f8", "<f4", ">f4", "<i8", ">i4", "|u1", "|b1", "<f2"]


def values(name, rows, rng):
    shape = (WIDTH[name],) if rows is None else (rows, WIDTH[name])
    if name != "x":
        return rng.normal(size=shape)
    x = rng.normal(size=shape)
    quat = x[..., 3:7]
    x[..., 3:7] = quat / np.linalg.norm(quat, axis=-1, keepdims=True)
    return x


def laid_out(v, rng, other_dtypes):
    dtype = np.dtype(rng.choice(DTYPES if other_dtypes else DTYPES[:2]))
    order = rng.choice(["C", "F"])
    steps = [int(rng.choice([1, 2, 3, -1, -2])) for _ in range(v.ndim)]
    offset = int(rng.choice([0, 0, 1, 3, 8]))
    big_shape = tuple(n * abs(s) for n, s in zip(v.shape, steps))
    buf = np.zeros(int(np.prod(big_shape)) * dtype.itemsize + offset, dtype=np.uint8)
    big = np.ndarray(big_shape, dtype=dtype, buffer=buf.data, offset=offset, order=order)
    view = big[tuple(slice(None, None, s) for s in steps)]
    view[...] = v.astype(dtype)
    if rng.random() < 0.3:
        view.setflags(write=False)
    return view


def call(method, names, keywords, vals):
    args = [vals[k] for k in names if k not in keywords]
    return getattr(ROBOT, method)(*args, **{k: vals[k] for k in keywords})


def parts(r):
    return [np.asarray(p) for p in r] if isinstance(r, tuple) else [np.asarray(r)]


def bad(kind, good):
    return {
        "extra axis": lambda: good[None, None], "wrong width": lambda: good[..., :-1], "complex": lambda: good + 1j,
        "object": lambda: good.astype(object), "strings": lambda: good.astype(str), "ragged": lambda: [list(good.ravel()), [1.0]],
    }[kind]()


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--calls", type=int, default=20000)
    p.add_argument("--seed", type=int, default=0)
    a = p.parse_args()
    rng = np.random.default_rng(a.seed)
    counts = collections.Counter()
    for k in range(a.calls):
        method, names, keywords = METHODS[rng.integers(len(METHODS))]
        rows = [None, 1, 2, 5][rng.integers(4)]
        vals = {n: values(n, rows if rows is not None and rng.random() < 0.7 else None, rng) for n in names}
        if rows is not None:
            vals["x"] = values("x", rows, rng)
        laid = {n: laid_out(v, rng, n != "x") for n, v in vals.items()}
        if k % 4 == 3:  # an invalid argument
            victim = names[rng.integers(len(names))]
            kinds = ["extra axis", "wrong width", "complex", "object", "strings", "ragged"]
            laid[victim] = bad(kinds[rng.integers(len(kinds))], np.asarray(laid[victim], dtype=float))
            try:
                call(method, names, keywords, laid)
                counts["invalid: ACCEPTED"] += 1
            except spacearm.SpacearmError:
                counts["invalid: refused"] += 1
            except Exception:  # noqa: BLE001 - counted, the point of the fuzzer
                counts["invalid: OTHER ERROR"] += 1
            continue
        canonical = {n: np.array(v, dtype=np.float64, order="C") for n, v in laid.items()}
        expected = parts(call(method, names, keywords, canonical))
        try:
            got = parts(call(method, names, keywords, laid))
        except Exception:  # noqa: BLE001
            counts["valid: refused"] += 1
            continue
        same = all(g.shape == e.shape and np.array_equal(g, e) for g, e in zip(got, expected))
        counts["valid: right" if same else "valid: WRONG"] += 1
    for key in sorted(counts):
        print(f"{key:24s} {counts[key]:7d}")
    print(f"{'calls':24s} {a.calls:7d}")
    return 1 if counts["valid: WRONG"] or counts["valid: refused"] or counts["invalid: OTHER ERROR"] or counts["invalid: ACCEPTED"] else 0


if __name__ == "__main__":
    sys.exit(main())
