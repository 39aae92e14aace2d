//! A model-neutral description of what FlightGear should draw, and its
//! conversion into a datagram.

use crate::fdm::{FgNetFdm, AGL_UNKNOWN};

/// Engine state as FlightGear's native-FDM protocol encodes it in `eng_state`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[repr(u32)]
pub enum EngineState {
    /// 0: FlightGear sets `/engines/engine[i]/cranking = false`, `/running = false`.
    #[default]
    Off = 0,
    /// 1: `cranking = true`, `running = false`.
    Cranking = 1,
    /// 2: `cranking = false`, `running = true`.
    Running = 2,
}

impl From<EngineState> for u32 {
    fn from(state: EngineState) -> Self {
        state as u32
    }
}

/// What a flight model hands over for display, in the units flight models
/// usually work in (every field name carries its unit).
///
/// It describes one aircraft with one engine, which is what both models in
/// this workspace are (Palmer's Cessna 172 and Bourg's aircraft).
/// [`FgNetFdm::from_display`] (or `From`) converts it to the wire units:
/// angles in radians, altitude in metres, speeds in ft/s and knots. The
/// "FlightGear shows" notes say which property FlightGear 2020.3 sets.
///
/// # Example
///
/// ```
/// use fgnet::{DisplayState, EngineState, FgNetFdm};
///
/// let state = DisplayState {
///     latitude_deg: 37.625,
///     longitude_deg: -122.375,
///     altitude_m: 100.0,
///     heading_deg: 90.0,
///     airspeed_kt: 90.0,
///     engine_state: EngineState::Running,
///     engine_rpm: 2400.0,
///     flaps_norm: 0.5,
///     ..DisplayState::default()
/// };
/// let fdm = FgNetFdm::from_display(&state);
/// assert_eq!(fdm.latitude, 37.625f64.to_radians());
/// assert_eq!(fdm.psi, std::f32::consts::FRAC_PI_2);
/// assert_eq!(fdm.vcas, 90.0);
/// assert_eq!((fdm.num_engines, fdm.eng_state[0], fdm.rpm[0]), (1, 2, 2400.0));
/// assert_eq!((fdm.left_flap, fdm.right_flap), (0.5, 0.5));
/// assert_eq!(fdm.agl, fgnet::AGL_UNKNOWN);
/// // Ready for the wire (or a `fgnet::Sender`).
/// assert_eq!(fdm.encode().len(), 408);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct DisplayState {
    /// Geodetic latitude, degrees, north positive. Sent as radians (f64).
    /// FlightGear shows `/position/latitude-deg` (5.49e-8 relatively smaller,
    /// from its float conversion constant).
    pub latitude_deg: f64,
    /// Geodetic longitude, degrees, east positive. Sent as radians (f64).
    /// FlightGear shows `/position/longitude-deg`.
    pub longitude_deg: f64,
    /// Altitude above sea level, metres. Sent as metres (f64).
    /// FlightGear shows `/position/altitude-ft` (× 3.28083989501312335958);
    /// the height above ground is left to FlightGear's terrain
    /// (`agl` = [`AGL_UNKNOWN`]).
    pub altitude_m: f64,
    /// Roll (bank) angle, degrees, right wing down positive. Sent as `phi`,
    /// radians (f32). FlightGear shows `/orientation/roll-deg`.
    pub roll_deg: f64,
    /// Pitch angle, degrees, nose up positive. Sent as `theta`, radians
    /// (f32). FlightGear shows `/orientation/pitch-deg`.
    pub pitch_deg: f64,
    /// True heading, degrees clockwise from north. Sent as `psi`, radians
    /// (f32). FlightGear shows `/orientation/heading-deg`.
    pub heading_deg: f64,
    /// Angle of attack, degrees. Sent as `alpha`, radians (f32).
    /// FlightGear shows `/orientation/alpha-deg`.
    pub alpha_deg: f64,
    /// Sideslip angle, degrees. Sent as `beta`, radians (f32).
    /// FlightGear shows `/orientation/side-slip-rad` (radians).
    pub beta_deg: f64,
    /// North velocity, ft/s. FlightGear shows `/velocities/speed-north-fps`.
    pub v_north_fps: f64,
    /// East velocity, ft/s. FlightGear shows `/velocities/speed-east-fps`.
    pub v_east_fps: f64,
    /// Down velocity, ft/s. FlightGear shows `/velocities/speed-down-fps`.
    pub v_down_fps: f64,
    /// Body-frame forward velocity u, ft/s. FlightGear shows `/velocities/uBody-fps`.
    pub u_body_fps: f64,
    /// Body-frame right velocity v, ft/s. FlightGear shows `/velocities/vBody-fps`.
    pub v_body_fps: f64,
    /// Body-frame down velocity w, ft/s. FlightGear shows `/velocities/wBody-fps`.
    pub w_body_fps: f64,
    /// Calibrated airspeed, knots. Sent as `vcas`.
    /// FlightGear shows `/velocities/airspeed-kt` (the airspeed indicator).
    pub airspeed_kt: f64,
    /// Vertical speed, ft/s, up positive. Sent as `climb_rate`.
    /// FlightGear shows `/velocities/vertical-speed-fps`.
    pub climb_rate_fps: f64,
    /// Elevator, normalised -1..1 (passed through unclamped).
    /// FlightGear shows `/surface-positions/elevator-pos-norm`.
    pub elevator_norm: f64,
    /// Left aileron, normalised -1..1.
    /// FlightGear shows `/surface-positions/left-aileron-pos-norm`.
    pub left_aileron_norm: f64,
    /// Right aileron, normalised -1..1.
    /// FlightGear shows `/surface-positions/right-aileron-pos-norm`.
    pub right_aileron_norm: f64,
    /// Rudder, normalised -1..1.
    /// FlightGear shows `/surface-positions/rudder-pos-norm`.
    pub rudder_norm: f64,
    /// Flaps, normalised (0 retracted .. 1 fully extended). Sent as both
    /// `left_flap` and `right_flap`, because FlightGear writes both to the one
    /// property `/surface-positions/flap-pos-norm` and `right_flap` wins.
    pub flaps_norm: f64,
    /// State of the single engine (`eng_state[0]`; `num_engines` = 1).
    /// FlightGear shows `/engines/engine[0]/cranking` and `/running`.
    pub engine_state: EngineState,
    /// Engine speed, rev/min (`rpm[0]`).
    /// FlightGear shows `/engines/engine[0]/rpm`.
    pub engine_rpm: f64,
}

impl FgNetFdm {
    /// Builds a datagram from a [`DisplayState`].
    ///
    /// Starts from [`FgNetFdm::new`] (version 24, `agl` = [`AGL_UNKNOWN`],
    /// everything else neutral) and sets:
    ///
    /// * `latitude`/`longitude` = degrees converted with `f64::to_radians`,
    ///   `altitude` = metres, unchanged;
    /// * `phi`, `theta`, `psi`, `alpha`, `beta` = degrees converted with
    ///   `f64::to_radians`, then rounded to `f32`;
    /// * `v_north`, `v_east`, `v_down`, `v_body_u/v/w`, `climb_rate` (ft/s)
    ///   and `vcas` (knots) rounded to `f32`;
    /// * `elevator`, `left_aileron`, `right_aileron`, `rudder`, and both
    ///   `left_flap` and `right_flap` from `flaps_norm`;
    /// * `num_engines` = 1 with `eng_state[0]` and `rpm[0]`, so FlightGear's
    ///   engine 0 shows the model's engine; `num_tanks` and `num_wheels`
    ///   stay 0 so FlightGear's own fuel and gear properties are untouched.
    ///
    /// Angular rates, accelerations and the other fields stay 0.
    #[must_use]
    pub fn from_display(state: &DisplayState) -> Self {
        let rad = |deg: f64| deg.to_radians() as f32;
        let mut fdm = Self::new();
        fdm.latitude = state.latitude_deg.to_radians();
        fdm.longitude = state.longitude_deg.to_radians();
        fdm.altitude = state.altitude_m;
        fdm.agl = AGL_UNKNOWN;
        fdm.phi = rad(state.roll_deg);
        fdm.theta = rad(state.pitch_deg);
        fdm.psi = rad(state.heading_deg);
        fdm.alpha = rad(state.alpha_deg);
        fdm.beta = rad(state.beta_deg);
        fdm.vcas = state.airspeed_kt as f32;
        fdm.climb_rate = state.climb_rate_fps as f32;
        fdm.v_north = state.v_north_fps as f32;
        fdm.v_east = state.v_east_fps as f32;
        fdm.v_down = state.v_down_fps as f32;
        fdm.v_body_u = state.u_body_fps as f32;
        fdm.v_body_v = state.v_body_fps as f32;
        fdm.v_body_w = state.w_body_fps as f32;
        fdm.num_engines = 1;
        fdm.eng_state[0] = state.engine_state.into();
        fdm.rpm[0] = state.engine_rpm as f32;
        fdm.elevator = state.elevator_norm as f32;
        fdm.left_aileron = state.left_aileron_norm as f32;
        fdm.right_aileron = state.right_aileron_norm as f32;
        fdm.rudder = state.rudder_norm as f32;
        fdm.left_flap = state.flaps_norm as f32;
        fdm.right_flap = state.flaps_norm as f32;
        fdm
    }
}

impl From<&DisplayState> for FgNetFdm {
    /// Same as [`FgNetFdm::from_display`].
    fn from(state: &DisplayState) -> Self {
        Self::from_display(state)
    }
}

impl From<DisplayState> for FgNetFdm {
    /// Same as [`FgNetFdm::from_display`].
    fn from(state: DisplayState) -> Self {
        Self::from_display(&state)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_display_field_lands_in_its_wire_field() {
        let s = DisplayState {
            latitude_deg: 37.625,
            longitude_deg: -122.375,
            altitude_m: 100.0,
            roll_deg: 30.0,
            pitch_deg: -5.0,
            heading_deg: 270.0,
            alpha_deg: 4.0,
            beta_deg: -2.0,
            v_north_fps: 150.0,
            v_east_fps: -20.0,
            v_down_fps: -8.0,
            u_body_fps: 151.0,
            v_body_fps: 1.0,
            w_body_fps: 2.0,
            airspeed_kt: 90.0,
            climb_rate_fps: 8.0,
            elevator_norm: -0.125,
            left_aileron_norm: 0.25,
            right_aileron_norm: -0.25,
            rudder_norm: 0.0625,
            flaps_norm: 0.5,
            engine_state: EngineState::Cranking,
            engine_rpm: 600.0,
        };
        let f = FgNetFdm::from(s);
        // The golden datagram's lat/lon are exactly these conversions.
        assert_eq!(f.latitude, 0.6566801310628665);
        assert_eq!(f.longitude, -2.1358466721280607);
        assert_eq!(f.altitude, 100.0);
        assert_eq!(f.agl, AGL_UNKNOWN);
        assert_eq!(f.phi, 30f64.to_radians() as f32);
        assert_eq!(f.theta, (-5f64).to_radians() as f32);
        assert_eq!(f.psi, 270f64.to_radians() as f32);
        assert_eq!(f.alpha, 4f64.to_radians() as f32);
        assert_eq!(f.beta, (-2f64).to_radians() as f32);
        assert_eq!(
            [f.v_north, f.v_east, f.v_down, f.v_body_u, f.v_body_v, f.v_body_w],
            [150.0, -20.0, -8.0, 151.0, 1.0, 2.0]
        );
        assert_eq!((f.vcas, f.climb_rate), (90.0, 8.0));
        assert_eq!(
            [f.elevator, f.left_aileron, f.right_aileron, f.rudder],
            [-0.125, 0.25, -0.25, 0.0625]
        );
        assert_eq!((f.left_flap, f.right_flap), (0.5, 0.5));
        assert_eq!(f.num_engines, 1);
        assert_eq!(f.eng_state, [1, 0, 0, 0]);
        assert_eq!(f.rpm, [600.0, 0.0, 0.0, 0.0]);
        assert_eq!((f.num_tanks, f.num_wheels), (0, 0));
        assert_eq!(f.version, 24);
        // Nothing else is touched: same as new() once those fields are reset.
        let mut rest = f;
        rest.latitude = 0.0;
        rest.longitude = 0.0;
        rest.altitude = 0.0;
        (rest.phi, rest.theta, rest.psi, rest.alpha, rest.beta) = (0.0, 0.0, 0.0, 0.0, 0.0);
        (rest.v_north, rest.v_east, rest.v_down) = (0.0, 0.0, 0.0);
        (rest.v_body_u, rest.v_body_v, rest.v_body_w) = (0.0, 0.0, 0.0);
        (rest.vcas, rest.climb_rate) = (0.0, 0.0);
        (
            rest.elevator,
            rest.left_aileron,
            rest.right_aileron,
            rest.rudder,
        ) = (0.0, 0.0, 0.0, 0.0);
        (rest.left_flap, rest.right_flap) = (0.0, 0.0);
        rest.num_engines = 0;
        rest.eng_state[0] = 0;
        rest.rpm[0] = 0.0;
        assert_eq!(rest, FgNetFdm::new());
    }

    #[test]
    fn engine_state_wire_values() {
        assert_eq!(u32::from(EngineState::Off), 0);
        assert_eq!(u32::from(EngineState::Cranking), 1);
        assert_eq!(u32::from(EngineState::Running), 2);
        assert_eq!(EngineState::default(), EngineState::Off);
    }
}
