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
