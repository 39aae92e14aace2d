//! [`SharedOutput`]: an output the caller keeps a handle to.

use std::sync::{Arc, Mutex, PoisonError};

use fdm_core::model::Model;

use crate::output::{Frame, Output, OutputError};

/// An output shared between a [`Run`](crate::Run) and its caller: attach a
/// clone, keep one, and look at (or take back) the output at any time.
#[derive(Debug)]
pub struct SharedOutput<O>(Arc<Mutex<Option<O>>>);

impl<O> Clone for SharedOutput<O> {
    fn clone(&self) -> Self {
        Self(Arc::clone(&self.0))
    }
}

impl<O> SharedOutput<O> {
    /// Shares `output`.
    #[must_use]
    pub fn new(output: O) -> Self {
        Self(Arc::new(Mutex::new(Some(output))))
    }

    /// Calls `f` with the output (`None` once taken).
    pub fn with<R>(&self, f: impl FnOnce(Option<&mut O>) -> R) -> R {
        let mut guard = self.0.lock().unwrap_or_else(PoisonError::into_inner);
        f(guard.as_mut())
    }

    /// Takes the output back; the run's clone then does nothing.
    #[must_use]
    pub fn take(&self) -> Option<O> {
        self.0.lock().unwrap_or_else(PoisonError::into_inner).take()
    }
}

impl<M: Model, O: Output<M>> Output<M> for SharedOutput<O> {
    fn frame(&mut self, frame: &Frame<'_, M>) -> Result<(), OutputError> {
        self.with(|o| o.map_or(Ok(()), |o| o.frame(frame)))
    }

    fn finish(&mut self) -> Result<(), OutputError> {
        self.with(|o| o.map_or(Ok(()), Output::finish))
    }
}
