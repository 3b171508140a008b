//! The one driver behind every per-state method of the extension: one state, or a batch of
//! states (a 2-D argument, one state per row) computed on rayon's threads with the GIL
//! released.
//!
//! A method describes its inputs (name and row width), its outputs (the shape of one row's
//! result) and a kernel that computes one row into preallocated output slices with a workspace
//! of its own. The driver converts the arguments, allocates the numpy results, runs the kernel
//! once (one state) or once per row (a batch: each rayon job makes its own workspace, nothing
//! mutable is shared) and checks every result for finiteness. A row's result depends only on
//! that row's inputs (the kernels run forward kinematics first and overwrite everything they
//! read), so a batch gives bit for bit the per-state results whatever the thread count.
//!
//! One-state calls take their workspace from a small [`Pool`] of the model, so concurrent
//! calls from several Python threads, or a call re-entered from Python code run by an argument
//! conversion, never share one.

use std::ptr;
use std::sync::atomic::{AtomicBool, AtomicPtr, Ordering};
use std::sync::{Arc, Mutex};

use numpy::{IxDyn, PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use rayon::prelude::*;
use spacearm_core::SpacearmError;

use crate::convert::{batch_arg, class_of_error, shape_error, to_py_err, ArgValue};
use crate::errors_py::{new_error, ErrorClass};

/// Workspaces of one model for one-state calls: taken for the duration of a call, given back
/// after it; a call that finds none free makes a new one. Boxed, so that taking and giving
/// back moves a pointer, not the workspace (a `Data` is a few hundred bytes).
///
/// One workspace waits in `hot`, taken and given back by one atomic swap each: the common case
/// (one thread calling) never touches the mutex, whose two lock/unlock pairs were a measurable
/// part of a one-state call. Concurrent calls find `hot` empty and fall back to the list.
pub struct Pool<W> {
    hot: AtomicPtr<W>,
    free: Mutex<Vec<Box<W>>>,
}

/// At most this many idle workspaces are kept besides the hot one (as many as threads are
/// likely to call at once).
const POOL_KEEP: usize = 16;

impl<W> Pool<W> {
    pub fn new() -> Self {
        Pool { hot: AtomicPtr::new(ptr::null_mut()), free: Mutex::new(Vec::new()) }
    }

    /// Run `f` with a workspace of the pool (or a new one from `make`).
    #[inline]
    pub fn with<R>(&self, make: impl FnOnce() -> W, f: impl FnOnce(&mut W) -> R) -> R {
        let hot = self.hot.swap(ptr::null_mut(), Ordering::Acquire);
        let mut work = if hot.is_null() {
            self.take_from_list(make)
        } else {
            // SAFETY: a non-null `hot` came from `Box::into_raw` below, and the swap gave this
            // call sole ownership of it.
            unsafe { Box::from_raw(hot) }
        };
        let result = f(&mut work);
        let raw = Box::into_raw(work);
        if self.hot.compare_exchange(ptr::null_mut(), raw, Ordering::Release, Ordering::Relaxed).is_err() {
            // SAFETY: `raw` was made by `Box::into_raw` just above and was not published.
            self.give_back_to_list(unsafe { Box::from_raw(raw) });
        }
        result
    }

    /// A workspace from the mutex list, or a new one: only when calls overlap (out of line, so
    /// that the one-thread path stays small).
    #[cold]
    #[inline(never)]
    fn take_from_list(&self, make: impl FnOnce() -> W) -> Box<W> {
        let taken = self.free.lock().unwrap_or_else(|e| e.into_inner()).pop();
        taken.unwrap_or_else(|| Box::new(make()))
    }

    /// Keep `work` in the mutex list (up to [`POOL_KEEP`]) when the hot slot is taken.
    #[cold]
    #[inline(never)]
    fn give_back_to_list(&self, work: Box<W>) {
        let mut free = self.free.lock().unwrap_or_else(|e| e.into_inner());
        if free.len() < POOL_KEEP {
            free.push(work);
        }
    }
}

impl<W> Drop for Pool<W> {
    fn drop(&mut self) {
        let hot = *self.hot.get_mut();
        if !hot.is_null() {
            // SAFETY: the pool owns the published workspace; nothing else can reach it now.
            drop(unsafe { Box::from_raw(hot) });
        }
    }
}

impl<W> Default for Pool<W> {
    fn default() -> Self {
        Self::new()
    }
}

/// Batches of at least this many rows run interruptibly (Ctrl-C within 0.1 s,
/// [`crate::interrupt`]); a smaller one is over before a helper thread would have started.
const INTERRUPTIBLE_ROWS: usize = 4096;

/// The thread pool batches run on: `None` is rayon's global pool (all cores, or
/// `RAYON_NUM_THREADS`).
static THREADS: Mutex<Option<Arc<rayon::ThreadPool>>> = Mutex::new(None);

/// Run batches on `threads` threads from now on (1 to `MAX_THREADS` = 1024; `None`: rayon's
/// global pool).
#[pyfunction]
#[pyo3(signature = (threads=None))]
pub fn set_batch_threads(py: Python<'_>, threads: Option<usize>) -> PyResult<()> {
    let pool = match threads {
        None => None,
        Some(0) => return Err(new_error(py, ErrorClass::Argument, "threads must be a positive integer or None (all cores), got 0".into())),
        // The one bound of a thread count (the rollouts' too): no request starts threads without limit.
        Some(n) if n > spacearm_core::sim::rollout::MAX_THREADS => {
            return Err(new_error(
                py,
                ErrorClass::Argument,
                format!("threads must be at most {} (or None: one per core), got {n}", spacearm_core::sim::rollout::MAX_THREADS),
            ))
        }
        Some(n) => Some(Arc::new(
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map_err(|e| new_error(py, ErrorClass::Argument, format!("could not start {n} threads: {e}")))?,
        )),
    };
    *THREADS.lock().unwrap_or_else(|e| e.into_inner()) = pool;
    Ok(())
}

/// The number of threads batches run on.
#[pyfunction]
pub fn batch_threads() -> usize {
    match &*THREADS.lock().unwrap_or_else(|e| e.into_inner()) {
        Some(pool) => pool.current_num_threads(),
        None => rayon::current_num_threads(),
    }
}

/// One input of a method: an argument (one vector, or a batch of rows) or a constant vector
/// used for every row (an omitted optional argument).
pub struct Input<'py> {
    name: &'static str,
    width: usize,
    value: Value<'py>,
}

enum Value<'py> {
    Arg(ArgValue<'py>),
    Constant(Vec<f64>),
}

impl<'py> Input<'py> {
    /// Convert argument `obj` named `name`, whose rows have `width` entries (the core checks a
    /// single vector's length itself, with its own message).
    pub fn arg(obj: &Bound<'py, PyAny>, name: &'static str, width: usize) -> PyResult<Self> {
        Ok(Input { name, width, value: Value::Arg(batch_arg(obj, name)?) })
    }

    /// [`Input::arg`], or zeros of length `width` when the argument is omitted.
    pub fn optional(obj: Option<&Bound<'py, PyAny>>, name: &'static str, width: usize) -> PyResult<Self> {
        match obj {
            Some(o) if !o.is_none() => Self::arg(o, name, width),
            _ => Ok(Input { name, width, value: Value::Constant(vec![0.0; width]) }),
        }
    }

    /// A constant vector used for every row.
    pub fn constant(name: &'static str, values: Vec<f64>) -> Self {
        Input { name, width: values.len(), value: Value::Constant(values) }
    }

    fn rows(&self) -> Option<usize> {
        match &self.value {
            Value::Arg(ArgValue::Many { rows, .. }) => Some(*rows),
            _ => None,
        }
    }

    fn single(&self) -> &[f64] {
        match &self.value {
            Value::Arg(ArgValue::One(v)) => v.as_slice(),
            Value::Constant(v) => v,
            Value::Arg(ArgValue::Many { values, .. }) => values,
        }
    }

    /// The values as rows that may cross to other threads, borrowed (no copy of the batch: a
    /// single vector is repeated for every row, stride 0).
    fn rows_source(&self) -> RowSource<'_> {
        match &self.value {
            Value::Arg(ArgValue::Many { values, width, .. }) => RowSource { values, stride: *width },
            _ => RowSource { values: self.single(), stride: 0 },
        }
    }
}

struct RowSource<'a> {
    values: &'a [f64],
    stride: usize,
}

impl RowSource<'_> {
    fn row(&self, i: usize) -> &[f64] {
        if self.stride == 0 {
            self.values
        } else {
            &self.values[i * self.stride..(i + 1) * self.stride]
        }
    }
}

/// What went wrong in one row.
enum RowError {
    Core(SpacearmError),
    NonFiniteResult { index: usize, value: f64 },
}

/// Whether every value is finite. `v · 0` is ±0 for a finite `v` and NaN for ±∞ and NaN, and a
/// NaN stays NaN through additions: eight running sums of `v · 0` (independent, so they stay
/// in vector registers even on the baseline x86-64 the wheels target, which has no 64-bit
/// integer compare to vectorize a test of the exponent bits) are all zero exactly when every
/// value is finite. About one instruction per value: the check of every result costs less
/// than copying it.
fn all_finite(values: &[f64]) -> bool {
    let mut sums = [0.0f64; 8];
    let chunks = values.chunks_exact(8);
    let rest = chunks.remainder();
    for chunk in chunks {
        for (s, v) in sums.iter_mut().zip(chunk) {
            *s += v * 0.0;
        }
    }
    for (s, v) in sums.iter_mut().zip(rest) {
        *s += v * 0.0;
    }
    sums.iter().all(|s| *s == 0.0)
}

/// The first non-finite entry of the outputs (index counted across them in order), if any.
fn first_non_finite(outputs: &[&mut [f64]]) -> Option<(usize, f64)> {
    if outputs.iter().all(|out| all_finite(out)) {
        return None;
    }
    let mut base = 0;
    for out in outputs {
        if let Some(i) = out.iter().position(|v| !v.is_finite()) {
            return Some((base + i, out[i]));
        }
        base += out.len();
    }
    None
}

#[cold]
#[inline(never)]
fn raise(py: Python<'_>, call: &str, row: Option<usize>, err: RowError) -> PyErr {
    let prefix = match row {
        Some(i) => format!("row {i} of the batch: "),
        None => String::new(),
    };
    match err {
        RowError::Core(e) => new_error(py, class_of_error(&e), format!("{prefix}{e}")),
        RowError::NonFiniteResult { index, value } => new_error(
            py,
            ErrorClass::NonFinite,
            format!(
                "{prefix}{call} gave a non-finite result (entry {index} of the result is {value}) from finite inputs: the \
                 state is beyond what double precision can represent (e.g. joint rates of 1e200 overflow the velocity \
                 products); reduce the magnitudes of the inputs"
            ),
        ),
    }
}

/// A raw output pointer that may cross to rayon's threads: each row writes only its own
/// disjoint part of the array.
#[derive(Clone, Copy)]
struct OutPtr(*mut f64);
// SAFETY: the pointer targets a fresh numpy buffer that lives (and is not touched by Python)
// until the batch returns; rows write disjoint ranges.
unsafe impl Send for OutPtr {}
unsafe impl Sync for OutPtr {}

/// The error of batch arguments whose row counts differ (kept out of line: the driver's hot
/// path stays small, see [`run`]).
#[cold]
#[inline(never)]
fn rows_disagree(py: Python<'_>, inputs: &[Input<'_>], rows: usize, name: &str, other: usize) -> PyErr {
    let first = inputs.iter().find(|i| i.rows().is_some()).map(|i| i.name).unwrap_or("?");
    shape_error(py, format!("the batch arguments disagree on the number of rows: {first} has {rows}, {name} has {other}"))
}

/// An empty batch (B = 0) runs no kernel, which checks the single vectors shared by every row:
/// they are checked here instead, with the kernel's messages, so that the verdict on the other
/// arguments does not depend on B (out of line, like [`rows_disagree`]).
#[cold]
#[inline(never)]
fn empty_batch_arguments(py: Python<'_>, inputs: &[Input<'_>]) -> PyResult<()> {
    for input in inputs {
        if let Value::Arg(ArgValue::One(v)) = &input.value {
            let v = v.as_slice();
            if v.len() != input.width {
                return Err(shape_error(py, format!("{} must have length {}, got {}", input.name, input.width, v.len())));
            }
            if let Some(k) = v.iter().position(|x| !x.is_finite()) {
                return Err(new_error(py, ErrorClass::NonFinite, format!("{} must be finite, but entry {k} is {}", input.name, v[k])));
            }
            // A configuration's one rule beyond length and finiteness: its unit quaternion.
            if input.name == "x" && v.len() >= 7 {
                spacearm_core::algorithms::kinematics::base_quaternion(v).map_err(|e| to_py_err(py, e))?;
            }
        }
    }
    Ok(())
}

/// The refusal of outputs beyond the core's memory limit, with the way out for `call`
/// (out of line, like [`rows_disagree`]).
#[cold]
#[inline(never)]
fn refuse_outputs(py: Python<'_>, call: &str, rows: usize, bytes: f64) -> PyResult<()> {
    let remedy = if call.ends_with("_partials") {
        "use the derivative along one velocity (mass_matrix_derivative, generalized_inertia_derivative, \
         generalized_jacobian_derivative: one slice instead of the whole tensor), a smaller batch or a smaller model"
    } else {
        "use a smaller batch or model, or the O(N) algorithms that need no dense matrix (ABA forward dynamics, RNEA, kinematics)"
    };
    spacearm_core::admission::admit(format_args!("{call} ({rows} state(s))"), bytes, remedy).map_err(|e| to_py_err(py, e))
}

/// A binding object that holds a model and a pool of its workspaces (`Model`: `Data`,
/// `Derivatives`: `DerivativeData`): its per-state methods are [`Batched::batch`] calls.
pub trait Batched {
    type Work;
    /// How a fresh workspace is made for the model.
    const WORKSPACE: fn(&spacearm_core::Model) -> Self::Work;
    /// The model and the pool of its workspaces.
    fn parts(&self) -> (&spacearm_core::Model, &Pool<Self::Work>);

    /// [`run`] of `kernel` on this object's pool of workspaces; `kernel` gets the model, a
    /// workspace, one row of each input and one row of each output.
    #[inline]
    fn batch<'py, const I: usize, const O: usize>(
        &self,
        py: Python<'py>,
        call: &str,
        inputs: [Input<'py>; I],
        outputs: [&[usize]; O],
        kernel: impl Fn(&spacearm_core::Model, &mut Self::Work, [&[f64]; I], &mut [&mut [f64]; O]) -> spacearm_core::Result<()> + Sync,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (model, pool) = self.parts();
        run(py, call, inputs, outputs, pool, || Self::WORKSPACE(model), |work, rows, out| kernel(model, work, rows, out))
    }

    /// The configuration argument `x` of a per-state method: rows of `7+N`.
    fn x_arg<'py>(&self, x: &Bound<'py, PyAny>) -> PyResult<Input<'py>> {
        Input::arg(x, "x", self.parts().0.nx())
    }

    /// The velocity argument `u` of a per-state method: rows of `6+N`.
    fn u_arg<'py>(&self, u: &Bound<'py, PyAny>) -> PyResult<Input<'py>> {
        Input::arg(u, "u", self.parts().0.nu())
    }
}

/// `impl Batched for $class` with workspaces `$work` (made by `$work::new(&Model)`), for a class
/// whose fields `model` and `workspaces` hold the model and the pool.
macro_rules! batched {
    ($class:ty, $work:ty) => {
        impl $crate::batch::Batched for $class {
            type Work = $work;
            const WORKSPACE: fn(&spacearm_core::Model) -> $work = <$work>::new;
            fn parts(&self) -> (&spacearm_core::Model, &$crate::batch::Pool<$work>) {
                (&self.model, &self.workspaces)
            }
        }
    };
}
pub(crate) use batched;

/// Compute `kernel` for one state or for a batch (see the module documentation).
///
/// `inputs` in the order their conversion errors should be reported; `outputs[k]` the shape of
/// one row's `k`-th result (`[]`: a scalar, returned as a Python float for one state); `call`
/// the method's name for error messages. One output is returned as it is, several as a tuple.
///
/// The one-state path is kept small and contiguous (the batch path and every error are out of
/// line): a call from Python runs with an instruction cache that the interpreter has just
/// refilled, so the code a call touches costs time beyond the instructions it executes.
pub fn run<'py, W, const I: usize, const O: usize>(
    py: Python<'py>,
    call: &str,
    inputs: [Input<'py>; I],
    outputs: [&[usize]; O],
    pool: &Pool<W>,
    make: impl Fn() -> W + Sync,
    kernel: impl Fn(&mut W, [&[f64]; I], &mut [&mut [f64]; O]) -> spacearm_core::Result<()> + Sync,
) -> PyResult<Bound<'py, PyAny>> {
    let mut rows: Option<usize> = None;
    for input in &inputs {
        if let Some(r) = input.rows() {
            match rows {
                Some(b) if b != r => return Err(rows_disagree(py, &inputs, b, input.name, r)),
                _ => rows = Some(r),
            }
        }
    }
    // The outputs are allocated here, before the kernel's own workspaces: refuse an oversize
    // request before numpy is asked for it (core admission, one limit for every request).
    let values: usize = outputs.iter().map(|shape| shape.iter().product::<usize>()).sum();
    let bytes = rows.unwrap_or(1) as f64 * spacearm_core::admission::bytes_of::<f64>(values as f64);
    if !spacearm_core::admission::within_memory_limit(bytes) {
        refuse_outputs(py, call, rows.unwrap_or(1), bytes)?;
    }
    match rows {
        None => run_one(py, call, &inputs, outputs, pool, make, kernel),
        Some(b) => run_batch(py, call, &inputs, outputs, b, make, kernel),
    }
}

fn new_output<'py>(py: Python<'py>, lead: Option<usize>, shape: &[usize]) -> Bound<'py, PyArrayDyn<f64>> {
    // On the stack: a one-state call allocates nothing but the array itself.
    let mut dims = [0usize; 8];
    let mut len = 0;
    for d in lead.iter().chain(shape) {
        dims[len] = *d;
        len += 1;
    }
    // SAFETY: a fresh array owned by nobody else; the kernel writes every element.
    unsafe { PyArrayDyn::<f64>::new(py, IxDyn(&dims[..len]), false) }
}

fn finish<'py, const O: usize>(py: Python<'py>, arrays: [Bound<'py, PyArrayDyn<f64>>; O], scalar_as_float: bool) -> PyResult<Bound<'py, PyAny>> {
    let as_python = |a: Bound<'py, PyArrayDyn<f64>>| -> PyResult<Bound<'py, PyAny>> {
        if scalar_as_float && a.ndim() == 0 {
            // SAFETY: a 0-d contiguous array holds one element.
            let v = unsafe { a.as_slice() }.map_err(PyErr::from)?[0];
            Ok(v.into_pyobject(py)?.into_any())
        } else {
            Ok(a.into_any())
        }
    };
    if O == 1 {
        return as_python(arrays.into_iter().next().expect("one output"));
    }
    let items = arrays.into_iter().map(as_python).collect::<PyResult<Vec<_>>>()?;
    Ok(PyTuple::new(py, items)?.into_any())
}

#[allow(clippy::too_many_arguments)]
fn run_one<'py, W, const I: usize, const O: usize>(
    py: Python<'py>,
    call: &str,
    inputs: &[Input<'py>; I],
    outputs: [&[usize]; O],
    pool: &Pool<W>,
    make: impl Fn() -> W,
    kernel: impl Fn(&mut W, [&[f64]; I], &mut [&mut [f64]; O]) -> spacearm_core::Result<()>,
) -> PyResult<Bound<'py, PyAny>> {
    let arrays: [Bound<'py, PyArrayDyn<f64>>; O] = std::array::from_fn(|k| new_output(py, None, outputs[k]));
    let args: [&[f64]; I] = std::array::from_fn(|k| inputs[k].single());
    // SAFETY: fresh contiguous arrays, not yet visible to Python.
    let mut bufs: [&mut [f64]; O] = std::array::from_fn(|k| unsafe { arrays[k].as_slice_mut() }.expect("a new array is contiguous"));
    let result = pool.with(make, |w| kernel(w, args, &mut bufs));
    result.map_err(|e| raise(py, call, None, RowError::Core(e)))?;
    if let Some((index, value)) = first_non_finite(&bufs) {
        return Err(raise(py, call, None, RowError::NonFiniteResult { index, value }));
    }
    finish(py, arrays, true)
}

#[inline(never)]
fn run_batch<'py, W, const I: usize, const O: usize>(
    py: Python<'py>,
    call: &str,
    inputs: &[Input<'py>; I],
    outputs: [&[usize]; O],
    rows: usize,
    make: impl Fn() -> W + Sync,
    kernel: impl Fn(&mut W, [&[f64]; I], &mut [&mut [f64]; O]) -> spacearm_core::Result<()> + Sync,
) -> PyResult<Bound<'py, PyAny>> {
    for input in inputs {
        if let Value::Arg(ArgValue::Many { width, .. }) = &input.value {
            if *width != input.width {
                return Err(shape_error(
                    py,
                    format!("{} must have shape (B, {}) for a batch of B states (one per row), got ({rows}, {width})", input.name, input.width),
                ));
            }
        }
    }
    if rows == 0 {
        empty_batch_arguments(py, inputs)?;
    }
    let sources: [RowSource<'_>; I] = std::array::from_fn(|k| inputs[k].rows_source());
    let arrays: [Bound<'py, PyArrayDyn<f64>>; O] = std::array::from_fn(|k| new_output(py, Some(rows), outputs[k]));
    let row_len: [usize; O] = std::array::from_fn(|k| outputs[k].iter().product());
    // SAFETY: fresh contiguous arrays, not yet visible to Python.
    let ptrs: [OutPtr; O] = std::array::from_fn(|k| OutPtr(unsafe { arrays[k].as_slice_mut() }.expect("a new array is contiguous").as_mut_ptr()));
    let first_error: Mutex<Option<(usize, RowError)>> = Mutex::new(None);
    let work = |cancel: &AtomicBool| {
        (0..rows).into_par_iter().with_min_len(16).for_each_init(&make, |w, i| {
            if cancel.load(Ordering::Relaxed) {
                return; // Ctrl-C: the remaining rows are skipped, the call raises the interrupt
            }
            let args: [&[f64]; I] = std::array::from_fn(|k| sources[k].row(i));
            // SAFETY: row i of output k is [i·len, (i+1)·len) of a buffer of rows·len
            // elements; no other row touches it.
            let mut bufs: [&mut [f64]; O] = std::array::from_fn(|k| unsafe { std::slice::from_raw_parts_mut(ptrs[k].0.add(i * row_len[k]), row_len[k]) });
            let outcome = match kernel(w, args, &mut bufs) {
                Err(e) => Some(RowError::Core(e)),
                Ok(()) => first_non_finite(&bufs).map(|(index, value)| RowError::NonFiniteResult { index, value }),
            };
            if let Some(err) = outcome {
                // Keep the error of the lowest row, whatever order the threads finish in.
                let mut slot = first_error.lock().unwrap_or_else(|e| e.into_inner());
                if slot.as_ref().is_none_or(|(j, _)| i < *j) {
                    *slot = Some((i, err));
                }
            }
        })
    };
    let pool = THREADS.lock().unwrap_or_else(|e| e.into_inner()).clone();
    let run = |cancel: &AtomicBool| match &pool {
        Some(p) => p.install(|| work(cancel)),
        None => work(cancel),
    };
    if rows >= INTERRUPTIBLE_ROWS {
        // A long batch: Ctrl-C stops it within 0.1 s (crate::interrupt).
        crate::interrupt::run_interruptible(py, run)?;
    } else {
        let never = AtomicBool::new(false);
        py.detach(|| run(&never));
    }
    if let Some((i, err)) = first_error.into_inner().unwrap_or_else(|e| e.into_inner()) {
        return Err(raise(py, call, Some(i), err));
    }
    finish(py, arrays, false)
}
