//! The models a run can fly and record, and the one registry that names them.
//!
//! [`RunModel`] is [`Model`] plus what a recording needs: serde state and
//! controls, and the aircraft's parameters as a storable record. The
//! registry ([`MODELS`], [`with_model`]) is the run library's list of its
//! models by name: the recording's and the flight CSV's model names
//! ([`Model::NAME`]; a flight CSV's first line is `# model: NAME`), and what
//! a program without models of its own (the Python bindings) reads
//! recordings, CSVs (`fdm_plot::csv::read_trace`) and study files
//! (`fdm_study::StudyEntry::registry`) with. `sim-cli`'s registry lists the
//! same models (and, with its `glider` feature, one outside the library
//! crates) and gives its own list to those readers. Its models also write
//! the flight CSV ([`CsvModel`]).
//!
//! [`FleetModel`] is what a fleet run ([`crate::fleet`]) needs besides: the
//! model's structure-of-arrays kernel, how to move a start for a formation,
//! and the model FlightGear draws for it as a multiplayer aircraft.
//!
//! [`NamedInputs`] is what a program setting a model up by name needs (a
//! study file's `[controls]` and `[aircraft]`, `fdm_study`): its controls
//! and physical parameters by name, with their ranges checked, and cheap
//! reads of a state.
//!
//! [`pilot::PilotModel`] is what a front end flying a model by hand needs
//! (`sim-cli`): what it flies, its start options as a table and the controls
//! at frame 0 from their values, its keys, its head-up display's controls
//! line.
//!
//! [`ColumnModel`] is a model's state and controls as named columns of
//! numbers, and [`AgentModel`] how a learning agent's actions set its
//! controls and what the agent's tasks observe (what the Python bindings
//! show and the Gymnasium tasks compute, so that they name no model).
//!
//! Each model's implementations of these traits (and of
//! [`ReportModel`](crate::report::ReportModel), its report's fields) are in
//! one adapter module per model: [`palmer`], [`bourg`]. A model of the
//! registry implements them all ([`RegisteredModel`]).

use std::fmt::Debug;

pub mod agent;
pub mod bourg;
pub mod columns;
pub mod palmer;
pub mod pilot;

use fdm_core::bourg::Bourg;
use fdm_core::message::ShortNumber;
use fdm_core::model::Model;
use fdm_core::palmer::Palmer;
use fdm_fleet::FleetKernel;
use serde::de::DeserializeOwned;
use serde::Serialize;

pub use agent::AgentModel;
pub use bourg::BourgAircraftRecord;
pub use columns::ColumnModel;

/// A model a run can fly, record and replay.
pub trait RunModel:
    Model<State: Serialize + DeserializeOwned, Controls: Serialize + DeserializeOwned>
{
    /// The aircraft's parameters as a recording stores them: everything
    /// needed to rebuild an identical [`Model::Aircraft`].
    type AircraftRecord: Serialize + DeserializeOwned + Debug;

    /// What Tacview shows for this model: its ACMI `Type` tags
    /// (e.g. `Air+FixedWing`) and object `Name`.
    const ACMI_TYPE: &'static str = "Air+FixedWing";

    /// The object `Name` Tacview shows (the aircraft type), e.g. `C172`.
    const ACMI_NAME: &'static str;

    /// The start of callsigns of this model's aircraft (ACMI and DIS
    /// markings): `C172-1`, `C172-2`, ...
    const CALLSIGN: &'static str;

    /// The model's DIS entity type (`fdm_run::dis`), a value of the
    /// registry: SISO-REF-010's seven numbers. The default is a small civil
    /// fixed-wing aircraft of no stated country or type (1.2.0.85.0.0.0).
    #[cfg(feature = "dis")]
    const DIS_KIND: fdm_dis::AircraftKind = fdm_dis::AircraftKind::SMALL_CIVIL_FIXED_WING;

    /// FlightGear's aircraft for this model (`fgfs --aircraft=...`,
    /// [`crate::fgfs`]).
    const FG_AIRCRAFT: &'static str;

    /// Further fgfs options that aircraft needs with `--fdm=null` (already
    /// shell-quoted where needed).
    const FG_OPTIONS: &'static [&'static str] = &[];

    /// Nasal statements FlightGear runs once its FDM is initialised (after the
    /// aircraft's own scripts, which reset properties given as `--prop:`
    /// options): property settings the aircraft needs with `--fdm=null`.
    /// Double quotes only (the whole script is one single-quoted shell word).
    const FG_STARTUP_NASAL: &'static str = "";

    /// The record of `aircraft`.
    fn aircraft_record(aircraft: &Self::Aircraft) -> Self::AircraftRecord;

    /// Rebuilds (and validates) the aircraft from its record.
    ///
    /// # Errors
    /// A one-line message naming what is wrong with the parameters.
    fn aircraft_from_record(record: Self::AircraftRecord) -> Result<Self::Aircraft, String>;

    /// A 64-bit hash of every bit of `state` (the `state` half of an
    /// [`fdm_core::fingerprint::Fingerprint`]): what a recording stores of
    /// its final state, so that a replay can tell whether it flew the same
    /// flight. Cheap enough to take every frame.
    fn state_fingerprint(state: &Self::State) -> u64;
}

/// A model whose flights write the flight CSV (docs/cli.md, "CSV output"):
/// its position and velocity in its own unit, its own columns, and how a
/// plot reads them back ([`crate::csv`] writes the rows). Every model of the
/// registry is one, so a job run by name ([`with_model`]) can also read or
/// write its CSV (`fdm_plot::csv` reads a CSV's model from its first line,
/// `# model: NAME`).
pub trait CsvModel: RunModel {
    /// The model's own columns, between
    /// [`COMMON_COLUMNS`](crate::csv::COMMON_COLUMNS) and `status`.
    const CSV_COLUMNS: &'static [&'static str];

    /// The column that holds the airspeed (one of [`Self::CSV_COLUMNS`]),
    /// in the model's unit per second: what a plot of the CSV draws as the
    /// airspeed (`sim-cli plot`).
    const CSV_SPEED_COLUMN: &'static str;

    /// Metres per unit of the model's position and velocity columns (1
    /// for metres).
    const METRES_PER_UNIT: f64;

    /// Position `[x, y, z]` in the model's earth frame (x north, y west, z
    /// up) in the model's own unit, widened to `f64` exactly.
    fn native_position(state: &Self::State) -> [f64; 3];

    /// Velocity in the same frame and unit per second.
    fn native_velocity(state: &Self::State) -> [f64; 3];

    /// Appends the values of [`Self::CSV_COLUMNS`], in order.
    fn csv_values(controls: &Self::Controls, state: &Self::State, out: &mut Vec<f64>);
}

/// A model a fleet run ([`crate::fleet`]) can fly: a [`RunModel`] with a
/// structure-of-arrays kernel, a way to place aircraft in formation, and
/// FlightGear's multiplayer model.
pub trait FleetModel: RunModel {
    /// The model's structure-of-arrays fleet (a fleet run's
    /// [`Kernel::Lanes`](crate::fleet::Kernel::Lanes)): `fdm_fleet::Fleet<Self>`
    /// for any model whose step is written over `fdm_core::real`'s number
    /// type (no hand-written kernel).
    type Lanes: fdm_fleet::LaneFleet<Model = Self> + Sync;

    /// The model file FlightGear loads for this model as a multiplayer
    /// aircraft (relative to its data directory), e.g.
    /// `Aircraft/c172p/Models/c172p.xml`.
    const FG_MP_MODEL: &'static str;

    /// `state` moved by `north_m`, `west_m` and `up_m` (the earth frame's x,
    /// y, z, metres), everything else unchanged: the start patterns of a
    /// fleet ([`crate::fleet::show::start_of`]).
    fn offset_state(state: &Self::State, north_m: f64, west_m: f64, up_m: f64) -> Self::State;

    /// DIS (feature `dis`): the [`fdm_dis::Rough`] frames of the
    /// demonstration fleet's aircraft `first..first + states.len()` with
    /// these states (`None`: none), into `out` (as long as `states`, all
    /// `None` on entry), for the fleet publisher's screen
    /// ([`fdm_dis::FleetPublisher::publish_screened`]): the view's time,
    /// position and velocity bit for bit, its attitude's body-to-NED matrix
    /// within [`fdm_dis::ROUGH_TOLERANCE`], made more cheaply than the view.
    /// An aircraft left `None` takes the exact path. The default makes none
    /// (every aircraft exact).
    #[cfg(feature = "dis")]
    fn dis_rough(first: usize, states: &[Option<Self::State>], out: &mut [Option<fdm_dis::Rough>]) {
        let _ = (first, states, out);
    }

    /// DIS (feature `dis`): [`FleetModel::dis_rough`] for up to
    /// [`fdm_dis::ROUGH_LANES`] aircraft (`first..first + states.len()`),
    /// into the lanes of `out` (every `ok` false on entry), as the fleet
    /// publisher's screen reads them
    /// ([`fdm_dis::ScreenedPiece::publish_lanes`]): the same rough frames,
    /// bit for bit. The default makes them with [`FleetModel::dis_rough`]
    /// and puts them in the lanes (the lanes past `states` not `ok`); a
    /// model can make them lane by lane instead, without a
    /// [`fdm_dis::Rough`] per aircraft (Palmer's and Bourg's do).
    #[cfg(feature = "dis")]
    #[inline]
    fn dis_rough_lanes(
        first: usize,
        states: &[Option<Self::State>],
        out: &mut fdm_dis::RoughLanes,
    ) {
        rough_lanes_by_frames::<Self>(first, states, out);
    }
}

/// [`FleetModel::dis_rough_lanes`]'s default: model `M`'s rough frames
/// ([`FleetModel::dis_rough`]) put in the lanes, every lane past `states`
/// not `ok`. A function of its own so that its tests can run it for models
/// that make their lanes themselves, against those.
#[cfg(feature = "dis")]
#[inline]
pub(crate) fn rough_lanes_by_frames<M: FleetModel>(
    first: usize,
    states: &[Option<M::State>],
    out: &mut fdm_dis::RoughLanes,
) {
    let n = states.len().min(fdm_dis::ROUGH_LANES);
    let mut roughs = [None; fdm_dis::ROUGH_LANES];
    M::dis_rough(first, &states[..n], &mut roughs[..n]);
    for (k, r) in roughs.iter().enumerate() {
        out.set(k, r.as_ref());
    }
}

/// A model's controls and physical parameters by name, as a study file
/// gives them (`[controls]`, `[aircraft]`, dispersions `controls.NAME` and
/// `aircraft.NAME`: docs/studies.md), and cheap reads of a state.
pub trait NamedInputs: RunModel {
    /// The control settings that can be given by name, with their units in
    /// the names.
    const CONTROL_KEYS: &'static [&'static str];
    /// The physical parameters that can be given by name.
    const AIRCRAFT_KEYS: &'static [&'static str];

    /// Sets control `key` (one of [`Self::CONTROL_KEYS`]) to `value`.
    ///
    /// # Errors
    /// An unknown key, or a value out of the control's range or not one of
    /// its settings (a notch, on/off), in words.
    fn set_control(controls: &mut Self::Controls, key: &str, value: f64) -> Result<(), String>;

    /// The model's default aircraft with the parameters `values` (keys of
    /// [`Self::AIRCRAFT_KEYS`]) set, in order, then checked.
    ///
    /// # Errors
    /// An unknown key, or parameters the model cannot fly, in words.
    fn aircraft_with(values: &[(&str, f64)]) -> Result<Self::Aircraft, String>;

    /// Velocity in the earth frame, m/s: the view's `velocity_mps`, bit for bit.
    fn velocity_mps(state: &Self::State) -> [f64; 3];

    /// The state's clock, s.
    fn time_s(state: &Self::State) -> f64;
}

/// The message for a name that is not one of `keys` (`kind`: "control",
/// "aircraft parameter").
pub(crate) fn unknown_key(kind: &str, key: &str, keys: &[&str]) -> String {
    format!(
        "unknown {kind} `{key}`; expected one of {}",
        keys.join(", ")
    )
}

/// `value` if it is finite and in `low..=high`, else the message naming
/// `key` and the range.
pub(crate) fn in_range(key: &str, value: f64, low: f64, high: f64) -> Result<f64, String> {
    if value.is_finite() && (low..=high).contains(&value) {
        Ok(value)
    } else {
        Err(format!(
            "{key} = {}: expected a number from {low} to {high}",
            ShortNumber(value)
        ))
    }
}

/// The message for `value` of `key` when only the values `allowed` (in
/// words: "0, 20 or 40") are settings (a notch, an on/off switch): no range
/// fits, so a value between two of them, or NaN, is refused naming them.
pub(crate) fn not_one_of(key: &str, value: f64, allowed: &str) -> String {
    format!("{key} = {}: expected {allowed}", ShortNumber(value))
}

/// What the registry's jobs ([`ModelJob`]) may use of a model: it records
/// and writes the flight CSV ([`RunModel`], [`CsvModel`]), flies in fleets
/// ([`FleetModel`], [`FleetKernel`]), is set up by name ([`NamedInputs`]),
/// is shown as columns of numbers and driven by an agent ([`ColumnModel`],
/// [`AgentModel`]) and is flown by hand from a front end, with its report
/// ([`PilotModel`](pilot::PilotModel), a
/// [`ReportModel`](crate::report::ReportModel)). Implemented for every model
/// that implements those.
pub trait RegisteredModel:
    CsvModel
    + FleetModel
    + NamedInputs
    + FleetKernel
    + ColumnModel
    + AgentModel
    + agent::LaneAgent
    + pilot::PilotModel
{
}

impl<
        M: CsvModel
            + FleetModel
            + NamedInputs
            + FleetKernel
            + ColumnModel
            + AgentModel
            + agent::LaneAgent
            + pilot::PilotModel,
    > RegisteredModel for M
{
}

/// Something to do with a model type chosen at run time by name
/// ([`with_model`]).
pub trait ModelJob {
    /// What it returns.
    type Output;
    /// Does it for model `M`, with all a model of the registry implements
    /// ([`RegisteredModel`]).
    fn call<M: RegisteredModel>(self) -> Self::Output;
}

/// The models of the registry, by [`Model::NAME`], in the order help texts
/// list them.
pub const MODELS: &[&str] = &[Palmer::NAME, Bourg::NAME];

/// Runs `job` with the model named `name` ([`Model::NAME`]), or `None`
/// when the registry has no such model. The one place above `fdm-core` that
/// maps a model's name to its type.
pub fn with_model<J: ModelJob>(name: &str, job: J) -> Option<J::Output> {
    match name {
        n if n == Palmer::NAME => Some(job.call::<Palmer>()),
        n if n == Bourg::NAME => Some(job.call::<Bourg>()),
        _ => None,
    }
}

/// What the adapters' tests share (`bourg.rs`, `palmer.rs`).
#[cfg(test)]
pub(crate) mod test_support {
    /// `M`'s cheap reads of a state in flight (fleet member 1 ten steps at
    /// 30 frames a second on, its time past 0) are the view's time and
    /// velocity, bit for bit.
    pub(crate) fn cheap_reads_are_the_views<M: super::NamedInputs>() {
        let aircraft = M::default_aircraft();
        let (controls, mut state) = M::fleet_member(1);
        for _ in 0..10 {
            state = M::step(&aircraft, &controls, &state, M::time_step(30.0));
        }
        let view = M::view(&aircraft, &controls, &state);
        assert!(view.time_s > 0.3, "{}", view.time_s);
        assert_eq!(M::time_s(&state).to_bits(), view.time_s.to_bits());
        assert_eq!(
            M::velocity_mps(&state).map(f64::to_bits),
            <[f64; 3]>::from(view.velocity_mps).map(f64::to_bits)
        );
    }

    /// `M::CONTROL_KEYS` is the keys of `values`, in order, and each key
    /// set alone on the model's initial controls changes exactly its own
    /// field (by its serialized name, `field(key)`); returns the initial
    /// controls with every value set, in order, for the caller to compare.
    pub(crate) fn each_control_key_sets_its_own_field<M: super::NamedInputs>(
        values: &[(&str, f64)],
        field: impl Fn(&str) -> &str,
    ) -> M::Controls
    where
        M::Controls: serde::Serialize,
    {
        let keys: Vec<&str> = values.iter().map(|(key, _)| *key).collect();
        assert_eq!(M::CONTROL_KEYS, keys.as_slice());
        let fields = |c: &M::Controls| match serde_json::to_value(c).unwrap() {
            serde_json::Value::Object(map) => map,
            other => panic!("{other}"),
        };
        let start = M::initial_controls();
        let mut all = start;
        for &(key, value) in values {
            let mut c = start;
            M::set_control(&mut c, key, value).unwrap_or_else(|e| panic!("{key}: {e}"));
            M::set_control(&mut all, key, value).unwrap();
            let (before, after) = (fields(&start), fields(&c));
            let changed: Vec<&str> = after
                .iter()
                .filter(|(k, v)| before.get(k.as_str()) != Some(*v))
                .map(|(k, _)| k.as_str())
                .collect();
            assert_eq!(changed, [field(key)], "{key}");
        }
        all
    }

    /// `M::state_fingerprint` is `want` (the state half of fdm-core's
    /// fingerprint of `M`) of fleet member 2's state, of that state a step
    /// (at 30 frames a second) on, and of each of `more`; and the first two
    /// differ.
    pub(crate) fn recorded_fingerprint_is_the_states<M: super::RunModel>(
        want: impl Fn(&M::State) -> u64,
        more: &[M::State],
    ) {
        let aircraft = M::default_aircraft();
        let (controls, state) = M::fleet_member(2);
        let next = M::step(&aircraft, &controls, &state, M::time_step(30.0));
        for s in [state, next].iter().chain(more) {
            assert_eq!(M::state_fingerprint(s), want(s));
        }
        assert_ne!(M::state_fingerprint(&state), M::state_fingerprint(&next));
    }

    /// A fixed sequence of numbers in [-1, 1) (xorshift64, the same seed in
    /// every call), for the adapters' tests' random but reproducible states.
    #[cfg(feature = "dis")]
    pub(crate) fn uniform_in_plus_minus_one() -> impl FnMut() -> f64 {
        let mut x: u64 = 0x2545_f491_4f6c_dd1d;
        move || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        }
    }

    /// Bits of a rough DIS frame's every number, to compare rough frames
    /// bit for bit.
    #[cfg(feature = "dis")]
    pub(crate) fn rough_bits(r: &fdm_dis::Rough) -> Vec<u64> {
        let mut b = vec![r.time_s.to_bits()];
        b.extend(r.position_m.iter().map(|x| x.to_bits()));
        b.extend(r.velocity_mps.iter().map(|x| x.to_bits()));
        b.extend(r.body_to_ned.iter().map(|x| x.to_bits()));
        b
    }

    /// `M::dis_rough_lanes` over `states` in groups of
    /// [`fdm_dis::ROUGH_LANES`] (every lane `ok` before each call, as an
    /// earlier group may leave it) against `want`, the one-at-a-time rough
    /// frames: each aircraft's lane is its frame bit for bit or none where
    /// it has none, and the lanes past a short last group are not `ok`.
    /// The trait's default ([`super::rough_lanes_by_frames`], which a
    /// model without lanes of its own gets) is checked the same way.
    /// Returns how many aircraft had a frame and how many had none.
    #[cfg(feature = "dis")]
    pub(crate) fn lanes_against_frames<M: super::FleetModel>(
        states: &[Option<M::State>],
        want: &[Option<fdm_dis::Rough>],
    ) -> (usize, usize) {
        let counts = lanes_against_frames_by::<M>(M::dis_rough_lanes, states, want);
        let by_frames = super::rough_lanes_by_frames::<M>;
        assert_eq!(
            lanes_against_frames_by::<M>(by_frames, states, want),
            counts
        );
        counts
    }

    /// [`lanes_against_frames`] for `lanes_of`, which makes the lanes as
    /// `M::dis_rough_lanes` does.
    #[cfg(feature = "dis")]
    fn lanes_against_frames_by<M: super::FleetModel>(
        lanes_of: fn(usize, &[Option<M::State>], &mut fdm_dis::RoughLanes),
        states: &[Option<M::State>],
        want: &[Option<fdm_dis::Rough>],
    ) -> (usize, usize) {
        const L: usize = fdm_dis::ROUGH_LANES;
        let (mut made, mut none) = (0, 0);
        for (g, group) in states.chunks(L).enumerate() {
            let at = g * L;
            let mut lanes = fdm_dis::RoughLanes {
                ok: [true; L],
                ..Default::default()
            };
            lanes_of(at, group, &mut lanes);
            for k in 0..group.len() {
                match (lanes.get(k), want[at + k]) {
                    (Some(got), Some(w)) => {
                        assert_eq!(rough_bits(&got), rough_bits(&w), "aircraft {}", at + k);
                        made += 1;
                    }
                    (None, None) => none += 1,
                    (got, w) => panic!("aircraft {}: {got:?} against {w:?}", at + k),
                }
            }
            for k in group.len()..L {
                assert!(lanes.get(k).is_none(), "lane {k} of {}", group.len());
            }
        }
        (made, none)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fdm_core::bourg::BourgAircraft;

    /// The cheap reads are the view's fields, bit for bit (exact equality:
    /// they must be the same expressions).
    #[test]
    fn reads_match_the_view() {
        fn check<M: RegisteredModel>() {
            let (controls, state) = M::fleet_member(5);
            let aircraft = M::default_aircraft();
            let view = M::view(&aircraft, &controls, &state);
            assert_eq!(
                <M as fdm_fleet::LaneModel>::position_m(&state),
                view.position_m
            );
            assert_eq!(M::velocity_mps(&state), <[f64; 3]>::from(view.velocity_mps));
            assert_eq!(M::time_s(&state), view.time_s);
        }
        check::<Palmer>();
        check::<Bourg>();
    }

    /// `with_model` calls the job with the model of that name, every name
    /// of [`MODELS`], and nothing for another name.
    #[test]
    fn with_model_picks_the_model_named() {
        struct Name;
        impl ModelJob for Name {
            type Output = &'static str;
            fn call<M: RegisteredModel>(self) -> &'static str {
                M::NAME
            }
        }
        assert_eq!(MODELS, ["palmer", "bourg"]);
        for &name in MODELS {
            assert_eq!(with_model(name, Name), Some(name));
        }
        for other in ["", "glider", "Palmer", "palmer "] {
            assert_eq!(with_model(other, Name), None, "{other:?}");
        }
    }

    #[test]
    fn parameters_are_set_and_checked() {
        let a = Palmer::aircraft_with(&[("mass_kg", 1000.0)]).unwrap();
        assert_eq!(a.mass_kg, 1000.0);
        assert!(Palmer::aircraft_with(&[("mass_kg", -1.0)]).is_err());
        assert!(Palmer::aircraft_with(&[("mass", 1.0)])
            .unwrap_err()
            .contains("mass_kg"));
        let b = Bourg::aircraft_with(&[("mass_scale", 1.1)]).unwrap();
        assert!(
            b.mass_properties().mass_slug
                > BourgAircraft::bourg_default().mass_properties().mass_slug
        );
        let mut c = Palmer::initial_controls();
        assert!(Palmer::set_control(&mut c, "throttle", 2.0).is_err());
        Palmer::set_control(&mut c, "throttle", 0.5).unwrap();
        assert_eq!(c.throttle, 0.5);
    }
}
