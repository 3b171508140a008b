//! A recording scalar: the algorithms run on [`Var`] write the operations they perform onto a
//! tape (a flat list of inputs, constants and unary/binary operations), which another system
//! can replay on its own symbols. `spacearm.casadi` replays the tapes of the equations of
//! motion on CasADi `SX` scalars, so that its CasADi `Function`s come from the same recursions
//! as the numbers (docs/optimal-control.md, docs/architecture.md).
//!
//! # What a tape holds
//!
//! A [`Var`] is a value and an index: the index of the tape node that computes it, or
//! [`CONSTANT`] for a number that depends on no input. Arithmetic between constants is folded
//! on the spot (with the same `f64` operations as the `f64` path, so those numbers are the
//! core's to the bit); an operation with at least one recorded operand appends a node. Exact
//! identities with a constant operand are simplified (`x + 0`, `x · 1`, `x · 0`, `0 / x`,
//! `x / 1`), which is where the structural zeros of the spatial algebra (the zero blocks of a
//! spatial inertia, the zero angular part of a prismatic joint's motion subspace) disappear
//! from the tape. [`Recording::finish`] keeps only the nodes the outputs depend on.
//!
//! # Branches: one path, chosen so that it is every state's path
//!
//! A tape records one path through the code. Every `Var` therefore also carries its value at
//! the state the recording was made at (the *nominal* state), and comparisons (`<`, `>`,
//! `max`, `try_sqrt`'s sign test, the singularity tests of the algorithms) read those nominal
//! values. That is sound because the branches of the recorded algorithms do not depend on the
//! state:
//!
//! * the shortcuts of the algorithms test for *structural* zeros only:
//!   [`crate::math::scalar::Real::is_exactly_zero`] and `num_traits::Zero::is_zero` are true
//!   only for the constant zero, never for a recorded value that happens to be zero at the
//!   nominal state (so a joint at `q = 0` still records its rotation, and nalgebra's
//!   `beta == 0` tests see constants);
//! * the remaining value tests are validity checks — the articulated inertia `D > 0` of ABA,
//!   the positive pivots of a Cholesky factorization of a positive-definite inertia, the
//!   non-singular Schur complement of `H0` — true at every state of a valid model, so the
//!   nominal state takes the branch every state takes;
//! * [`PartialEq`] is structural (the same node, or equal constants), so `a == b` is never
//!   true by numerical coincidence at the nominal state.
//!
//! The tests (`crates/spacearm-core/tests/taped.rs`, `tests/optimal_control/`) replay each
//! tape at random states on both sides of the branches the code has — joints exactly at zero
//! and not, attitudes with either sign of the quaternion's scalar part, the identity attitude,
//! quaternions of other norms — and compare with the `f64` path.
//!
//! Operations the recursions do not use (`floor`, `sinh`, `%`, ...) panic with a message
//! saying so rather than record something wrong.

use std::cell::RefCell;
use std::collections::HashMap;
use std::fmt;
use std::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Rem, RemAssign, Sub, SubAssign};

use approx::{AbsDiffEq, RelativeEq, UlpsEq};
use num_traits::{FromPrimitive, Num, One, Signed, Zero};
use simba::scalar::{SubsetOf, SupersetOf};

use crate::math::scalar::Real;

/// The index of a [`Var`] that is a constant (depends on no input).
pub const CONSTANT: u32 = u32::MAX;

/// Operation codes of a tape node (the values of [`Tape::ops`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub enum Op {
    /// Input number `a` (`args[i][0]`).
    Input = 0,
    /// The constant `constants[a]`.
    Const = 1,
    /// `a + b`.
    Add = 2,
    /// `a − b`.
    Sub = 3,
    /// `a · b`.
    Mul = 4,
    /// `a / b`.
    Div = 5,
    /// `atan2(a, b)` (`a` the ordinate, as `f64::atan2`).
    Atan2 = 6,
    /// `−a`.
    Neg = 16,
    /// `√a`.
    Sqrt = 17,
    /// `sin a`.
    Sin = 18,
    /// `cos a`.
    Cos = 19,
    /// `tan a`.
    Tan = 20,
    /// `asin a`.
    Asin = 21,
    /// `acos a`.
    Acos = 22,
    /// `atan a`.
    Atan = 23,
    /// `exp a`.
    Exp = 24,
    /// `ln a`.
    Ln = 25,
    /// `|a|`.
    Abs = 26,
}

impl Op {
    /// `true` for the operations with two operands.
    pub fn is_binary(self) -> bool {
        matches!(self, Op::Add | Op::Sub | Op::Mul | Op::Div | Op::Atan2)
    }

    fn from_u8(code: u8) -> Op {
        match code {
            0 => Op::Input,
            1 => Op::Const,
            2 => Op::Add,
            3 => Op::Sub,
            4 => Op::Mul,
            5 => Op::Div,
            6 => Op::Atan2,
            16 => Op::Neg,
            17 => Op::Sqrt,
            18 => Op::Sin,
            19 => Op::Cos,
            20 => Op::Tan,
            21 => Op::Asin,
            22 => Op::Acos,
            23 => Op::Atan,
            24 => Op::Exp,
            25 => Op::Ln,
            26 => Op::Abs,
            _ => unreachable!("no tape operation has the code {code}"),
        }
    }

    /// The operation on `f64` values (`b` unused for unary operations).
    #[inline]
    fn apply(self, a: f64, b: f64) -> f64 {
        match self {
            Op::Input | Op::Const => unreachable!("inputs and constants are not operations"),
            Op::Add => a + b,
            Op::Sub => a - b,
            Op::Mul => a * b,
            Op::Div => a / b,
            Op::Atan2 => a.atan2(b),
            Op::Neg => -a,
            Op::Sqrt => a.sqrt(),
            Op::Sin => a.sin(),
            Op::Cos => a.cos(),
            Op::Tan => a.tan(),
            Op::Asin => a.asin(),
            Op::Acos => a.acos(),
            Op::Atan => a.atan(),
            Op::Exp => a.exp(),
            Op::Ln => a.ln(),
            Op::Abs => a.abs(),
        }
    }
}

/// A recorded scalar: its value at the nominal state and the tape node computing it
/// ([`CONSTANT`] for a constant). `Copy`, so the generic algorithms use it like `f64`.
#[derive(Clone, Copy)]
pub struct Var {
    value: f64,
    id: u32,
}

#[derive(Default)]
struct Buffer {
    active: bool,
    ops: Vec<Op>,
    args: Vec<[u32; 2]>,
    values: Vec<f64>,
    constants: Vec<f64>,
    constant_nodes: HashMap<u64, u32>,
    n_inputs: u32,
}

thread_local! {
    static TAPE: RefCell<Buffer> = RefCell::new(Buffer::default());
}

impl Buffer {
    fn push(&mut self, op: Op, a: u32, b: u32, value: f64) -> u32 {
        assert!(self.active, "a tape variable (spacearm_core::math::tape::Var) was used outside a Recording");
        let id = u32::try_from(self.ops.len()).ok().filter(|&i| i < CONSTANT).expect("the tape has more than 2³² − 1 nodes");
        self.ops.push(op);
        self.args.push([a, b]);
        self.values.push(value);
        id
    }

    /// The node of an operand (a constant gets one node per distinct value).
    fn node(&mut self, v: Var) -> u32 {
        if v.id != CONSTANT {
            return v.id;
        }
        if let Some(&id) = self.constant_nodes.get(&v.value.to_bits()) {
            return id;
        }
        let k = self.constants.len() as u32;
        self.constants.push(v.value);
        let id = self.push(Op::Const, k, 0, v.value);
        self.constant_nodes.insert(v.value.to_bits(), id);
        id
    }
}

fn record(op: Op, a: Var, b: Var, value: f64) -> Var {
    TAPE.with(|t| {
        let mut t = t.borrow_mut();
        let ia = t.node(a);
        let ib = if op.is_binary() { t.node(b) } else { 0 };
        Var { value, id: t.push(op, ia, ib, value) }
    })
}

impl Var {
    /// A constant.
    #[inline]
    pub const fn constant(value: f64) -> Var {
        Var { value, id: CONSTANT }
    }

    /// `true` for a constant.
    #[inline]
    pub fn is_constant(self) -> bool {
        self.id == CONSTANT
    }

    /// The value at the nominal state of the recording.
    #[inline]
    pub fn nominal(self) -> f64 {
        self.value
    }

    #[inline]
    fn is_const(self, c: f64) -> bool {
        self.id == CONSTANT && self.value == c
    }

    fn unary(self, op: Op) -> Var {
        let value = op.apply(self.value, 0.0);
        if self.is_constant() {
            return Var::constant(value);
        }
        record(op, self, self, value)
    }

    fn binary(self, op: Op, other: Var) -> Var {
        let value = op.apply(self.value, other.value);
        if self.is_constant() && other.is_constant() {
            return Var::constant(value);
        }
        // Exact identities with a constant operand.
        match op {
            Op::Add if self.is_const(0.0) => return other,
            Op::Add | Op::Sub if other.is_const(0.0) => return self,
            Op::Sub if self.is_const(0.0) => return other.unary(Op::Neg),
            Op::Mul if self.is_const(0.0) || other.is_const(0.0) => return Var::constant(0.0),
            Op::Mul if self.is_const(1.0) => return other,
            Op::Mul | Op::Div if other.is_const(1.0) => return self,
            Op::Mul if self.is_const(-1.0) => return other.unary(Op::Neg),
            Op::Mul if other.is_const(-1.0) => return self.unary(Op::Neg),
            Op::Div if self.is_const(0.0) => return Var::constant(0.0),
            _ => {}
        }
        record(op, self, other, value)
    }
}

/// A tape under way on this thread: create one, make its inputs with [`Recording::input`], run
/// the algorithm on them, and [`Recording::finish`] with the outputs. One recording at a time
/// per thread; dropping it (an error on the way) discards the tape.
pub struct Recording {
    // Not Send: the tape is thread-local.
    _thread: std::marker::PhantomData<*const ()>,
}

impl Recording {
    /// Start recording on this thread. Panics if a recording is already under way here.
    pub fn start() -> Recording {
        TAPE.with(|t| {
            let mut t = t.borrow_mut();
            assert!(!t.active, "a Recording is already under way on this thread");
            *t = Buffer { active: true, ..Buffer::default() };
        });
        Recording { _thread: std::marker::PhantomData }
    }

    /// The next input (numbered in order of creation from 0), with its nominal value.
    pub fn input(&mut self, nominal: f64) -> Var {
        TAPE.with(|t| {
            let mut t = t.borrow_mut();
            let k = t.n_inputs;
            t.n_inputs += 1;
            Var { value: nominal, id: t.push(Op::Input, k, 0, nominal) }
        })
    }

    /// `n` inputs with the nominal values `nominal` (length `n`).
    pub fn inputs(&mut self, nominal: &[f64]) -> Vec<Var> {
        nominal.iter().map(|&v| self.input(v)).collect()
    }

    /// End the recording: the tape of `outputs`, reduced to the nodes they depend on (inputs
    /// are all kept, in order).
    pub fn finish(self, outputs: &[Var]) -> Tape {
        let buffer = TAPE.with(|t| std::mem::take(&mut *t.borrow_mut()));
        drop(self);
        let Buffer { ops, args, values, constants, n_inputs, .. } = buffer;
        let n = ops.len();
        // Liveness, backwards from the outputs (operands precede their node).
        let mut live = vec![false; n];
        for o in outputs {
            if o.id != CONSTANT {
                live[o.id as usize] = true;
            }
        }
        for i in (0..n).rev() {
            if live[i] || ops[i] == Op::Input {
                live[i] = true;
                match ops[i] {
                    Op::Input | Op::Const => {}
                    op => {
                        live[args[i][0] as usize] = true;
                        if op.is_binary() {
                            live[args[i][1] as usize] = true;
                        }
                    }
                }
            }
        }
        let mut tape = Tape { n_inputs: n_inputs as usize, ..Tape::default() };
        let mut new_id = vec![u32::MAX; n];
        let mut new_constant: HashMap<u64, u32> = HashMap::new();
        let push = |tape: &mut Tape, op: Op, a: u32, b: u32, value: f64| -> u32 {
            let id = tape.ops.len() as u32;
            tape.ops.push(op as u8);
            tape.args.push([a, b]);
            tape.nominal.push(value);
            id
        };
        for i in 0..n {
            if !live[i] {
                continue;
            }
            let [a, b] = args[i];
            new_id[i] = match ops[i] {
                Op::Input => push(&mut tape, Op::Input, a, 0, values[i]),
                Op::Const => {
                    let k = tape.constants.len() as u32;
                    tape.constants.push(constants[a as usize]);
                    let id = push(&mut tape, Op::Const, k, 0, values[i]);
                    new_constant.insert(constants[a as usize].to_bits(), id);
                    id
                }
                op if op.is_binary() => push(&mut tape, op, new_id[a as usize], new_id[b as usize], values[i]),
                op => push(&mut tape, op, new_id[a as usize], 0, values[i]),
            };
        }
        for o in outputs {
            let id = if o.id != CONSTANT {
                new_id[o.id as usize]
            } else if let Some(&id) = new_constant.get(&o.value.to_bits()) {
                id
            } else {
                let k = tape.constants.len() as u32;
                tape.constants.push(o.value);
                let id = push(&mut tape, Op::Const, k, 0, o.value);
                new_constant.insert(o.value.to_bits(), id);
                id
            };
            tape.outputs.push(id);
        }
        tape
    }
}

impl Drop for Recording {
    fn drop(&mut self) {
        TAPE.with(|t| {
            if let Ok(mut t) = t.try_borrow_mut() {
                *t = Buffer::default();
            }
        });
    }
}

/// A recorded computation: node `i` is `ops[i]` applied to the nodes `args[i]` (operands
/// always precede their node; a unary operation's second argument is 0), an input
/// (`args[i][0]` its number) or a constant (`constants[args[i][0]]`). The outputs are the nodes
/// `outputs` in order (a constant output is a `Const` node).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Tape {
    /// Operation code of each node ([`Op`] as `u8`).
    pub ops: Vec<u8>,
    /// Operands of each node.
    pub args: Vec<[u32; 2]>,
    /// The constants referred to by `Const` nodes.
    pub constants: Vec<f64>,
    /// Value of each node at the nominal state of the recording.
    pub nominal: Vec<f64>,
    /// Number of inputs.
    pub n_inputs: usize,
    /// Node of each output.
    pub outputs: Vec<u32>,
}

impl Tape {
    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.ops.len()
    }

    /// `true` if the tape has no node.
    pub fn is_empty(&self) -> bool {
        self.ops.is_empty()
    }

    /// Replay the tape on `f64` inputs (length [`Tape::n_inputs`]): the outputs.
    pub fn eval(&self, inputs: &[f64]) -> Vec<f64> {
        assert_eq!(inputs.len(), self.n_inputs, "the tape has {} inputs", self.n_inputs);
        let mut v = Vec::with_capacity(self.len());
        for (code, [a, b]) in self.ops.iter().zip(&self.args) {
            let op = Op::from_u8(*code);
            v.push(match op {
                Op::Input => inputs[*a as usize],
                Op::Const => self.constants[*a as usize],
                op if op.is_binary() => op.apply(v[*a as usize], v[*b as usize]),
                op => op.apply(v[*a as usize], 0.0),
            });
        }
        self.outputs.iter().map(|&o| v[o as usize]).collect()
    }
}

// ---- Arithmetic ----

macro_rules! binary_ops {
    ($($trait:ident $method:ident $assign_trait:ident $assign:ident $op:ident),*) => {$(
        impl $trait for Var {
            type Output = Var;
            #[inline]
            fn $method(self, other: Var) -> Var {
                self.binary(Op::$op, other)
            }
        }
        impl $assign_trait for Var {
            #[inline]
            fn $assign(&mut self, other: Var) {
                *self = self.binary(Op::$op, other);
            }
        }
    )*};
}
binary_ops!(Add add AddAssign add_assign Add, Sub sub SubAssign sub_assign Sub, Mul mul MulAssign mul_assign Mul, Div div DivAssign div_assign Div);

impl Neg for Var {
    type Output = Var;
    #[inline]
    fn neg(self) -> Var {
        self.unary(Op::Neg)
    }
}

impl Rem for Var {
    type Output = Var;
    fn rem(self, _: Var) -> Var {
        unsupported("%")
    }
}

impl RemAssign for Var {
    fn rem_assign(&mut self, _: Var) {
        unsupported("%=")
    }
}

#[cold]
fn unsupported(what: &str) -> ! {
    panic!("{what} is not recorded on a tape: the recursions of spacearm-core do not use it (math::tape)")
}

/// Trait methods `fn f(self) -> Var` that record the one unary operation `Op::$op`.
macro_rules! recorded_unary {
    ($($f:ident => $op:ident),* $(,)?) => {$(
        fn $f(self) -> Var {
            self.unary(Op::$op)
        }
    )*};
}

/// Trait methods `fn f(self) -> Var` the tape does not record: they panic naming themselves
/// ([`unsupported`]).
macro_rules! unrecorded {
    ($($f:ident),* $(,)?) => {$(
        fn $f(self) -> Var {
            unsupported(stringify!($f))
        }
    )*};
}

/// Trait methods `fn f() -> Var` that return a constant (no operation recorded).
macro_rules! constants {
    ($($f:ident => $v:expr),* $(,)?) => {$(
        fn $f() -> Var {
            Var::constant($v)
        }
    )*};
}

// ---- Comparisons: structural equality, order of the nominal values ----

impl PartialEq for Var {
    /// The same node, or two equal constants: never equal by coincidence at the nominal state.
    fn eq(&self, other: &Var) -> bool {
        if self.id == CONSTANT || other.id == CONSTANT {
            self.id == other.id && self.value == other.value
        } else {
            self.id == other.id
        }
    }
}

impl PartialOrd for Var {
    /// The order of the nominal values (module docs: the branches this decides are validity
    /// checks that hold at every state).
    fn partial_cmp(&self, other: &Var) -> Option<std::cmp::Ordering> {
        self.value.partial_cmp(&other.value)
    }
}

impl fmt::Debug for Var {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.id == CONSTANT {
            write!(f, "Var(const {})", self.value)
        } else {
            write!(f, "Var(#{} = {})", self.id, self.value)
        }
    }
}

impl fmt::Display for Var {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Debug::fmt(self, f)
    }
}

// ---- num-traits ----

impl Zero for Var {
    #[inline]
    fn zero() -> Var {
        Var::constant(0.0)
    }
    /// Structural: only the constant zero.
    #[inline]
    fn is_zero(&self) -> bool {
        self.is_const(0.0)
    }
}

impl One for Var {
    #[inline]
    fn one() -> Var {
        Var::constant(1.0)
    }
}

impl Num for Var {
    type FromStrRadixErr = <f64 as Num>::FromStrRadixErr;
    fn from_str_radix(s: &str, radix: u32) -> Result<Var, Self::FromStrRadixErr> {
        f64::from_str_radix(s, radix).map(Var::constant)
    }
}

impl Signed for Var {
    fn abs(&self) -> Var {
        self.unary(Op::Abs)
    }
    fn abs_sub(&self, _: &Var) -> Var {
        unsupported("abs_sub")
    }
    fn signum(&self) -> Var {
        if self.is_constant() {
            Var::constant(self.value.signum())
        } else {
            unsupported("signum of a recorded value")
        }
    }
    fn is_positive(&self) -> bool {
        self.value > 0.0
    }
    fn is_negative(&self) -> bool {
        self.value < 0.0
    }
}

impl FromPrimitive for Var {
    fn from_i64(n: i64) -> Option<Var> {
        Some(Var::constant(n as f64))
    }
    fn from_u64(n: u64) -> Option<Var> {
        Some(Var::constant(n as f64))
    }
    fn from_f64(n: f64) -> Option<Var> {
        Some(Var::constant(n))
    }
}

// ---- approx (nominal values, like num-dual's real parts) ----

impl AbsDiffEq for Var {
    type Epsilon = Var;
    fn default_epsilon() -> Var {
        Var::constant(f64::default_epsilon())
    }
    fn abs_diff_eq(&self, other: &Var, epsilon: Var) -> bool {
        self.value.abs_diff_eq(&other.value, epsilon.value)
    }
}

impl RelativeEq for Var {
    fn default_max_relative() -> Var {
        Var::constant(f64::default_max_relative())
    }
    fn relative_eq(&self, other: &Var, epsilon: Var, max_relative: Var) -> bool {
        self.value.relative_eq(&other.value, epsilon.value, max_relative.value)
    }
}

impl UlpsEq for Var {
    fn default_max_ulps() -> u32 {
        f64::default_max_ulps()
    }
    fn ulps_eq(&self, other: &Var, epsilon: Var, max_ulps: u32) -> bool {
        self.value.ulps_eq(&other.value, epsilon.value, max_ulps)
    }
}

// ---- simba ----

impl simba::simd::SimdValue for Var {
    const LANES: usize = 1;
    type Element = Var;
    type SimdBool = bool;
    #[inline]
    fn splat(val: Var) -> Var {
        val
    }
    #[inline]
    fn extract(&self, _: usize) -> Var {
        *self
    }
    #[inline]
    unsafe fn extract_unchecked(&self, _: usize) -> Var {
        *self
    }
    #[inline]
    fn replace(&mut self, _: usize, val: Var) {
        *self = val
    }
    #[inline]
    unsafe fn replace_unchecked(&mut self, _: usize, val: Var) {
        *self = val
    }
    #[inline]
    fn select(self, cond: bool, other: Var) -> Var {
        if cond {
            self
        } else {
            other
        }
    }
}

impl SubsetOf<Var> for Var {
    fn to_superset(&self) -> Var {
        *self
    }
    fn from_superset_unchecked(element: &Var) -> Var {
        *element
    }
    fn is_in_subset(_: &Var) -> bool {
        true
    }
}

impl SupersetOf<f64> for Var {
    fn is_in_subset(&self) -> bool {
        self.is_constant()
    }
    fn to_subset_unchecked(&self) -> f64 {
        self.value
    }
    fn from_subset(element: &f64) -> Var {
        Var::constant(*element)
    }
}

impl SupersetOf<f32> for Var {
    fn is_in_subset(&self) -> bool {
        self.is_constant()
    }
    fn to_subset_unchecked(&self) -> f32 {
        self.value as f32
    }
    fn from_subset(element: &f32) -> Var {
        Var::constant(*element as f64)
    }
}

impl simba::scalar::Field for Var {}

impl simba::scalar::ComplexField for Var {
    type RealField = Var;

    fn from_real(re: Var) -> Var {
        re
    }
    fn real(self) -> Var {
        self
    }
    fn imaginary(self) -> Var {
        Var::constant(0.0)
    }
    fn modulus_squared(self) -> Var {
        self * self
    }
    fn scale(self, factor: Var) -> Var {
        self * factor
    }
    fn unscale(self, factor: Var) -> Var {
        self / factor
    }
    recorded_unary!(
        modulus => Abs, norm1 => Abs, abs => Abs,
        sin => Sin, cos => Cos, tan => Tan, asin => Asin, acos => Acos, atan => Atan,
        ln => Ln, sqrt => Sqrt, exp => Exp,
    );
    unrecorded!(
        argument, floor, ceil, round, trunc, fract,
        sinh, cosh, tanh, asinh, acosh, atanh,
        log2, log10, ln_1p, exp2, exp_m1, cbrt,
    );
    /// `self · a + b`, as two operations (as nalgebra's `f64` path computes it without FMA).
    fn mul_add(self, a: Var, b: Var) -> Var {
        self * a + b
    }
    fn hypot(self, other: Var) -> Var {
        (self * self + other * other).unary(Op::Sqrt)
    }
    fn recip(self) -> Var {
        Var::constant(1.0) / self
    }
    fn conjugate(self) -> Var {
        self
    }
    fn sin_cos(self) -> (Var, Var) {
        (self.unary(Op::Sin), self.unary(Op::Cos))
    }
    fn log(self, base: Var) -> Var {
        self.unary(Op::Ln) / base.unary(Op::Ln)
    }
    /// Repeated products for small integer powers (what the algorithms use: squares).
    fn powi(self, n: i32) -> Var {
        match n {
            0 => Var::constant(1.0),
            1 => self,
            2 => self * self,
            3 => self * self * self,
            -1 => Var::constant(1.0) / self,
            _ if self.is_constant() => Var::constant(self.value.powi(n)),
            _ => unsupported("powi with |n| > 3 of a recorded value"),
        }
    }
    fn powf(self, n: Var) -> Var {
        if self.is_constant() && n.is_constant() {
            Var::constant(self.value.powf(n.value))
        } else {
            unsupported("powf of a recorded value")
        }
    }
    fn powc(self, n: Var) -> Var {
        self.powf(n)
    }
    fn is_finite(&self) -> bool {
        self.value.is_finite()
    }
    /// The square root if the nominal value is non-negative (a validity check: module docs).
    fn try_sqrt(self) -> Option<Var> {
        if self.value >= 0.0 {
            Some(self.unary(Op::Sqrt))
        } else {
            None
        }
    }
}

impl simba::scalar::RealField for Var {
    fn is_sign_positive(&self) -> bool {
        self.value.is_sign_positive()
    }
    fn is_sign_negative(&self) -> bool {
        self.value.is_sign_negative()
    }
    fn copysign(self, _: Var) -> Var {
        unsupported("copysign")
    }
    /// The larger by nominal value (the algorithms use it on validity checks only).
    fn max(self, other: Var) -> Var {
        if other.value > self.value {
            other
        } else {
            self
        }
    }
    /// The smaller by nominal value (the algorithms use it on validity checks only).
    fn min(self, other: Var) -> Var {
        if other.value < self.value {
            other
        } else {
            self
        }
    }
    fn clamp(self, _: Var, _: Var) -> Var {
        unsupported("clamp")
    }
    fn atan2(self, other: Var) -> Var {
        self.binary(Op::Atan2, other)
    }
    constants!(
        pi => std::f64::consts::PI,
        two_pi => std::f64::consts::TAU,
        frac_pi_2 => std::f64::consts::FRAC_PI_2,
        frac_pi_3 => std::f64::consts::FRAC_PI_3,
        frac_pi_4 => std::f64::consts::FRAC_PI_4,
        frac_pi_6 => std::f64::consts::FRAC_PI_6,
        frac_pi_8 => std::f64::consts::FRAC_PI_8,
        frac_1_pi => std::f64::consts::FRAC_1_PI,
        frac_2_pi => std::f64::consts::FRAC_2_PI,
        frac_2_sqrt_pi => std::f64::consts::FRAC_2_SQRT_PI,
        e => std::f64::consts::E,
        log2_e => std::f64::consts::LOG2_E,
        log10_e => std::f64::consts::LOG10_E,
        ln_2 => std::f64::consts::LN_2,
        ln_10 => std::f64::consts::LN_10,
    );
    fn min_value() -> Option<Var> {
        Some(Var::constant(f64::MIN))
    }
    fn max_value() -> Option<Var> {
        Some(Var::constant(f64::MAX))
    }
}

impl Real for Var {
    #[inline(always)]
    fn c(x: f64) -> Var {
        Var::constant(x)
    }

    #[inline(always)]
    fn value(self) -> f64 {
        self.value
    }

    /// Structural: only the constant zero (a recorded value is never a shortcut's zero).
    #[inline(always)]
    fn is_exactly_zero(self) -> bool {
        self.is_const(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{ComplexField, RealField};

    #[test]
    fn records_folds_and_replays() {
        let mut rec = Recording::start();
        let x = rec.input(2.0);
        let y = rec.input(3.0);
        let c = Var::constant(4.0) * Var::constant(0.5); // folded
        assert!(c.is_constant() && c.nominal() == 2.0);
        let z = (x * y + c).sin() / (x - Var::constant(0.0)) + y * Var::constant(0.0) + x * Var::constant(1.0);
        let w = x.atan2(y) + (x * x + y).sqrt();
        let tape = rec.finish(&[z, w, Var::constant(7.0)]);
        let f = |x: f64, y: f64| [(x * y + 2.0).sin() / x + x, x.atan2(y) + (x * x + y).sqrt(), 7.0];
        assert_eq!(tape.eval(&[2.0, 3.0]), f(2.0, 3.0));
        assert_eq!(tape.eval(&[-1.5, 0.25]), f(-1.5, 0.25));
        assert_eq!(tape.n_inputs, 2);
        // The nominal values are the values at the recording's inputs.
        assert_eq!(tape.outputs.iter().map(|&o| tape.nominal[o as usize]).collect::<Vec<_>>(), f(2.0, 3.0));
    }

    #[test]
    fn dead_nodes_are_dropped_and_zeros_are_structural() {
        let mut rec = Recording::start();
        let x = rec.input(0.0);
        let _unused = x.cos() * x;
        assert!(!x.is_exactly_zero() && !x.is_zero(), "a recorded value at zero is not a structural zero");
        assert!(Var::constant(0.0).is_exactly_zero());
        assert!(x != Var::constant(0.0) && x == x);
        let tape = rec.finish(&[x + Var::constant(0.0)]);
        assert_eq!(tape.len(), 1);
        assert_eq!(tape.eval(&[5.0]), vec![5.0]);
    }

    #[test]
    #[should_panic(expected = "outside a Recording")]
    fn recorded_operations_need_a_recording() {
        let x = {
            let mut rec = Recording::start();
            rec.input(1.0)
        };
        let _ = x * x;
    }
}
