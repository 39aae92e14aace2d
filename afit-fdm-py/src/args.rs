//! The package's plain arguments (whole numbers, real numbers, flags, text,
//! origins) read with the argument's name in the error's message:
//! `Fleet("palmer", -5)` raises `ValueError: n: -5 is not a whole number in
//! 0..=18446744073709551615`, not PyO3's `OverflowError: can't convert
//! negative int to unsigned`, whose name is only in a note (which
//! `str(error)` leaves out and Python 3.9 and 3.10 do not have).
//!
//! Each reader ([`fps`], [`frames`], …) is an argument's name and type, used
//! as `#[pyo3(from_py_with = args::frames)] frames: u64`; its errors are a
//! `TypeError` for the wrong kind of object (`n: expected a whole number
//! (int), got float`) and a `ValueError` for a whole number out of the type's
//! range, both starting with the argument's name as the package's other
//! errors do (`throttle: expected a number or a float64 array, ...`).

use fdm_run::MAX_FPS;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyFloat, PyInt, PyString};

/// A value of a plain argument, read with the argument's name in its errors.
pub trait Argument: Sized {
    /// `obj` as `Self`, for the argument `name`.
    ///
    /// # Errors
    /// `TypeError` or `ValueError`, the message starting with `name`.
    fn read(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Self>;
}

/// The name of `obj`'s type (`float`, `numpy.float32`), for messages.
fn type_name(obj: &Bound<'_, PyAny>) -> String {
    let kind = obj.get_type();
    let name = kind
        .name()
        .map_or_else(|_| "object".to_owned(), |n| n.to_string());
    match kind.module().map(|m| m.to_string()) {
        Ok(module) if module != "builtins" => format!("{module}.{name}"),
        _ => name,
    }
}

/// The `TypeError` `name: expected {what}, got {obj's type}`.
fn wrong_type(obj: &Bound<'_, PyAny>, name: &str, what: &str) -> PyErr {
    PyTypeError::new_err(format!("{name}: expected {what}, got {}", type_name(obj)))
}

macro_rules! whole_numbers {
    ($($int:ty),*) => {$(
        impl Argument for $int {
            /// A Python `int` (or an object with `__index__`, as NumPy's
            /// integers) in the type's range: what PyO3 takes, with the
            /// argument named in the refusals.
            fn read(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Self> {
                match obj.extract::<Self>() {
                    Ok(value) => Ok(value),
                    // A whole number it cannot hold: out of range.
                    Err(_) if obj.is_instance_of::<PyInt>() || obj.hasattr("__index__")? => {
                        let shown = obj.str().map_or_else(|_| "?".to_owned(), |s| s.to_string());
                        Err(PyValueError::new_err(format!(
                            "{name}: {shown} is not a whole number in {}..={}",
                            <$int>::MIN,
                            <$int>::MAX
                        )))
                    }
                    Err(_) => Err(wrong_type(obj, name, "a whole number (int)")),
                }
            }
        }
    )*};
}

whole_numbers!(u8, u16, u32, u64, usize, i64);

impl Argument for f64 {
    /// A Python `float` or `int` (or an object with `__float__`, as NumPy's
    /// floats): what PyO3 takes, with the argument named in the refusals.
    fn read(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Self> {
        if obj.is_instance_of::<PyFloat>() || obj.is_instance_of::<PyInt>() {
            return obj.extract::<Self>().map_err(|e| {
                // An int too big for a float.
                PyValueError::new_err(format!("{name}: {e}"))
            });
        }
        obj.extract::<Self>()
            .map_err(|_| wrong_type(obj, name, "a number"))
    }
}

impl Argument for bool {
    /// `True` or `False` (or NumPy's `bool_`): a number is not a flag.
    fn read(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Self> {
        obj.extract::<Self>()
            .map_err(|_| wrong_type(obj, name, "True or False"))
    }
}

impl Argument for String {
    /// A `str`.
    fn read(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Self> {
        obj.extract::<Self>()
            .map_err(|_| wrong_type(obj, name, "a str"))
    }
}

impl Argument for std::path::PathBuf {
    /// A `str` or an `os.PathLike` path.
    fn read(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Self> {
        obj.extract::<Self>()
            .map_err(|_| wrong_type(obj, name, "a path (str or os.PathLike)"))
    }
}

impl Argument for Vec<String> {
    /// A list or tuple of `str` (not one `str`: its letters are not names).
    fn read(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Self> {
        if obj.is_instance_of::<PyString>() {
            return Err(wrong_type(obj, name, "a list of str"));
        }
        obj.extract::<Self>()
            .map_err(|_| wrong_type(obj, name, "a list of str"))
    }
}

impl Argument for (f64, f64, f64) {
    /// Three numbers (a tuple, list or array of them).
    fn read(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Self> {
        let what = "three numbers (latitude_deg, longitude_deg, altitude_m)";
        if obj.is_instance_of::<PyString>() {
            return Err(wrong_type(obj, name, what));
        }
        let items: Vec<Bound<'_, PyAny>> =
            obj.extract().map_err(|_| wrong_type(obj, name, what))?;
        let [lat, lon, alt] = items.as_slice() else {
            return Err(PyValueError::new_err(format!(
                "{name}: expected {what}, got {} items",
                items.len()
            )));
        };
        Ok((
            f64::read(lat, name)?,
            f64::read(lon, name)?,
            f64::read(alt, name)?,
        ))
    }
}

impl<T: Argument> Argument for Option<T> {
    /// `None`, or a `T`.
    fn read(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Self> {
        if obj.is_none() {
            Ok(None)
        } else {
            T::read(obj, name).map(Some)
        }
    }
}

/// Defines each reader `$reader` of the argument `$name` of type `$ty`, for
/// `#[pyo3(from_py_with = args::$reader)]`.
macro_rules! readers {
    ($($reader:ident: $ty:ty = $name:literal;)*) => {$(
        #[doc = concat!("The argument `", $name, "` (`", stringify!($ty), "`): [`Argument::read`].")]
        ///
        /// # Errors
        /// `TypeError` or `ValueError` naming the argument.
        pub fn $reader(obj: &Bound<'_, PyAny>) -> PyResult<$ty> {
            <$ty as Argument>::read(obj, $name)
        }
    )*};
}

/// The argument `fps` (`u32`): a whole number in `1..=`[`MAX_FPS`], the
/// frame rates the run library takes, every refusal with the same message
/// (`fps: 0 is not a whole number in 1..=10000`).
///
/// # Errors
/// `TypeError` for the wrong kind of object, `ValueError` out of range.
pub fn fps(obj: &Bound<'_, PyAny>) -> PyResult<u32> {
    let out_of_range = || {
        let shown = obj.str().map_or_else(|_| "?".to_owned(), |s| s.to_string());
        PyValueError::new_err(format!(
            "fps: {shown} is not a whole number in 1..={MAX_FPS}"
        ))
    };
    match u32::read(obj, "fps") {
        Ok(fps) if (1..=MAX_FPS).contains(&fps) => Ok(fps),
        Ok(_) => Err(out_of_range()),
        Err(e) if e.is_instance_of::<PyValueError>(obj.py()) => Err(out_of_range()),
        Err(e) => Err(e),
    }
}

/// `obj` as one of `choices` (a `str`), for the argument `name`: a
/// `&'static str`, so that the argument's default can be a literal (which
/// PyO3 shows in the text signature the stubs are checked against).
fn choice(obj: &Bound<'_, PyAny>, name: &str, choices: &[&'static str]) -> PyResult<&'static str> {
    let text = String::read(obj, name)?;
    choices.iter().copied().find(|c| *c == text).ok_or_else(|| {
        let (last, rest) = choices.split_last().unwrap_or((&"", &[]));
        PyValueError::new_err(format!(
            "{name}: {text:?} is not {} or {last}",
            rest.join(", ")
        ))
    })
}

/// The argument `precision`: `"exact"` or `"fast"`.
///
/// # Errors
/// `TypeError` or `ValueError` naming the argument.
pub fn precision(obj: &Bound<'_, PyAny>) -> PyResult<&'static str> {
    choice(obj, "precision", &["exact", "fast"])
}

/// The argument `dr`: a dead-reckoning algorithm's short name.
///
/// # Errors
/// `TypeError` or `ValueError` naming the argument.
pub fn dr(obj: &Bound<'_, PyAny>) -> PyResult<&'static str> {
    choice(obj, "dr", &["fpw", "rpw", "rvw", "fvw"])
}

readers! {
    model: String = "model";
    n_frames: u64 = "n";
    n_aircraft: usize = "n";
    frames: u64 = "frames";
    altitude_ft: Option<f64> = "altitude_ft";
    speed_kt: Option<f64> = "speed_kt";
    heading_deg: Option<f64> = "heading_deg";
    trim: bool = "trim";
    script: Option<String> = "script";
    actions: Option<Vec<String>> = "actions";
    origin: Option<(f64, f64, f64)> = "origin";
    reference_time: Option<String> = "reference_time";
    title: Option<String> = "title";
    target: String = "target";
    entity: u16 = "entity";
    callsign: Option<String> = "callsign";
    site: u16 = "site";
    application: u16 = "application";
    exercise: u8 = "exercise";
    version: u8 = "version";
    position_threshold_m: f64 = "position_threshold_m";
    orientation_threshold_deg: f64 = "orientation_threshold_deg";
    heartbeat_s: f64 = "heartbeat_s";
    every_frame: bool = "every_frame";
    parallel: bool = "parallel";
    task: String = "task";
    max_steps: i64 = "max_steps";
    observe: bool = "observe";
    views: bool = "views";
    text: String = "text";
    path: std::path::PathBuf = "path";
    runs: Option<u64> = "runs";
    seed: Option<u64> = "seed";
    first: u64 = "first";
    end: u64 = "end";
    threads: Option<usize> = "threads";
    trajectory: bool = "trajectory";
    salvage: bool = "salvage";
}
