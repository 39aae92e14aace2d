//! The NumPy arrays of `Fleet.task_step` and `Fleet.task_observe`: read,
//! checked (dtype, shape, contiguity), and borrowed as slices for the
//! GIL-released pass.

use numpy::{
    PyArray1, PyArray2, PyArrayDyn, PyArrayMethods, PyReadonlyArray1, PyReadonlyArrayDyn,
    PyReadwriteArray1, PyReadwriteArray2, PyUntypedArrayMethods,
};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

use crate::fleet::{ActionValues, TaskOut};

/// A non-contiguous array as a `ValueError` naming it.
fn contiguous<T>(name: &str, r: Result<T, numpy::AsSliceError>) -> PyResult<T> {
    r.map_err(|_| PyValueError::new_err(format!("{name}: expected a C-contiguous array")))
}

/// The action array, float32 or float64, as given when it is C-contiguous;
/// anything else converted with `numpy.ascontiguousarray(actions,
/// dtype=float64)`.
pub enum Actions<'py> {
    /// float32 values.
    F32(PyReadonlyArrayDyn<'py, f32>),
    /// float64 values.
    F64(PyReadonlyArrayDyn<'py, f64>),
}

impl Actions<'_> {
    /// The values, row by row.
    ///
    /// # Errors
    /// Not contiguous (cannot happen: checked when read).
    pub fn values(&self) -> PyResult<ActionValues<'_>> {
        Ok(match self {
            Self::F32(a) => ActionValues::F32(contiguous("actions", a.as_slice())?),
            Self::F64(a) => ActionValues::F64(contiguous("actions", a.as_slice())?),
        })
    }
}

/// Reads `obj` as `n` aircraft's actions, `k` each.
///
/// # Errors
/// What NumPy raises converting it, or a `ValueError` for the wrong number
/// of values.
pub fn actions<'py>(
    py: Python<'py>,
    obj: &Bound<'py, PyAny>,
    n: usize,
    k: usize,
) -> PyResult<Actions<'py>> {
    let mut read = None;
    if let Ok(a) = obj.cast::<PyArrayDyn<f32>>() {
        if a.is_c_contiguous() {
            read = Some(Actions::F32(a.try_readonly()?));
        }
    } else if let Ok(a) = obj.cast::<PyArrayDyn<f64>>() {
        if a.is_c_contiguous() {
            read = Some(Actions::F64(a.try_readonly()?));
        }
    }
    let actions = match read {
        Some(a) => a,
        None => {
            let numpy = py.import("numpy")?;
            let kwargs = pyo3::types::PyDict::new(py);
            kwargs.set_item("dtype", numpy.getattr("float64")?)?;
            let converted = numpy.call_method("ascontiguousarray", (obj,), Some(&kwargs))?;
            let array = converted
                .cast_into::<PyArrayDyn<f64>>()
                .map_err(|_| PyTypeError::new_err("actions: expected a float NumPy array"))?;
            Actions::F64(array.try_readonly()?)
        }
    };
    let (len, shape) = match &actions {
        Actions::F32(a) => (a.len(), a.shape().to_vec()),
        Actions::F64(a) => (a.len(), a.shape().to_vec()),
    };
    if len != n * k {
        return Err(PyValueError::new_err(format!(
            "actions: expected {n} × {k} values (shape ({n}, {k})), got shape {shape:?}"
        )));
    }
    Ok(actions)
}

/// A float64 array of shape `(n,)`.
fn column<'py>(
    obj: &Bound<'py, PyAny>,
    name: &str,
    n: usize,
) -> PyResult<PyReadonlyArray1<'py, f64>> {
    let a = obj.cast::<PyArray1<f64>>().map_err(|_| {
        PyTypeError::new_err(format!("{name}: expected a float64 array of shape ({n},)"))
    })?;
    if a.len() != n {
        return Err(PyValueError::new_err(format!(
            "{name}: expected shape ({n},), got ({},)",
            a.len()
        )));
    }
    Ok(a.try_readonly()?)
}

/// The targets of every aircraft.
pub struct Targets<'py>(PyReadonlyArray1<'py, f64>, PyReadonlyArray1<'py, f64>);

impl<'py> Targets<'py> {
    /// Reads the target altitudes and headings.
    ///
    /// # Errors
    /// Wrong type or shape.
    pub fn read(alt: &Bound<'py, PyAny>, hdg: &Bound<'py, PyAny>, n: usize) -> PyResult<Self> {
        Ok(Self(
            column(alt, "target_alt_ft", n)?,
            column(hdg, "target_heading_deg", n)?,
        ))
    }

    /// `(altitudes, headings)`.
    ///
    /// # Errors
    /// Not contiguous.
    pub fn slices(&self) -> PyResult<(&[f64], &[f64])> {
        Ok((
            contiguous("target_alt_ft", self.0.as_slice())?,
            contiguous("target_heading_deg", self.1.as_slice())?,
        ))
    }
}

/// The step counters, an int64 array of shape `(n,)`, writable.
///
/// # Errors
/// Wrong type or shape, or borrowed elsewhere.
pub fn steps<'py>(obj: &Bound<'py, PyAny>, n: usize) -> PyResult<PyReadwriteArray1<'py, i64>> {
    let a = obj.cast::<PyArray1<i64>>().map_err(|_| {
        PyTypeError::new_err(format!("steps: expected an int64 array of shape ({n},)"))
    })?;
    if a.len() != n {
        return Err(PyValueError::new_err(format!(
            "steps: expected shape ({n},)"
        )));
    }
    Ok(a.try_readwrite()?)
}

/// The outputs: observations `(n, n_obs)` float32, rewards `(n,)` float64,
/// terminated and truncated `(n,)` bool; all writable.
pub struct Outs<'py> {
    obs: PyReadwriteArray2<'py, f32>,
    reward: PyReadwriteArray1<'py, f64>,
    terminated: PyReadwriteArray1<'py, bool>,
    truncated: PyReadwriteArray1<'py, bool>,
}

/// [`Outs`] as slices.
pub struct OutSlices<'a> {
    obs: &'a mut [f32],
    reward: &'a mut [f64],
    terminated: &'a mut [bool],
    truncated: &'a mut [bool],
}

impl<'a> OutSlices<'a> {
    /// With the fleet's buffers: what a task pass fills.
    pub fn into_task_out(self, columns: &'a mut [f64], status: &'a mut [u8]) -> TaskOut<'a> {
        TaskOut {
            columns,
            status,
            obs: self.obs,
            reward: self.reward,
            terminated: self.terminated,
            truncated: self.truncated,
        }
    }
}

impl<'py> Outs<'py> {
    /// Reads and checks the four output arrays.
    ///
    /// # Errors
    /// Wrong type or shape, or borrowed elsewhere.
    pub fn read(
        obs: &Bound<'py, PyAny>,
        reward: &Bound<'py, PyAny>,
        terminated: &Bound<'py, PyAny>,
        truncated: &Bound<'py, PyAny>,
        n: usize,
        n_obs: usize,
    ) -> PyResult<Self> {
        let obs = obs.cast::<PyArray2<f32>>().map_err(|_| {
            PyTypeError::new_err(format!(
                "obs: expected a float32 array of shape ({n}, {n_obs})"
            ))
        })?;
        if obs.shape() != [n, n_obs] {
            return Err(PyValueError::new_err(format!(
                "obs: expected shape ({n}, {n_obs}), got {:?}",
                obs.shape()
            )));
        }
        let reward = reward.cast::<PyArray1<f64>>().map_err(|_| {
            PyTypeError::new_err(format!("reward: expected a float64 array of shape ({n},)"))
        })?;
        let flags = |a: &Bound<'py, PyAny>, name: &str| -> PyResult<Bound<'py, PyArray1<bool>>> {
            let a = a.cast::<PyArray1<bool>>().map_err(|_| {
                PyTypeError::new_err(format!("{name}: expected a bool array of shape ({n},)"))
            })?;
            if a.len() != n {
                return Err(PyValueError::new_err(format!(
                    "{name}: expected shape ({n},)"
                )));
            }
            Ok(a.clone())
        };
        if reward.len() != n {
            return Err(PyValueError::new_err(format!(
                "reward: expected shape ({n},)"
            )));
        }
        let (terminated, truncated) = (
            flags(terminated, "terminated")?,
            flags(truncated, "truncated")?,
        );
        Ok(Self {
            obs: obs.try_readwrite()?,
            reward: reward.try_readwrite()?,
            terminated: terminated.try_readwrite()?,
            truncated: truncated.try_readwrite()?,
        })
    }

    /// The four arrays' memory.
    ///
    /// # Errors
    /// Not contiguous.
    pub fn slices(&mut self) -> PyResult<OutSlices<'_>> {
        Ok(OutSlices {
            obs: contiguous("obs", self.obs.as_slice_mut())?,
            reward: contiguous("reward", self.reward.as_slice_mut())?,
            terminated: contiguous("terminated", self.terminated.as_slice_mut())?,
            truncated: contiguous("truncated", self.truncated.as_slice_mut())?,
        })
    }
}

/// `fdm_core::math`'s function `f` of each pair of `a` and `b` (float64,
/// shape `(n,)` each), one pair at a time: the tasks' deterministic maths
/// for the NumPy oracle of `tests/test_task_kernel.py`.
fn pairwise<'py>(
    py: Python<'py>,
    name: &str,
    a: &PyReadonlyArray1<'py, f64>,
    b: &PyReadonlyArray1<'py, f64>,
    f: fn(f64, f64) -> f64,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let (a, b) = (a.as_array(), b.as_array());
    if a.len() != b.len() {
        return Err(PyValueError::new_err(format!(
            "{name}: the arrays' lengths differ ({} and {})",
            a.len(),
            b.len()
        )));
    }
    let out: Vec<f64> = a.iter().zip(b.iter()).map(|(&x, &y)| f(x, y)).collect();
    Ok(PyArray1::from_vec(py, out))
}

/// `_math_atan2(y, x)`: `fdm_core::math::atan2` elementwise (fdlibm's,
/// pure Rust), the function the tasks' track uses.
///
/// # Errors
/// Arrays of different lengths.
#[pyfunction]
#[pyo3(name = "_math_atan2")]
pub fn math_atan2<'py>(
    py: Python<'py>,
    y: PyReadonlyArray1<'py, f64>,
    x: PyReadonlyArray1<'py, f64>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    pairwise(py, "_math_atan2", &y, &x, fdm_core::math::atan2)
}

/// `_math_hypot(x, y)`: `fdm_core::math::hypot` elementwise (musl's, pure
/// Rust), the function the tasks' horizontal speed uses.
///
/// # Errors
/// Arrays of different lengths.
#[pyfunction]
#[pyo3(name = "_math_hypot")]
pub fn math_hypot<'py>(
    py: Python<'py>,
    x: PyReadonlyArray1<'py, f64>,
    y: PyReadonlyArray1<'py, f64>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    pairwise(py, "_math_hypot", &x, &y, fdm_core::math::hypot)
}
