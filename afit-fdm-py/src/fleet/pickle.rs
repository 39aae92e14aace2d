//! A fleet as `pickle` holds it (`Fleet.__reduce__`, `Fleet._from_pickle`).
//!
//! The bytes, in bincode's standard encoding (floats as their bits, so every
//! aircraft comes back bit for bit): the format version and the model's
//! name; the frame rate, the precision's name, whether the fleet steps on
//! rayon's pool, and the number of aircraft; then one record per aircraft:
//! its state, controls and flight status. The records are read one at a
//! time, each under the flight pickle's 16 MiB limit, so a fleet of any size
//! travels, and a damaged count cannot ask for more memory than the bytes
//! could hold (every record takes at least one byte).

use fdm_core::model::FlightStatus;
use fdm_core::script::Echo;
use fdm_fleet::Precision;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use super::{check_memory, AnyFleet, Lanes};
use crate::flight::{check_controls, pickle_config, pickle_header};
use crate::models::{BindModel, FleetOps};

/// The version of the bytes, their first field: a fleet pickled by another
/// version of the package is refused by name, not misread.
const FORMAT: u32 = 1;

/// What follows the format and the model's name.
#[derive(serde::Serialize, serde::Deserialize)]
struct Header {
    fps: f64,
    precision: String,
    parallel: bool,
    aircraft: u64,
}

/// [`AnyFleet::pickled`] of a fleet of model `M`.
pub(super) fn pickled<M: BindModel>(lanes: &Lanes<M>) -> Vec<u8> {
    let header = Header {
        fps: lanes.fps,
        precision: lanes.precision.name().to_owned(),
        parallel: lanes.parallel,
        aircraft: lanes.len as u64,
    };
    let mut bytes = Vec::new();
    // Plain data of known size into a vector: encoding cannot fail.
    let _ = bincode::serde::encode_into_std_write(
        (FORMAT, M::NAME, header),
        &mut bytes,
        pickle_config(),
    );
    let mut states = Vec::with_capacity(lanes.len);
    lanes.fleet.for_each_state(|_, s| states.push(*s));
    let mut statuses = Vec::with_capacity(lanes.len);
    lanes.fleet.for_each_status(|_, s| statuses.push(s));
    for (i, (state, status)) in states.into_iter().zip(statuses).enumerate() {
        let controls = lanes.fleet.controls(i).unwrap_or_else(M::initial_controls);
        let record = (state, controls, status);
        let _ = bincode::serde::encode_into_std_write(record, &mut bytes, pickle_config());
    }
    bytes
}

/// A fleet from the bytes of [`AnyFleet::pickled`].
///
/// # Errors
/// `ValueError` for bytes that are not a fleet of this package's format
/// (another format version, an unknown model, damaged or cut bytes, bytes
/// after the last aircraft, numbers no fleet has: a frame rate out of range,
/// an unknown precision, a state that is not finite, controls out of their
/// ranges); `MemoryError` for more aircraft than this process can hold
/// ([`check_memory`]).
pub fn restore(data: &[u8]) -> PyResult<Box<dyn AnyFleet>> {
    let (model, body) = pickle_header(data, "fleet", FORMAT).map_err(refused)?;
    struct Restore<'a>(&'a [u8]);
    impl crate::models::ModelJob for Restore<'_> {
        type Output = PyResult<Box<dyn AnyFleet>>;
        fn call<M: crate::models::RegisteredModel>(self) -> Self::Output {
            restore_model::<M>(self.0)
        }
    }
    crate::models::with_model(&model, Restore(body))
        .unwrap_or_else(|| Err(refused(format!("`{}` is not a model", Echo::short(&model)))))
}

fn refused(why: String) -> PyErr {
    PyValueError::new_err(format!("Fleet: cannot restore a pickled fleet: {why}"))
}

/// [`restore`] of model `M`, from the bytes after the model's name.
fn restore_model<M: BindModel>(data: &[u8]) -> PyResult<Box<dyn AnyFleet>> {
    let (header, mut at): (Header, usize) =
        bincode::serde::decode_from_slice(data, pickle_config())
            .map_err(|e| refused(format!("damaged ({e})")))?;
    let fps = header.fps;
    let max_fps = f64::from(fdm_run::MAX_FPS);
    if !(fps.fract() == 0.0 && (1.0..=max_fps).contains(&fps)) {
        return Err(refused(format!(
            "fps {fps} is not a whole number in 1..={max_fps}"
        )));
    }
    let precision: Precision = header
        .precision
        .parse()
        .map_err(|e| refused(format!("precision: {e}")))?;
    M::Fleet::check_precision(precision).map_err(|e| refused(format!("precision: {e}")))?;
    let remaining = (data.len() - at) as u64;
    if header.aircraft > remaining {
        return Err(refused(format!(
            "{} aircraft in {remaining} bytes: cut or damaged",
            header.aircraft
        )));
    }
    // At most `remaining`, so it fits in a usize.
    let n = usize::try_from(header.aircraft).unwrap_or(usize::MAX);
    check_memory::<M>(n, fdm_run::memory::available_bytes())?;
    let mut fleet = M::Fleet::empty().map_err(|e| refused(e.to_string()))?;
    for i in 0..n {
        let ((state, controls, status), used): ((M::State, M::Controls, FlightStatus), usize) =
            bincode::serde::decode_from_slice(&data[at..], pickle_config())
                .map_err(|e| refused(format!("aircraft {i}: damaged ({e})")))?;
        at += used;
        if !M::is_finite(&state) {
            return Err(refused(format!("aircraft {i}: the state is not finite")));
        }
        check_controls::<M>(&controls)
            .map_err(|e| refused(format!("aircraft {i}: the controls: {e}")))?;
        fleet.push(state, controls);
        fleet
            .set_status(i, status)
            .map_err(|e| refused(e.to_string()))?;
    }
    if at != data.len() {
        let more = data.len() - at;
        let plural = if more == 1 { "" } else { "s" };
        return Err(refused(format!("{more} byte{plural} after the fleet")));
    }
    Ok(Box::new(Lanes::<M> {
        fleet,
        len: n,
        fps,
        precision,
        parallel: header.parallel,
    }))
}
