//! A run: one aircraft of a [`Scenario`] flying in an `fdm_ecs::Simulation`,
//! driven frame by frame or to the end, headless or paced, with outputs
//! attached.

use std::sync::Arc;
use std::time::Instant;

use fdm_core::model::{FlightStatus, FlightView, Model};
use fdm_core::script::ScriptCursor;
use fdm_ecs::{EcsError, Entity, Resources, Simulation};

use crate::output::{Event, Frame, Output, OutputError, Placement};
use crate::pacer::FramePacer;
use crate::scenario::{Scenario, ScenarioError, MAX_FPS};

/// Why a run stopped or could not start.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The scenario is not valid.
    #[error(transparent)]
    Scenario(#[from] ScenarioError),
    /// The ECS refused an operation.
    #[error(transparent)]
    Ecs(#[from] EcsError),
    /// The model's step produced a non-finite state on frame `frame`; the
    /// aircraft keeps its last finite state and the run cannot go on.
    #[error("the {model} model diverged (non-finite state) at dt = {dt} s")]
    Diverged {
        /// The model's name.
        model: &'static str,
        /// The frame (since the start or the last reset).
        frame: u64,
        /// The time step, as the model's own type prints it (e.g.
        /// `0.033333335` for Bourg's `f32`).
        dt: String,
    },
    /// An output failed. Display is the output's own message and
    /// [`std::error::Error::source`] is its cause (the error is transparent),
    /// so a chain printer (`anyhow`'s `{:#}`) shows e.g. `writing CSV file
    /// out.csv: disk full`, not only the first half.
    #[error(transparent)]
    Output(OutputError),
    /// The aircraft is no longer in the simulation.
    #[error("the {0} aircraft is gone from the simulation")]
    Gone(&'static str),
}

/// How a [`Run::run_to_end`] ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct End {
    /// Frames flown by this call.
    pub frames: u64,
    /// With real-time pacing: frames that missed their deadline.
    pub overruns: Option<u64>,
}

/// One flight of model `M`: a [`Scenario`] flown in its own
/// `fdm_ecs::Simulation` (one aircraft entity, the thesis schedule), with
/// any number of [`Output`]s attached.
///
/// Drive it frame by frame ([`Self::step_frame`]: the script's actions for
/// the frame, then the caller's) or to the end ([`Self::run_to_end`]),
/// headless (as fast as possible) or paced at 1/fps of wall-clock time per
/// frame ([`Self::with_realtime`]).
pub struct Run<M: Model> {
    sim: Simulation,
    entity: Entity,
    scenario: Scenario<M>,
    cursor: ScriptCursor,
    /// Frames since the start or the last reset.
    frame: u64,
    /// Frames flown since the run began.
    flown: u64,
    buffer: Vec<M::Action>,
    outputs: Vec<Box<dyn Output<M>>>,
    realtime: bool,
}

impl<M: Model> std::fmt::Debug for Run<M> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Run")
            .field("model", &M::NAME)
            .field("entity", &self.entity)
            .field("frame", &self.frame)
            .field("flown", &self.flown)
            .field("outputs", &self.outputs.len())
            .finish_non_exhaustive()
    }
}

impl<M: Model> Run<M> {
    /// The scenario's aircraft in a simulation of its own, nothing attached.
    ///
    /// # Errors
    /// A frame rate the scenario or the ECS refuses.
    pub fn new(scenario: Scenario<M>) -> Result<Self, RunError> {
        if !(1..=MAX_FPS).contains(&scenario.fps) {
            return Err(ScenarioError::Fps(scenario.fps).into());
        }
        let resources = Resources::new(f64::from(scenario.fps))?.with_origin(scenario.origin);
        let mut sim = Simulation::new(resources);
        let start = &scenario.start;
        let entity = sim.spawn::<M>(
            Arc::new(start.aircraft.clone()),
            start.controls,
            start.state,
        );
        Ok(Self {
            sim,
            entity,
            scenario,
            cursor: ScriptCursor::new(),
            frame: 0,
            flown: 0,
            buffer: Vec::new(),
            outputs: Vec::new(),
            realtime: false,
        })
    }

    /// Paces [`Self::run_to_end`] at one frame per 1/fps of wall-clock time.
    #[must_use]
    pub fn with_realtime(mut self, realtime: bool) -> Self {
        self.realtime = realtime;
        self
    }

    /// Attaches `output`: it takes frame 0 now ([`Event::Start`]) and every
    /// later frame and reset.
    ///
    /// # Errors
    /// The output fails on frame 0.
    pub fn attach(&mut self, output: impl Output<M> + 'static) -> Result<(), RunError> {
        let mut output: Box<dyn Output<M>> = Box::new(output);
        self.emit(Event::Start, std::slice::from_mut(&mut output), &[])?;
        self.outputs.push(output);
        Ok(())
    }

    /// Flies one frame: the script's actions for the next frame (in file
    /// order), then `keys` in order, then one model step; the outputs take
    /// the frame.
    ///
    /// # Errors
    /// [`RunError::Diverged`] when the step produced a non-finite state
    /// (after the outputs took the frame, its status
    /// [`FlightStatus::Diverged`]), or a failing output.
    pub fn step_frame(&mut self, keys: &[M::Action]) -> Result<(), RunError> {
        let mut actions = std::mem::take(&mut self.buffer);
        actions.clear();
        actions.extend(
            self.cursor
                .actions(&self.scenario.script, self.frame.saturating_add(1)),
        );
        actions.extend_from_slice(keys);
        let result = self.step_actions(&actions);
        self.buffer = actions;
        result
    }

    /// Flies one frame applying exactly `actions`, in order (no script):
    /// what a replay or a caller that merges its own inputs uses.
    ///
    /// # Errors
    /// As [`Self::step_frame`].
    pub fn step_actions(&mut self, actions: &[M::Action]) -> Result<(), RunError> {
        for &action in actions {
            self.sim.push_input(self.entity, action)?;
        }
        self.sim.run_frame();
        self.frame += 1;
        self.flown += 1;
        let mut outputs = std::mem::take(&mut self.outputs);
        let emitted = self.emit(Event::Step, &mut outputs, actions);
        self.outputs = outputs;
        if self.status() == FlightStatus::Diverged {
            return Err(RunError::Diverged {
                model: M::NAME,
                frame: self.frame,
                dt: format!("{:?}", M::time_step(f64::from(self.scenario.fps))),
            });
        }
        emitted
    }

    /// Puts the aircraft back to the scenario's start (frame 0; the script
    /// starts over); the outputs take the reset.
    ///
    /// # Errors
    /// The ECS refuses, or an output fails.
    pub fn reset(&mut self) -> Result<(), RunError> {
        let start = &self.scenario.start;
        self.sim
            .reset::<M>(self.entity, start.controls, start.state)?;
        self.frame = 0;
        self.cursor.reset();
        let mut outputs = std::mem::take(&mut self.outputs);
        let emitted = self.emit(Event::Reset, &mut outputs, &[]);
        self.outputs = outputs;
        emitted
    }

    /// Flies the scenario's remaining frames (up to [`Scenario::frames`]
    /// since the start or the last reset), paced if asked.
    ///
    /// # Errors
    /// As [`Self::step_frame`]; the frames flown so far stay flown.
    pub fn run_to_end(&mut self) -> Result<End, RunError> {
        let mut pacer = self
            .realtime
            .then(|| FramePacer::new(FramePacer::period_for(self.scenario.fps), Instant::now()));
        let mut frames = 0;
        while self.frame < self.scenario.frames {
            self.step_frame(&[])?;
            frames += 1;
            if let Some(pacer) = pacer.as_mut() {
                let sleep = pacer.finish_frame(Instant::now());
                if !sleep.is_zero() {
                    std::thread::sleep(sleep);
                }
            }
        }
        Ok(End {
            frames,
            overruns: pacer.map(|p| p.overruns()),
        })
    }

    /// Completes every output (in the order attached); all are finished
    /// even when one fails, and the first failure is returned.
    ///
    /// # Errors
    /// The first failing output.
    pub fn finish(&mut self) -> Result<(), RunError> {
        let mut first = None;
        for output in &mut self.outputs {
            if let Err(e) = output.finish() {
                first.get_or_insert(e);
            }
        }
        first.map_or(Ok(()), |e| Err(RunError::Output(e)))
    }

    /// Hands every output in `outputs` the current frame.
    fn emit(
        &self,
        event: Event,
        outputs: &mut [Box<dyn Output<M>>],
        actions: &[M::Action],
    ) -> Result<(), RunError> {
        if outputs.is_empty() {
            return Ok(());
        }
        let state = self.state()?;
        let controls = self.controls()?;
        let view = self.view();
        let placement = self.placement();
        let frame = Frame {
            event,
            number: self.frame,
            flown: self.flown,
            fps: self.scenario.fps,
            actions,
            controls: &controls,
            state: &state,
            view: &view,
            placement: &placement,
            status: self.status(),
        };
        for output in outputs {
            output.frame(&frame).map_err(RunError::Output)?;
        }
        Ok(())
    }

    /// The scenario flown.
    #[must_use]
    pub fn scenario(&self) -> &Scenario<M> {
        &self.scenario
    }

    /// Frames since the start or the last reset.
    #[must_use]
    pub fn frame(&self) -> u64 {
        self.frame
    }

    /// Frames flown since the run began, across resets.
    #[must_use]
    pub fn flown(&self) -> u64 {
        self.flown
    }

    /// The model's state now.
    ///
    /// # Errors
    /// [`RunError::Gone`] if the aircraft was removed from the simulation.
    pub fn state(&self) -> Result<M::State, RunError> {
        self.sim
            .state::<M>(self.entity)
            .ok_or(RunError::Gone(M::NAME))
    }

    /// The model's controls now.
    ///
    /// # Errors
    /// As [`Self::state`].
    pub fn controls(&self) -> Result<M::Controls, RunError> {
        self.sim
            .controls::<M>(self.entity)
            .ok_or(RunError::Gone(M::NAME))
    }

    /// The model's common view now (of the start if the aircraft is gone).
    #[must_use]
    pub fn view(&self) -> FlightView {
        self.sim.view::<M>(self.entity).unwrap_or_else(|| {
            let s = &self.scenario.start;
            M::view(&s.aircraft, &s.controls, &s.state)
        })
    }

    /// The flight status now.
    #[must_use]
    pub fn status(&self) -> FlightStatus {
        self.sim
            .status(self.entity)
            .unwrap_or(FlightStatus::OnGround)
    }

    /// The aircraft on WGS-84 as of the last frame (computed once per frame
    /// by the ECS's Place system; NaN if the aircraft is gone).
    #[must_use]
    pub fn placement(&self) -> Placement {
        match (
            self.sim.geodetic(self.entity),
            self.sim.attitude(self.entity),
        ) {
            (Some(geodetic), Some(attitude)) => Placement { geodetic, attitude },
            _ => Placement {
                geodetic: fdm_core::geodesy::Geodetic {
                    lat_deg: f64::NAN,
                    lon_deg: f64::NAN,
                    alt_m: f64::NAN,
                },
                attitude: fdm_core::geodesy::Attitude {
                    roll_deg: f64::NAN,
                    pitch_deg: f64::NAN,
                    heading_deg: f64::NAN,
                },
            },
        }
    }

    /// The simulation the aircraft flies in.
    #[must_use]
    pub fn simulation(&self) -> &Simulation {
        &self.sim
    }

    /// The simulation, for what the run does not wrap.
    pub fn simulation_mut(&mut self) -> &mut Simulation {
        &mut self.sim
    }

    /// The aircraft's entity.
    #[must_use]
    pub fn entity(&self) -> Entity {
        self.entity
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Start;
    use fdm_core::palmer::Palmer;

    /// An output that takes every frame and keeps nothing.
    struct Quiet;

    impl<M: Model> Output<M> for Quiet {
        fn frame(&mut self, _: &Frame<'_, M>) -> Result<(), OutputError> {
            Ok(())
        }
    }

    /// `frame` counts frames since the start or the last reset and `flown`
    /// every frame; a run shows both, its model, entity and how many outputs
    /// are attached (not the outputs themselves, which need not be `Debug`).
    #[test]
    fn debug_shows_the_model_and_the_counts() {
        let mut run = Run::new(Scenario::<Palmer>::new(Start::thesis(), 30, 5).unwrap()).unwrap();
        run.attach(Quiet).unwrap();
        run.step_frame(&[]).unwrap();
        run.step_frame(&[]).unwrap();
        assert_eq!((run.frame(), run.flown()), (2, 2));
        run.reset().unwrap();
        assert_eq!((run.frame(), run.flown()), (0, 2));
        run.step_frame(&[]).unwrap();
        assert_eq!((run.frame(), run.flown()), (1, 3));
        let shown = format!("{run:?}");
        let entity = format!("{:?}", run.entity());
        assert_eq!(
            shown,
            format!(
                "Run {{ model: \"palmer\", entity: {entity}, frame: 1, flown: 3, outputs: 1, .. }}"
            )
        );
    }

    /// `run_to_end` with real-time pacing takes a period a frame (10 frames
    /// at 50 fps: at least 150 ms, allowing for the first frame, which is
    /// not waited for, and the timer's granularity) and counts overruns;
    /// headless it counts none (`None`).
    #[test]
    fn a_paced_run_takes_a_period_a_frame() {
        let scenario = Scenario::<Palmer>::new(Start::thesis(), 50, 10).unwrap();
        let mut paced = Run::new(scenario.clone()).unwrap().with_realtime(true);
        let started = Instant::now();
        let end = paced.run_to_end().unwrap();
        let took = started.elapsed();
        assert_eq!(end.frames, 10);
        assert!(end.overruns.is_some());
        assert!(took >= std::time::Duration::from_millis(150), "{took:?}");
        let headless = Run::new(scenario).unwrap().run_to_end().unwrap();
        assert_eq!(
            headless,
            End {
                frames: 10,
                overruns: None
            }
        );
    }
}
