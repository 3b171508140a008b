"""Replay of the core's tapes on CasADi ``SX`` symbols.

The Rust core records a function of the equations of motion by running its own recursions
(forward kinematics, ABA, RNEA, CRBA, the GJM reduction) once on a recording scalar
(``spacearm_core::math::tape``, ``spacearm_core::taped``): a flat list of nodes, each an input,
a constant, or a unary or binary operation on earlier nodes. ``function`` replays that
list on ``SX`` scalars, one ``SX.binary`` / ``SX.unary`` call per node, and wraps the result
in a ``casadi.Function`` with the core's input and output names (one that checks numeric
inputs before it evaluates, ``._checked``). Nothing of the physics is
written here: the graph is the core's arithmetic, operation for operation.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, List, Optional, Sequence

if TYPE_CHECKING:
    from .. import _core

# Operation codes of spacearm_core::math::tape::Op, by name (the core's values).
_INPUT, _CONST = 0, 1
_BINARY = {2: "OP_ADD", 3: "OP_SUB", 4: "OP_MUL", 5: "OP_DIV", 6: "OP_ATAN2"}
_UNARY = {16: "OP_NEG", 17: "OP_SQRT", 18: "OP_SIN", 19: "OP_COS", 20: "OP_TAN", 21: "OP_ASIN",
          22: "OP_ACOS", 23: "OP_ATAN", 24: "OP_EXP", 25: "OP_LOG", 26: "OP_FABS"}
_FIRST_UNARY = 16


def _casadi_codes(ca) -> List[Optional[int]]:
    """CasADi's operation code for each tape code (``None`` for inputs and constants)."""
    codes: List[Optional[int]] = [None] * (max(_UNARY) + 1)
    for table in (_BINARY, _UNARY):
        for code, name in table.items():
            codes[code] = getattr(ca, name)
    return codes


def tape(robot, name: str, body: Optional[int] = None, offset: Optional[Sequence[float]] = None) -> "_core.Tape":
    """The core's tape of the function ``name`` of ``robot`` (``_core.Model.tape``)."""
    return robot.core_model.tape(name, body, offset)


def replay(ca, recorded: "_core.Tape", inputs: Sequence[object]) -> List[object]:
    """The outputs of a tape (``SX`` matrices of the core's shapes) for the ``SX`` column
    vectors ``inputs`` (the tape's inputs in order)."""
    xs = ca.vertsplit(ca.vertcat(*inputs)) if inputs else []
    if len(xs) != recorded.n_inputs:
        raise AssertionError(f"the tape has {recorded.n_inputs} inputs, {len(xs)} given")
    codes = _casadi_codes(ca)
    binary, unary, sx = ca.SX.binary, ca.SX.unary, ca.SX
    constants = recorded.constants.tolist()
    nodes: List[object] = []
    push = nodes.append
    # CasADi's simplification on the fly rewrites some expressions as they are built (e.g.
    # (a + b) − b → a), which changes the last digits and, on these graphs, adds instructions:
    # off during the replay, so that the graph is the core's arithmetic exactly. (The option
    # is global to CasADi: SX built on another thread during a replay is not simplified either,
    # which changes nothing but the size of its graph.)
    simplifying = ca.GlobalOptions.getSimplificationOnTheFly()
    ca.GlobalOptions.setSimplificationOnTheFly(False)
    try:
        for op, (a, b) in zip(recorded.ops.tolist(), recorded.args.tolist()):
            if op >= _FIRST_UNARY:
                push(unary(codes[op], nodes[a]))
            elif op > _CONST:
                push(binary(codes[op], nodes[a], nodes[b]))
            elif op == _INPUT:
                push(xs[a])
            else:
                push(sx(constants[a]))
    finally:
        ca.GlobalOptions.setSimplificationOnTheFly(simplifying)
    values = [nodes[k] for k in recorded.outputs.tolist()]
    outputs, start = [], 0
    for _, rows, cols in recorded.outputs_shapes:
        part = values[start:start + rows * cols]
        start += rows * cols
        outputs.append(ca.reshape(ca.vertcat(*part), rows, cols))
    return outputs


def function(ca, robot, name: str, body: Optional[int] = None, offset: Optional[Sequence[float]] = None):
    """``casadi.Function`` ``name`` of ``robot``: fresh ``SX`` symbols for the core's inputs,
    the core's tape replayed on them, the core's names for inputs and outputs."""
    recorded = tape(robot, name, body, offset)
    symbols = [ca.SX.sym(n, k) for n, k in recorded.inputs]
    outputs = replay(ca, recorded, symbols)
    from ._checked import checked_function

    return checked_function(ca, name, symbols, outputs, [n for n, _ in recorded.inputs], [n for n, _, _ in recorded.outputs_shapes])
