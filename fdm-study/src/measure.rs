//! The built-in measures of a run and the tracker that computes them frame
//! by frame, the same code for the batch (fleet lanes) and for a run flown
//! alone (`fdm_run::Run`), so both give the same bits.

use fdm_core::model::FlightStatus;

use crate::model::StudyModel;

/// Standard gravity, m/s² (the load factor's unit).
pub const STANDARD_GRAVITY_MPS2: f64 = 9.806_65;

/// A built-in measure of one run. Positions are in the model's earth frame
/// (x north, y west, z up, metres from the origin); "the end" is the last
/// frame flown (the duration, or the stop condition).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Measure {
    /// Time at the end, s.
    FinalTimeS,
    /// North position at the end, m.
    FinalXM,
    /// West position at the end, m.
    FinalYM,
    /// Height at the end, m.
    FinalHeightM,
    /// Ground speed (horizontal) at the end, m/s.
    FinalGroundSpeedMps,
    /// Lowest height over the run (frame 0 included), m.
    MinHeightM,
    /// Highest height over the run (frame 0 included), m.
    MaxHeightM,
    /// Time of the first touchdown, s (none without one).
    TouchdownTimeS,
    /// North position at the first touchdown, m.
    TouchdownXM,
    /// West position at the first touchdown, m.
    TouchdownYM,
    /// Ground speed at the last frame above the ground before the first
    /// touchdown, m/s.
    TouchdownGroundSpeedMps,
    /// Sink rate (positive down) at the last frame above the ground before
    /// the first touchdown, m/s.
    TouchdownSinkRateMps,
    /// Time the height first reaches `target_height_m`, s.
    TimeToHeightS,
    /// Horizontal distance from the start when the height first reaches
    /// `target_height_m`, m.
    DistanceToHeightM,
    /// Largest |bank| over the run, degrees.
    MaxBankDeg,
    /// Largest load factor over airborne frames, from the change of the
    /// earth-frame velocity between frames: |Δv/Δt + g ẑ| / g.
    MaxLoadFactor,
}

impl Measure {
    /// Every measure, in the order the docs list them.
    pub const ALL: &'static [Measure] = &[
        Self::FinalTimeS,
        Self::FinalXM,
        Self::FinalYM,
        Self::FinalHeightM,
        Self::FinalGroundSpeedMps,
        Self::MinHeightM,
        Self::MaxHeightM,
        Self::TouchdownTimeS,
        Self::TouchdownXM,
        Self::TouchdownYM,
        Self::TouchdownGroundSpeedMps,
        Self::TouchdownSinkRateMps,
        Self::TimeToHeightS,
        Self::DistanceToHeightM,
        Self::MaxBankDeg,
        Self::MaxLoadFactor,
    ];

    /// The measure's name in study files and column headers.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::FinalTimeS => "final_time_s",
            Self::FinalXM => "final_x_m",
            Self::FinalYM => "final_y_m",
            Self::FinalHeightM => "final_height_m",
            Self::FinalGroundSpeedMps => "final_ground_speed_mps",
            Self::MinHeightM => "min_height_m",
            Self::MaxHeightM => "max_height_m",
            Self::TouchdownTimeS => "touchdown_time_s",
            Self::TouchdownXM => "touchdown_x_m",
            Self::TouchdownYM => "touchdown_y_m",
            Self::TouchdownGroundSpeedMps => "touchdown_ground_speed_mps",
            Self::TouchdownSinkRateMps => "touchdown_sink_rate_mps",
            Self::TimeToHeightS => "time_to_height_s",
            Self::DistanceToHeightM => "distance_to_height_m",
            Self::MaxBankDeg => "max_bank_deg",
            Self::MaxLoadFactor => "max_load_factor",
        }
    }

    /// The measure named `name`.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.iter().copied().find(|m| m.name() == name)
    }

    /// Whether it needs the study's `target_height_m`.
    #[must_use]
    pub const fn needs_target_height(self) -> bool {
        matches!(self, Self::TimeToHeightS | Self::DistanceToHeightM)
    }
}

/// Follows one run frame by frame and gives its measures.
#[derive(Debug, Clone)]
pub struct Tracker {
    target_height_m: f64,
    needs_bank: bool,
    dt_s: f64,
    frames: u64,
    start_xy_m: [f64; 2],
    last_position_m: [f64; 3],
    last_velocity_mps: [f64; 3],
    last_time_s: f64,
    last_status: FlightStatus,
    min_height_m: f64,
    max_height_m: f64,
    touchdown: Option<[f64; 5]>,
    reached_height: Option<[f64; 2]>,
    max_bank_deg: f64,
    max_load_factor: Option<f64>,
}

impl Tracker {
    /// A tracker for a run at `fps` frames per second; `needs_bank` when the
    /// bank (the model's view, dearer than the other reads) is measured.
    #[must_use]
    pub fn new(fps: u32, target_height_m: Option<f64>, needs_bank: bool) -> Self {
        Self {
            target_height_m: target_height_m.unwrap_or(f64::INFINITY),
            needs_bank,
            dt_s: 1.0 / f64::from(fps),
            frames: 0,
            start_xy_m: [0.0; 2],
            last_position_m: [0.0; 3],
            last_velocity_mps: [0.0; 3],
            last_time_s: 0.0,
            last_status: FlightStatus::OnGround,
            min_height_m: f64::INFINITY,
            max_height_m: f64::NEG_INFINITY,
            touchdown: None,
            reached_height: None,
            max_bank_deg: 0.0,
            max_load_factor: None,
        }
    }

    /// Takes frame `number` (0 for the start) of an `M` aircraft.
    pub fn observe<M: StudyModel>(
        &mut self,
        number: u64,
        aircraft: &M::Aircraft,
        controls: &M::Controls,
        state: &M::State,
        status: FlightStatus,
    ) {
        let position: [f64; 3] = <M as fdm_fleet::LaneModel>::position_m(state).into();
        let velocity = M::velocity_mps(state);
        let time = M::time_s(state);
        let height = position[2];
        if number == 0 {
            self.start_xy_m = [position[0], position[1]];
        } else {
            if self.touchdown.is_none()
                && self.last_status == FlightStatus::Airborne
                && matches!(status, FlightStatus::Landed(_))
            {
                let [vx, vy, vz] = self.last_velocity_mps;
                self.touchdown = Some([
                    time,
                    position[0],
                    position[1],
                    fdm_core::math::hypot(vx, vy),
                    -vz,
                ]);
            }
            if self.last_status == FlightStatus::Airborne && status == FlightStatus::Airborne {
                let g = STANDARD_GRAVITY_MPS2;
                let a = |k: usize| (velocity[k] - self.last_velocity_mps[k]) / self.dt_s;
                let (ax, ay, az) = (a(0), a(1), a(2) + g);
                let n = fdm_core::math::sqrt(ax * ax + ay * ay + az * az) / g;
                if n.is_finite() {
                    self.max_load_factor = Some(self.max_load_factor.map_or(n, |m| m.max(n)));
                }
            }
        }
        if self.reached_height.is_none() && height >= self.target_height_m {
            let distance = fdm_core::math::hypot(
                position[0] - self.start_xy_m[0],
                position[1] - self.start_xy_m[1],
            );
            self.reached_height = Some([time, distance]);
        }
        self.min_height_m = self.min_height_m.min(height);
        self.max_height_m = self.max_height_m.max(height);
        if self.needs_bank {
            let bank = M::view(aircraft, controls, state).attitude.roll_deg.abs();
            if bank.is_finite() {
                self.max_bank_deg = self.max_bank_deg.max(bank);
            }
        }
        self.frames = number;
        self.last_position_m = position;
        self.last_velocity_mps = velocity;
        self.last_time_s = time;
        self.last_status = status;
    }

    /// Whether the run has touched down since its start.
    #[must_use]
    pub fn touched_down(&self) -> bool {
        self.touchdown.is_some()
    }

    /// The last frame observed.
    #[must_use]
    pub fn frames(&self) -> u64 {
        self.frames
    }

    /// The flight status at the last frame observed.
    #[must_use]
    pub fn status(&self) -> FlightStatus {
        self.last_status
    }

    /// The value of `measure`: `None` where it does not apply (no touchdown,
    /// target height never reached) or is not finite.
    #[must_use]
    pub fn value(&self, measure: Measure) -> Option<f64> {
        let [x, y, z] = self.last_position_m;
        let [vx, vy, _] = self.last_velocity_mps;
        let value = match measure {
            Measure::FinalTimeS => Some(self.last_time_s),
            Measure::FinalXM => Some(x),
            Measure::FinalYM => Some(y),
            Measure::FinalHeightM => Some(z),
            Measure::FinalGroundSpeedMps => Some(fdm_core::math::hypot(vx, vy)),
            Measure::MinHeightM => Some(self.min_height_m),
            Measure::MaxHeightM => Some(self.max_height_m),
            Measure::TouchdownTimeS => self.touchdown.map(|t| t[0]),
            Measure::TouchdownXM => self.touchdown.map(|t| t[1]),
            Measure::TouchdownYM => self.touchdown.map(|t| t[2]),
            Measure::TouchdownGroundSpeedMps => self.touchdown.map(|t| t[3]),
            Measure::TouchdownSinkRateMps => self.touchdown.map(|t| t[4]),
            Measure::TimeToHeightS => self.reached_height.map(|r| r[0]),
            Measure::DistanceToHeightM => self.reached_height.map(|r| r[1]),
            Measure::MaxBankDeg => Some(self.max_bank_deg),
            Measure::MaxLoadFactor => self.max_load_factor,
        };
        value.filter(|v| v.is_finite())
    }
}

/// Whether `M`'s runs need the tracker's per-frame view (for the bank).
#[must_use]
pub fn needs_view(measures: &[Measure]) -> bool {
    measures.contains(&Measure::MaxBankDeg)
}

#[cfg(test)]
mod tests {
    use super::*;
    use fdm_core::model::{FlightStatus, LandingState, Model};
    use fdm_core::palmer::{Palmer, PalmerControls, PalmerState};

    /// A Palmer state at `time_s`, `position_m`, `velocity_mps`.
    fn state(time_s: f64, position_m: [f64; 3], velocity_mps: [f64; 3]) -> PalmerState {
        PalmerState {
            time_s,
            position_m: position_m.into(),
            velocity_mps: velocity_mps.into(),
        }
    }

    /// The controls banked `bank_deg`.
    fn banked(bank_deg: f64) -> PalmerControls {
        PalmerControls {
            bank_deg,
            ..Palmer::initial_controls()
        }
    }

    /// A made-up flight at 10 frames per second whose measures are worked
    /// out by hand below: it reaches the target height of 120 m exactly at
    /// frame 2, tops out at frame 3, touches down at frame 4, bounces and
    /// touches down again at frame 6. Every number a mutant of the tracker
    /// could move (the touchdown's frame and the frame before it, `>=`
    /// against `>` at the target, the start's position, Δt) shows in one of
    /// the measures. The touchdown's own change of velocity is the largest
    /// of the flight (a load factor of about 510, from the ground's
    /// reaction), so a load factor taken over a frame on the ground would
    /// show.
    fn flight() -> Vec<(PalmerState, f64, FlightStatus)> {
        let up = FlightStatus::Airborne;
        let down = FlightStatus::Landed(LandingState::Safe);
        vec![
            (state(0.0, [1.0, 2.0, 100.0], [50.0, 0.0, 0.0]), 0.0, up),
            (state(0.1, [6.0, 2.0, 90.0], [50.0, 0.0, -1.0]), -10.0, up),
            (state(0.2, [10.0, 6.0, 120.0], [30.0, 40.0, 0.0]), 15.0, up),
            (state(0.3, [12.0, 4.0, 200.0], [3.0, 4.0, -5.0]), -20.0, up),
            (
                state(0.4, [13.0, 5.0, 0.0], [-300.0, 400.0, 0.0]),
                5.0,
                down,
            ),
            (state(0.5, [14.0, 6.0, 50.0], [1.0, 1.0, 1.0]), 0.0, up),
            (state(0.6, [15.0, 7.0, 0.0], [0.0, 0.0, -2.0]), 0.0, down),
        ]
    }

    /// The tracker after `frames` (numbered from 0).
    fn tracked(
        frames: &[(PalmerState, f64, FlightStatus)],
        target_height_m: Option<f64>,
        needs_bank: bool,
    ) -> Tracker {
        let aircraft = Palmer::default_aircraft();
        let mut tracker = Tracker::new(10, target_height_m, needs_bank);
        for (number, (state, bank_deg, status)) in frames.iter().enumerate() {
            tracker.observe::<Palmer>(number as u64, &aircraft, &banked(*bank_deg), state, *status);
        }
        tracker
    }

    /// Every measure of the made-up flight, against the numbers worked out
    /// by hand. The tolerance is 1e-12 relative where the tracker divides
    /// by Δt = 1/10 (not exact in binary: the accelerations carry a
    /// rounding of about 1e-16 relative) and none elsewhere (the positions
    /// and times are copied, the ground speeds are `hypot`s of 3-4-5
    /// triangles, exact).
    #[test]
    fn measures_of_a_made_up_flight_are_the_hand_worked_ones() {
        let tracker = tracked(&flight(), Some(120.0), true);
        let value = |m: Measure| tracker.value(m);
        for (measure, want) in [
            (Measure::FinalTimeS, 0.6),
            (Measure::FinalXM, 15.0),
            (Measure::FinalYM, 7.0),
            (Measure::FinalHeightM, 0.0),
            (Measure::FinalGroundSpeedMps, 0.0),
            (Measure::MinHeightM, 0.0),
            (Measure::MaxHeightM, 200.0),
            // The first touchdown (frame 4), with frame 3's velocity (3, 4, -5).
            (Measure::TouchdownTimeS, 0.4),
            (Measure::TouchdownXM, 13.0),
            (Measure::TouchdownYM, 5.0),
            (Measure::TouchdownGroundSpeedMps, 5.0),
            (Measure::TouchdownSinkRateMps, 5.0),
            // 120 m is reached at frame 2 (exactly: `>=`), hypot(9, 4) = √97
            // m from the start (1, 2) horizontally.
            (Measure::TimeToHeightS, 0.2),
            (Measure::DistanceToHeightM, fdm_core::math::hypot(9.0, 4.0)),
        ] {
            assert_eq!(value(measure), Some(want), "{}", measure.name());
        }
        assert!((fdm_core::math::hypot(9.0, 4.0) - 97.0_f64.sqrt()).abs() < 1e-12);
        // The largest |bank| is frame 3's 20 degrees (the view's roll,
        // through a rotation matrix: within 1e-9 degrees).
        let bank = value(Measure::MaxBankDeg).unwrap();
        assert!((bank - 20.0).abs() < 1e-9, "{bank}");
        // The load factor of the airborne pairs (0, 1), (1, 2), (2, 3) and
        // not (3, 4) (landed) nor (4, 5) (from the ground): Δv/Δt + g ẑ.
        // (0, 1): (0, 0, -10 + g); (1, 2): (-200, 400, 10 + g);
        // (2, 3): (-270, -360, -50 + g), the largest: sqrt(270² + 360² +
        // (g - 50)²) / g, with 270² + 360² = 450².
        let g = STANDARD_GRAVITY_MPS2;
        let want = (450.0_f64 * 450.0 + (g - 50.0) * (g - 50.0)).sqrt() / g;
        let n = value(Measure::MaxLoadFactor).unwrap();
        assert!((n - want).abs() <= 1e-12 * want, "{n} against {want}");
        assert!(want > 46.0 && want < 46.1);
        assert!(tracker.touched_down());
        assert_eq!(tracker.frames(), 6);
        assert_eq!(tracker.status(), FlightStatus::Landed(LandingState::Safe));
    }

    /// Before anything lands or climbs: no touchdown, no height reached
    /// (and none without a target height), no load factor from frame 0
    /// alone; the bank is 0 when it is not measured.
    #[test]
    fn measures_that_do_not_apply_are_none() {
        let frames = flight();
        let start = tracked(&frames[..1], Some(120.0), false);
        for m in [
            Measure::TouchdownTimeS,
            Measure::TouchdownXM,
            Measure::TouchdownYM,
            Measure::TouchdownGroundSpeedMps,
            Measure::TouchdownSinkRateMps,
            Measure::TimeToHeightS,
            Measure::DistanceToHeightM,
            Measure::MaxLoadFactor,
        ] {
            assert_eq!(start.value(m), None, "{}", m.name());
        }
        assert!(!start.touched_down());
        assert_eq!(start.frames(), 0);
        assert_eq!(start.status(), FlightStatus::Airborne);
        assert_eq!(start.value(Measure::MinHeightM), Some(100.0));
        assert_eq!(start.value(Measure::MaxHeightM), Some(100.0));
        assert_eq!(start.value(Measure::FinalGroundSpeedMps), Some(50.0));
        // Frame 1's load factor: (0, 0, -10 + g) / g.
        let two = tracked(&frames[..2], None, false);
        let g = STANDARD_GRAVITY_MPS2;
        let n = two.value(Measure::MaxLoadFactor).unwrap();
        let want = (10.0 - g) / g;
        assert!((n - want).abs() <= 1e-12, "{n} against {want}");
        // The whole flight without a target height, without the bank.
        let all = tracked(&frames, None, false);
        assert_eq!(all.value(Measure::TimeToHeightS), None);
        assert_eq!(all.value(Measure::DistanceToHeightM), None);
        assert_eq!(all.value(Measure::MaxBankDeg), Some(0.0));
    }

    /// A state that is not finite leaves the load factor and the bank as
    /// they were, and a measure that is not finite is `None`, never NaN.
    #[test]
    fn non_finite_frames_give_none_not_nan() {
        let mut frames = flight()[..3].to_vec();
        frames.push((
            state(0.3, [f64::NAN, 4.0, 200.0], [f64::NAN, 4.0, -5.0]),
            f64::NAN,
            FlightStatus::Airborne,
        ));
        let tracker = tracked(&frames, Some(120.0), true);
        assert_eq!(tracker.value(Measure::FinalXM), None);
        assert_eq!(tracker.value(Measure::FinalGroundSpeedMps), None);
        // The bank and load factor of frames 0 to 2 stand.
        let bank = tracker.value(Measure::MaxBankDeg).unwrap();
        assert!((bank - 15.0).abs() < 1e-9, "{bank}");
        let g = STANDARD_GRAVITY_MPS2;
        let want = (200.0_f64 * 200.0 + 400.0 * 400.0 + (10.0 + g) * (10.0 + g)).sqrt() / g;
        let n = tracker.value(Measure::MaxLoadFactor).unwrap();
        assert!((n - want).abs() <= 1e-12 * want, "{n} against {want}");
        assert_eq!(tracker.value(Measure::MaxHeightM), Some(200.0));
    }

    #[test]
    fn names_and_needs() {
        for &m in Measure::ALL {
            assert_eq!(Measure::from_name(m.name()), Some(m));
            assert_eq!(
                m.needs_target_height(),
                matches!(m, Measure::TimeToHeightS | Measure::DistanceToHeightM)
            );
        }
        assert_eq!(Measure::from_name("final_time"), None);
        let names: std::collections::HashSet<_> = Measure::ALL.iter().map(|m| m.name()).collect();
        assert_eq!(names.len(), Measure::ALL.len());
        assert!(needs_view(&[Measure::FinalXM, Measure::MaxBankDeg]));
        assert!(!needs_view(&[Measure::FinalXM, Measure::MaxLoadFactor]));
        assert!(!needs_view(&[]));
    }
}
