//! What the binding needs of a model beyond the run library's registry
//! (`fdm_run::model`): one adapter to each model's fleet ([`FleetOps`]) and
//! the status codes. The models themselves, their named columns
//! ([`ColumnModel`]) and how the Gymnasium tasks act on them
//! ([`AgentModel`]), are the run library's, which picks a model by name
//! ([`MODELS`], [`with_model`] running a [`ModelJob`]): no file of this
//! crate names a model; everything is generic over [`BindModel`].

use fdm_core::model::FlightStatus;
use fdm_fleet::{Fleet, FleetError, FleetKernel, FleetPiece, Precision};

pub use fdm_run::model::agent::AgentModel;
pub use fdm_run::model::columns::{ColumnModel, ControlRange, MAX_BLOCK_FIELDS};
pub use fdm_run::model::{with_model, ModelJob, RegisteredModel, MODELS};

/// A model as the Python binding exposes it: any model of the run
/// library's registry ([`RegisteredModel`]: its columns, its agent's tasks,
/// its fleet kernel), with its fleet behind the binding's one adapter.
pub trait BindModel: RegisteredModel {
    /// The model's fleet kernel behind the one adapter the binding uses.
    type Fleet: FleetOps<Self> + Sync + Clone;
}

/// Every model of the registry, its fleet `fdm-fleet`'s one generic
/// [`Fleet`].
impl<M: RegisteredModel> BindModel for M {
    type Fleet = Fleet<M>;
}

/// The few fleet operations the binding uses, over `fdm-fleet`'s one
/// generic [`Fleet`].
pub trait FleetOps<M: FleetKernel>: Send + Sized {
    /// An empty fleet of the model's default aircraft.
    ///
    /// # Errors
    /// The kernel's refusal of the aircraft.
    fn empty() -> Result<Self, FleetError>;
    /// Adds an aircraft.
    fn push(&mut self, state: M::State, controls: M::Controls);
    /// Replaces aircraft `index`'s state, controls and status.
    ///
    /// # Errors
    /// Out of range.
    fn set(
        &mut self,
        index: usize,
        state: &M::State,
        controls: M::Controls,
        status: FlightStatus,
    ) -> Result<(), FleetError>;
    /// Replaces aircraft `index`'s controls.
    ///
    /// # Errors
    /// Out of range.
    fn set_controls(&mut self, index: usize, controls: M::Controls) -> Result<(), FleetError>;
    /// Replaces aircraft `index`'s flight status.
    ///
    /// # Errors
    /// Out of range.
    fn set_status(&mut self, index: usize, status: FlightStatus) -> Result<(), FleetError>;
    /// Aircraft `index`'s controls.
    fn controls(&self, index: usize) -> Option<M::Controls>;
    /// Aircraft `index`'s state.
    fn state_at(&self, index: usize) -> Option<M::State>;
    /// Aircraft `index`'s status.
    fn status_at(&self, index: usize) -> Option<FlightStatus>;
    /// Every aircraft's controls become `f(index, controls)`, on rayon's
    /// pool when `parallel`.
    fn update_controls(
        &mut self,
        parallel: bool,
        f: impl Fn(usize, M::Controls) -> M::Controls + Sync,
    );
    /// One frame of every aircraft with its status ([`fdm_core::model::fly`]),
    /// on this thread or on rayon's pool.
    ///
    /// # Errors
    /// A precision the kernel does not have ([`Self::check_precision`],
    /// which the constructor already asked).
    fn fly(&mut self, fps: f64, precision: Precision, parallel: bool) -> Result<(), FleetError>;
    /// `frames` calls of [`Self::fly`], with the same bits, each cache-sized
    /// run of blocks flown every frame before the next
    /// ([`Fleet::fly_frames_with`]).
    ///
    /// # Errors
    /// As [`Self::fly`] (nothing is flown then).
    fn fly_frames(
        &mut self,
        fps: f64,
        precision: Precision,
        parallel: bool,
        frames: usize,
    ) -> Result<(), FleetError>;
    /// Every aircraft's state, in order.
    fn for_each_state(&self, f: impl FnMut(usize, &M::State));
    /// Every aircraft's status, in order.
    fn for_each_status(&self, f: impl FnMut(usize, FlightStatus));
    /// Whether the kernel has `precision`.
    ///
    /// # Errors
    /// When it does not.
    fn check_precision(precision: Precision) -> Result<(), FleetError>;
    /// The fleet as runs of `blocks` whole blocks ([`Fleet::pieces_mut`]).
    fn pieces_mut(&mut self, blocks: usize) -> Vec<FleetPiece<'_, M>>;
    /// Aircraft per block.
    fn lanes() -> usize;
    /// The instruction set the kernel dispatched to.
    fn instruction_set(&self) -> &'static str;
}

/// The integer code of a status (the CSV's `status` column of `sim-cli`,
/// without its report-only 6 "stalling").
pub const fn status_code(status: FlightStatus) -> u8 {
    fdm_core::model::DisplayStatus::new(status, false).number()
}

/// One adapter for every model with a lane instantiation: the fleets are one
/// generic type ([`Fleet`]).
impl<M> FleetOps<M> for Fleet<M>
where
    M: fdm_fleet::FleetKernel,
    M::Controls: Send + Sync,
    Self: Send,
{
    fn empty() -> Result<Self, FleetError> {
        Self::try_new(M::default_aircraft())
    }
    fn push(&mut self, state: M::State, controls: M::Controls) {
        Self::push(self, state, controls);
    }
    fn set(
        &mut self,
        index: usize,
        state: &M::State,
        controls: M::Controls,
        status: FlightStatus,
    ) -> Result<(), FleetError> {
        self.set_state(index, state)?;
        Self::set_controls(self, index, controls)?;
        self.set_status(index, status)
    }
    fn set_controls(&mut self, index: usize, controls: M::Controls) -> Result<(), FleetError> {
        Self::set_controls(self, index, controls)
    }
    fn set_status(&mut self, index: usize, status: FlightStatus) -> Result<(), FleetError> {
        Self::set_status(self, index, status)
    }
    fn controls(&self, index: usize) -> Option<M::Controls> {
        Self::controls(self, index)
    }
    fn state_at(&self, index: usize) -> Option<M::State> {
        self.state(index)
    }
    fn status_at(&self, index: usize) -> Option<FlightStatus> {
        self.status(index)
    }
    /// The fleet's own [`Fleet::par_update_controls`] on rayon's pool when
    /// `parallel`, else [`Fleet::update_controls`] (the same fleet either
    /// way).
    fn update_controls(
        &mut self,
        parallel: bool,
        f: impl Fn(usize, M::Controls) -> M::Controls + Sync,
    ) {
        if parallel {
            self.par_update_controls(f);
        } else {
            Self::update_controls(self, f);
        }
    }
    fn fly(&mut self, fps: f64, precision: Precision, parallel: bool) -> Result<(), FleetError> {
        let dt = M::time_step(fps);
        if parallel {
            self.par_fly_with(dt, precision)
        } else {
            self.fly_with(dt, precision)
        }
    }
    fn fly_frames(
        &mut self,
        fps: f64,
        precision: Precision,
        parallel: bool,
        frames: usize,
    ) -> Result<(), FleetError> {
        let dt = M::time_step(fps);
        if parallel {
            self.par_fly_frames_with(dt, precision, frames)
        } else {
            self.fly_frames_with(dt, precision, frames)
        }
    }
    fn for_each_state(&self, mut f: impl FnMut(usize, &M::State)) {
        for (i, s) in self.states().enumerate() {
            f(i, &s);
        }
    }
    fn for_each_status(&self, mut f: impl FnMut(usize, FlightStatus)) {
        for (i, s) in self.statuses().enumerate() {
            f(i, s);
        }
    }
    fn check_precision(precision: Precision) -> Result<(), FleetError> {
        Self::check_precision(precision)
    }
    fn pieces_mut(&mut self, blocks: usize) -> Vec<FleetPiece<'_, M>> {
        Self::pieces_mut(self, blocks)
    }
    fn lanes() -> usize {
        <M::Lanes as fdm_core::real::Real>::LANES
    }
    fn instruction_set(&self) -> &'static str {
        Self::instruction_set(self)
    }
}
